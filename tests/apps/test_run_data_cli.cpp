// Issue 28 rows 5-8: damaged run data is refused, never crashes. `dmbd report` on a run
// directory whose log.csv holds only its header, a variant without values, a column twice,
// a row short of cells or out of time order; `dmbd sweep collect` on a part with no rows,
// a row count whose size wraps, a column twice or a log.bin of another size: each one
// located line on stderr, exit 2, and collect writes nothing. Inputs that never end
// (/dev/zero, /dev/urandom) are read boundedly: "not text" at once.
#include <gtest/gtest.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "cli_support.hpp"

namespace {

namespace fs = std::filesystem;
using dmbd::cli_testing::run_dmbd;
using dmbd::cli_testing::slurp;

const std::string kScenario = std::string(DMBD_SOURCE_DIR) + "/examples/scenarios/position_controllers.yaml";

void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

// One run directory (three variants, 0.2 s) and one sweep plan with its three parts,
// made once for the suite; each test damages a copy.
class RunData : public ::testing::Test {
 protected:
  static fs::path root() { return fs::temp_directory_path() / ("dmbd_run_data_" + std::to_string(::getpid())); }
  static void SetUpTestSuite() {
    fs::remove_all(root());
    fs::create_directories(root());
    const auto s = run_dmbd({"simulate", kScenario, "--out", (root() / "run").string(), "--no-frames", "--duration", "0.2"}, root());
    ASSERT_EQ(s.code, 0) << s.err;
    const auto p = run_dmbd({"sweep", "plan", kScenario, "--out", (root() / "plan").string()}, root());
    ASSERT_EQ(p.code, 0) << p.err;
    const std::vector<std::string> variants{"encoder", "potentiometer", "encoder_force"};
    for (std::size_t k = 0; k < variants.size(); ++k) {
      const auto v = run_dmbd({"simulate", "scenario/scenarios/position_controllers.yaml", "--variant", variants[k], "--out",
                               "parts/" + std::to_string(k + 1), "--duration", "0.2"},
                              root(), root() / "plan");
      ASSERT_EQ(v.code, 0) << v.err;
    }
  }
  static void TearDownTestSuite() { fs::remove_all(root()); }
  void SetUp() override { fs::remove_all(root() / "t"); }
  void TearDown() override { fs::remove_all(root() / "t"); }

  // A copy of the run directory with log.csv changed line by line.
  fs::path damaged_run(const std::function<void(std::vector<std::string>&)>& damage) const {
    const fs::path d = root() / "t";
    fs::copy(root() / "run", d, fs::copy_options::recursive);
    std::vector<std::string> lines = lines_of(slurp(d / "log.csv"));
    damage(lines);
    std::string text;
    for (const auto& l : lines) text += l + "\n";
    write(d / "log.csv", text);
    return d;
  }
  // A copy of the plan with part 2's part.json changed.
  fs::path damaged_plan(const std::function<void(nlohmann::json&)>& damage) const {
    const fs::path d = root() / "t";
    fs::copy(root() / "plan", d, fs::copy_options::recursive);
    nlohmann::json part = nlohmann::json::parse(slurp(d / "parts/2/part.json"));
    damage(part);
    write(d / "parts/2/part.json", part.dump());
    return d;
  }
  // `dmbd report DIR --no-frames`: exit 2 and exactly `line` on stderr.
  void expect_report_error(const fs::path& d, const std::string& line) const {
    const auto r = run_dmbd({"report", d.string(), "--no-frames"}, root());
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(r.err, "dmbd: error: " + line + "\n");
  }
  // `dmbd sweep collect DIR`: exit 2, `line` on stderr, no run folder written.
  void expect_collect_error(const fs::path& d, const std::string& line) const {
    const auto r = run_dmbd({"sweep", "collect", d.string(), "--no-frames"}, root());
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(r.err, "dmbd: error: " + line + "\n");
    EXPECT_FALSE(fs::exists(d / "run")) << "collect wrote " << d / "run";
  }
};

// Row 5.
TEST_F(RunData, ReportOfALogWithOnlyItsHeaderIsOneLine) {
  const fs::path d = damaged_run([](std::vector<std::string>& l) { l.resize(1); });
  expect_report_error(d, (d / "log.csv").string() + ":1: no rows after the header (expected at least one row of values)");
}

TEST_F(RunData, ReportOfAVariantWhoseColumnsAreAllEmptyIsOneLine) {
  const fs::path d = damaged_run([](std::vector<std::string>& l) {
    const std::vector<std::string> header = dmbd::cli_testing::split(l[0]);
    for (std::size_t r = 1; r < l.size(); ++r) {
      std::vector<std::string> cells = dmbd::cli_testing::split(l[r]);
      for (std::size_t c = 0; c < cells.size(); ++c)
        if (header[c].rfind("potentiometer/", 0) == 0) cells[c].clear();
      l[r] = dmbd::cli_testing::join(cells);
    }
  });
  expect_report_error(d, (d / "log.csv").string() + ": variant 'potentiometer' has no values in any row (expected at least one row of its columns)");
}

TEST_F(RunData, ReportOfAColumnTwiceAPartialRowOrTimeBackwardsIsOneLine) {
  fs::path d = damaged_run([](std::vector<std::string>& l) {
    std::vector<std::string> header = dmbd::cli_testing::split(l[0]);
    header[2] = header[1];
    l[0] = dmbd::cli_testing::join(header);
  });
  expect_report_error(d, (d / "log.csv").string() + ":1: column 'encoder/l_knee.q' appears twice (expected each signal once, time first)");
  fs::remove_all(d);
  d = damaged_run([](std::vector<std::string>& l) {
    std::vector<std::string> cells = dmbd::cli_testing::split(l[3]);
    cells[5].clear();
    l[3] = dmbd::cli_testing::join(cells);
  });
  expect_report_error(d, (d / "log.csv").string() + ":4: variant 'encoder' has 14 of its 15 values (expected all or none)");
  fs::remove_all(d);
  d = damaged_run([](std::vector<std::string>& l) { std::swap(l[3], l[4]); });
  expect_report_error(d, (d / "log.csv").string() + ":5: time 0.002 is not after the previous row's 0.003 (expected increasing times)");
}

// Row 6.
TEST_F(RunData, CollectOfAPartWithNoRowsIsOneLineAndWritesNothing) {
  const fs::path d = damaged_plan([](nlohmann::json& p) { p["log"]["rows"] = 0; });
  write(d / "parts/2/log.bin", "");
  expect_collect_error(d, (d / "parts/2/part.json").string() + ": log.rows: 0 (expected a whole number of rows, at least 1)");
}

// Row 7.
TEST_F(RunData, CollectOfARowCountWhoseSizeWrapsIsOneLine) {
  const fs::path d = damaged_plan([](nlohmann::json& p) { p["log"]["rows"] = (std::uint64_t{1} << 57) + 501; });
  expect_collect_error(d, (d / "parts/2/part.json").string() +
                              ": log.rows: 144115188075856373 rows of 16 columns exceed the limit of a part's log (2147483648 bytes: "
                              "at most 16777216 rows)");
}

TEST_F(RunData, CollectOfAColumnListedTwiceIsOneLine) {
  const fs::path d = damaged_plan([](nlohmann::json& p) { p["log"]["columns"][3] = p["log"]["columns"][2]; });
  expect_collect_error(d, (d / "parts/2/part.json").string() + ": log.columns[3]: 'l_knee.qd' appears twice (expected each signal once)");
}

TEST_F(RunData, CollectOfFieldsOfTheWrongKindOrALogOfAnotherSizeIsOneLine) {
  fs::path d = damaged_plan([](nlohmann::json& p) { p["log"]["columns"][1] = 5; });
  expect_collect_error(d, (d / "parts/2/part.json").string() + ": log.columns[1]: expected a [name, unit] pair of strings");
  fs::remove_all(d);
  d = damaged_plan([](nlohmann::json& p) { p["log"]["rows"] = -3; });
  expect_collect_error(d, (d / "parts/2/part.json").string() + ": log.rows: -3 (expected a whole number of rows, at least 1)");
  fs::remove_all(d);
  d = damaged_plan([](nlohmann::json& p) { p["log"]["rows"] = p["log"]["rows"].get<int>() - 1; });
  expect_collect_error(d, (d / "parts/2/log.bin").string() + ": 25728 bytes or more, expected 25600 (16 columns of 200 doubles, as " +
                              (d / "parts/2/part.json").string() + " says)");
}

// Found by fuzz_sweep_part: a count too large for its integer (a float such as 7.18e20)
// was converted anyway (undefined behaviour); now one line, in part.json and metrics.json.
TEST_F(RunData, ACountBeyondItsIntegerInTheRunFactsIsOneLine) {
  fs::path d = damaged_plan([](nlohmann::json& p) { p["run"]["integrator_steps"] = 7.18e20; });
  expect_collect_error(d, (d / "parts/2/part.json").string() + ": run.integrator_steps: 7.18e+20 (expected a whole number)");
  fs::remove_all(d);
  d = damaged_run([](std::vector<std::string>&) {});
  nlohmann::json m = nlohmann::json::parse(slurp(d / "metrics.json"));
  m["runs"]["encoder"]["controller_steps"] = {1.5};
  write(d / "metrics.json", m.dump());
  expect_report_error(d, (d / "metrics.json").string() + ": runs.encoder: run.controller_steps: 1.5 (expected a whole number)");
}

// Row 8.
TEST_F(RunData, EndlessInputsAreRefusedAtOnce) {
  const auto sim = run_dmbd({"simulate", "/dev/zero", "--out", (root() / "t").string()}, root());
  EXPECT_EQ(sim.code, 2);
  EXPECT_EQ(lines_of(sim.err).size(), 1u) << sim.err;
  EXPECT_NE(sim.err.find("/dev/zero:1:1: the file is not text: byte 1 is 0x00, a control character"), std::string::npos) << sim.err;
  const auto an = run_dmbd({"analyze", "/dev/urandom", "--from", "a", "--to", "b"}, root());
  EXPECT_EQ(an.code, 2);
  EXPECT_NE(an.err.find("/dev/urandom:1:"), std::string::npos) << an.err;
  EXPECT_NE(an.err.find("the file is not text: byte "), std::string::npos) << an.err;
  EXPECT_FALSE(fs::exists(root() / "t"));
}

}  // namespace
