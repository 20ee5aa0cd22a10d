// The command line's contract (issue 13, items 2, 3, 10): every mistake is one line on
// stderr and exit status 2, nothing half-written and no folder left behind; an unknown
// command names the commands and the closest; --duration is checked; a run that cannot
// fit in memory is refused before it starts; an output that cannot be written is a
// user error, not an internal one.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"

namespace {

namespace fs = std::filesystem;
using dmbd::cli_testing::run_dmbd;

const std::string kScenario = std::string(DMBD_SOURCE_DIR) + "/examples/scenarios/standing.yaml";

class CliContract : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dmbd_cli_contract_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // Exit 2 and exactly one line on stderr containing `needle`.
  void expect_one_line_error(const std::vector<std::string>& args, const std::string& needle) {
    const auto r = run_dmbd(args, dir_);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
  }
  fs::path dir_;
};

TEST_F(CliContract, UnknownCommandNamesTheClosest) {
  expect_one_line_error({"analize", "--tf", "1/(s+1)"}, "unknown command 'analize'");
  const auto r = run_dmbd({"analize"}, dir_);
  EXPECT_NE(r.err.find("did you mean 'analyze'?"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("simulate"), std::string::npos) << r.err;
}

TEST_F(CliContract, DurationIsCheckedAndNoFolderIsLeftBehind) {
  const std::string out = (dir_ / "out").string();
  for (const char* d : {"nan", "0", "-1", "inf", "2x"})
    expect_one_line_error({"simulate", kScenario, "--out", out, "--duration", d, "--no-frames"}, "--duration '" + std::string(d) + "'");
  expect_one_line_error({"simulate", kScenario, "--out", out, "--duration", "1e9", "--no-frames"}, "out of range");
  // 1e6 s at the scenario's 200 Hz: 36 billion values, refused before it starts.
  expect_one_line_error({"simulate", kScenario, "--out", out, "--duration", "1e6", "--no-frames"}, "limit is 2 GB");
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(CliContract, AnOutputThatCannotBeWrittenIsAUserError) {
  // A directory where the report's page should go.
  const fs::path out = dir_ / "run";
  fs::create_directories(out / "report.html");
  expect_one_line_error({"simulate", kScenario, "--out", out.string(), "--duration", "0.01", "--no-frames"}, "cannot write");
  EXPECT_FALSE(fs::exists(out / "report.html.tmp"));
}

TEST_F(CliContract, ReportOfAFolderThatIsNotARun) {
  expect_one_line_error({"report", dir_.string()}, "metrics.json");
  expect_one_line_error({"report", (dir_ / "nope").string()}, "cannot read");
}

TEST_F(CliContract, EveryOutputIsCheckedBeforeAnyIsWritten) {
  // analyze: the step plot cannot be written (a directory is in the way), so the Bode
  // plot, which comes first, must not be written either.
  fs::create_directories(dir_ / "s.png");
  expect_one_line_error({"analyze", "--tf", "1/(s+1)", "--bode", (dir_ / "b.png").string(), "--step-plot",
                         (dir_ / "s.png").string()},
                        "--step-plot");
  EXPECT_FALSE(fs::exists(dir_ / "b.png"));
  // codegen: the report cannot be written, so no header either.
  fs::create_directories(dir_ / "tf.report.md");
  expect_one_line_error({"codegen", "--tf", "1/(s+1)", "--rate", "1000", "--out", dir_.string()}, "tf.report.md");
  EXPECT_FALSE(fs::exists(dir_ / "tf.hpp"));
  EXPECT_FALSE(fs::exists(dir_ / "tf.report.json"));
}

// Issue 13, item 7: a filter above the Nyquist frequency of the generated loop.
TEST_F(CliContract, CodegenWarnsOfAPoleAboveTheNyquistFrequency) {
  const std::vector<std::string> args{"codegen", "--tf", "1/(s/(2*pi*8000)+1)", "--out", dir_.string(), "--rate"};
  auto at = [&](const char* rate) {
    auto a = args;
    a.push_back(rate);
    return run_dmbd(a, dir_);
  };
  const auto fast = at("20000"), slow = at("10000");
  ASSERT_EQ(fast.code, 0) << fast.err;
  ASSERT_EQ(slow.code, 0) << slow.err;
  EXPECT_EQ(fast.out.find("Nyquist"), std::string::npos) << fast.out;  // 8 kHz below 10 kHz: fine
  EXPECT_NE(slow.out.find("warning: block 'G' has a pole or zero at 8000 Hz, above the Nyquist frequency 5000 Hz"),
            std::string::npos)
      << slow.out;
  EXPECT_NE(dmbd::cli_testing::slurp(dir_ / "tf.report.md").find("above the Nyquist frequency"), std::string::npos);
}

// Issue 13, item 7: a 16-bit build whose predicted error bound exceeds the output's
// range (the DOB controller at its 2 kHz: 5.4e4 A against +-22 A; 32 bits are within).
TEST_F(CliContract, CodegenWarnsWhenTheFixedPointBoundExceedsTheOutputRange) {
  const std::string diagram = std::string(DMBD_SOURCE_DIR) + "/examples/diagrams/dob_controller.yaml";
  auto build = [&](const char* word) {
    return run_dmbd({"codegen", diagram, "--rate", "2000", "--scalar", "fixed", "--word", word, "--out", dir_.string()}, dir_);
  };
  const auto w16 = build("16");
  ASSERT_EQ(w16.code, 0) << w16.err;
  EXPECT_NE(w16.out.find("warning: output 'out_i': the predicted 16-bit fixed-point error bound"), std::string::npos) << w16.out;
  EXPECT_NE(w16.out.find("exceeds the output's range (+-22 A)"), std::string::npos) << w16.out;
  const auto w32 = build("32");
  ASSERT_EQ(w32.code, 0) << w32.err;
  EXPECT_EQ(w32.out.find("exceeds the output's range"), std::string::npos) << w32.out;
}

// Issue 28, row 12: --state-bits chooses the words of a fixed-point program's state
// update (auto, 16 or 32); anything else is one line and exit 2, before anything is written.
TEST_F(CliContract, CodegenStateBitsAreCheckedAndReported) {
  const std::string diagram = std::string(DMBD_SOURCE_DIR) + "/tests/codegen/data/pi_position_loop.yaml";
  auto codegen = [&](const char* word, const char* state) {
    return std::vector<std::string>{"codegen", diagram, "--rate", "2000", "--scalar", "fixed", "--word", word,
                                    "--state-bits", state, "--out", dir_.string()};
  };
  expect_one_line_error(codegen("16", "24"), "--state-bits '24': expected auto, 16 or 32");
  expect_one_line_error(codegen("32", "16"), "--state-bits 16: narrower than the 32-bit word");
  EXPECT_FALSE(fs::exists(dir_ / "pi_position_loop.hpp"));
  // 16 bits, every word 16: the bound exceeds the +-100 N m output range, and says so.
  const auto narrow = run_dmbd(codegen("16", "16"), dir_);
  ASSERT_EQ(narrow.code, 0) << narrow.err;
  EXPECT_NE(narrow.out.find("exceeds the output's range (+-100 N m)"), std::string::npos) << narrow.out;
  // auto: the state in a 32-bit word, listed in the report; no warning.
  const auto wide = run_dmbd(codegen("16", "auto"), dir_);
  ASSERT_EQ(wide.code, 0) << wide.err;
  EXPECT_EQ(wide.out.find("exceeds the output's range"), std::string::npos) << wide.out;
  const auto report = nlohmann::json::parse(dmbd::cli_testing::slurp(dir_ / "pi_position_loop.report.json"));
  EXPECT_EQ(report["word_bits"]["word"], 16);
  EXPECT_EQ(report["word_bits"]["state"], 32);
  const auto& widened = report["word_bits"]["widened"];
  EXPECT_NE(std::find(widened.begin(), widened.end(), "PI_s1"), widened.end()) << widened.dump();
}

}  // namespace
