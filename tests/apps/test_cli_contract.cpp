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

}  // namespace
