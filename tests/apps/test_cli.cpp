// The `dmbd` command line: help, version, analysis output, and every bad-input case
// of issue 2 (one line on stderr naming the problem and where, exit code 2, no output
// file written, never a crash).
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

using dmbd::cli_testing::quote;
using dmbd::cli_testing::Result;
using dmbd::cli_testing::slurp;

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("dmbd_cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  Result run(const std::vector<std::string>& args) { return dmbd::cli_testing::run_dmbd(args, dir_); }

  // A bad-input case: exit 2, exactly one line on stderr containing every fragment,
  // nothing on stdout, and no file left in the output folder.
  void expect_bad(const std::vector<std::string>& args, const std::vector<std::string>& fragments) {
    std::vector<std::string> full = args;
    full.insert(full.end(), {"--bode", (dir_ / "b.png").string(), "--step-plot", (dir_ / "s.png").string()});
    const Result r = run(full);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind("dmbd: error: ", 0), 0u) << r.err;
    for (const auto& f : fragments) EXPECT_NE(r.err.find(f), std::string::npos) << "missing '" << f << "' in: " << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
    EXPECT_TRUE(fs::is_empty(dir_)) << "an output file was written";
  }

  fs::path dir_;
};

TEST_F(Cli, HelpAndVersion) {
  Result r = run({"--help"});
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("analyze"), std::string::npos);
  r = run({"--version"});
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("dmbd 0."), std::string::npos);
  r = run({"analyze", "--help"});
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("--freq-range"), std::string::npos);
}

TEST_F(Cli, JsonReportOfThePaperQFilter) {
  // Paper eq. frc_ctrl: Q = 1/((s/wc)^2 + sqrt(2) s/wc + 1), wc = 2 pi 60 Hz.
  const Result r = run({"analyze", "--tf", "1/((s/wc)^2 + sqrt(2)*s/wc + 1)", "--param", "wc=2*pi*60", "--json",
                        "--freq", "60", "--step", "0.05:501", "--c2d", "tustin", "--ts", "0.001"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const double wc = 2 * M_PI * 60;
  ASSERT_EQ(j["den"].size(), 3u);
  EXPECT_DOUBLE_EQ(j["den"][0].get<double>(), 1.0);  // leading coefficient scaled to exactly 1
  EXPECT_NEAR(j["den"][1].get<double>(), std::sqrt(2.0) * wc, 1e-9 * wc);
  EXPECT_NEAR(j["den"][2].get<double>(), wc * wc, 1e-9 * wc * wc);
  EXPECT_EQ(j["order"].get<int>(), 2);
  EXPECT_TRUE(j["stable"].get<bool>());
  EXPECT_NEAR(j["dc_gain"].get<double>(), 1.0, 1e-12);
  EXPECT_NEAR(j["bode"]["mag_db"][0].get<double>(), -10 * std::log10(2.0), 1e-9);  // -3.0103 dB at the cutoff
  EXPECT_NEAR(j["bode"]["phase_deg"][0].get<double>(), -90.0, 1e-9);
  EXPECT_TRUE(j["gain_margin_db"].is_null());   // |Q| < 1 everywhere: no gain crossover...
  EXPECT_TRUE(j["phase_margin_deg"].is_null());  // ...and the phase never reaches -180
  EXPECT_EQ(j["step"]["t"].size(), 501u);
  // Overshoot of zeta = 1/sqrt(2): exp(-pi) * 100 = 4.3214 %.
  EXPECT_NEAR(j["step"]["overshoot_pct"].get<double>(), 100 * std::exp(-M_PI), 1e-7);
  EXPECT_EQ(j["discrete"]["method"], "tustin");
  EXPECT_DOUBLE_EQ(j["discrete"]["den"][0].get<double>(), 1.0);
  EXPECT_EQ(j["discrete"]["poles"].size(), 2u);
}

TEST_F(Cli, SummaryAndPlots) {
  const auto bode = dir_ / "bode.png", step = dir_ / "step.png";
  const Result r = run({"analyze", "--tf", "10/(s*(s+1)*(s+5))", "--bode", bode.string(), "--step-plot", step.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("gain margin: 9.54243 dB"), std::string::npos) << r.out;  // 20 log10(3)
  EXPECT_GT(fs::file_size(bode), 10000u);
  EXPECT_GT(fs::file_size(step), 5000u);
  for (const auto& e : fs::directory_iterator(dir_)) EXPECT_NE(e.path().extension(), ".tmp");
}

TEST_F(Cli, DiscreteExpressionInZ) {
  const Result r = run({"analyze", "--tf", "0.5/(z - 0.5)", "--ts", "0.01", "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_FALSE(j["continuous"].get<bool>());
  EXPECT_NEAR(j["dc_gain"].get<double>(), 1.0, 1e-12);  // 0.5 / (1 - 0.5)
}

TEST_F(Cli, BadExpressions) {
  expect_bad({"analyze", "--tf", "1/(s+"}, {"--tf '1/(s+'", "column 6", "expected"});
  expect_bad({"analyze", "--tf", "1/(s+1"}, {"column 7", "')'"});
  expect_bad({"analyze", "--tf", "2s+1"}, {"column 1", "malformed number"});
  expect_bad({"analyze", "--tf", "1/(s^2+x*s+1)"}, {"column 8", "unknown parameter 'x'"});
  expect_bad({"analyze", "--tf", "s^0.5"}, {"column 3", "integer"});
  expect_bad({"analyze", "--tf", "1/0"}, {"column 2", "division by zero"});
  expect_bad({"analyze", "--tf", "s+z"}, {"uses both s and z"});
  expect_bad({"analyze", "--tf", "1/(z-0.5)"}, {"needs --ts"});
  expect_bad({"analyze", "--tf", "foo(2)*s"}, {"column 1", "unknown function"});
  expect_bad({"analyze", "--tf", ""}, {"empty expression"});
}

TEST_F(Cli, ImproperWhereProperIsNeeded) {
  expect_bad({"analyze", "--tf", "s^2/(s+1)", "--step", "1:10"}, {"proper"});
  expect_bad({"analyze", "--tf", "s^2/(s+1)", "--c2d", "tustin", "--ts", "0.01"}, {"proper"});
}

TEST_F(Cli, BadSampleTimes) {
  expect_bad({"analyze", "--tf", "1/(s+1)", "--c2d", "zoh", "--ts", "0"}, {"--ts", "> 0"});
  expect_bad({"analyze", "--tf", "1/(s+1)", "--c2d", "zoh", "--ts", "-0.1"}, {"--ts", "> 0"});
  expect_bad({"analyze", "--tf", "1/(s+1)", "--c2d", "zoh"}, {"needs --ts"});
  expect_bad({"analyze", "--tf", "1/(s+1)", "--c2d", "magic", "--ts", "0.1"}, {"unknown discretisation method"});
  expect_bad({"analyze", "--tf", "1/(s+1)", "--c2d", "tustin", "--ts", "0.01", "--prewarp", "60"}, {"Nyquist"});
}

TEST_F(Cli, BadOptions) {
  expect_bad({"analyze", "--tf", "1/(s+1)", "--param", "wc"}, {"NAME=VALUE"});
  expect_bad({"analyze", "--tf", "1/(s+1)", "--param", "wc=2*"}, {"--param wc", "column 3"});
  expect_bad({"analyze", "--tf", "1/(s+1)", "--freq", "1,,2"}, {"--freq"});
  expect_bad({"analyze", "--tf", "1/(s+1)", "--freq", "-1"}, {"--freq", "> 0"});
  expect_bad({"analyze", "--tf", "1/(s+1)", "--freq-range", "1:10"}, {"LO:HI:N"});
  expect_bad({"analyze", "--tf", "1/(s+1)", "--freq-range", "10:1:5"}, {"HI"});
  expect_bad({"analyze", "--tf", "1/(s+1)", "--freq-range", "1:10:2.5"}, {"whole number"});
  expect_bad({"analyze", "--tf", "1/(s+1)", "--step", "abc:10"}, {"--step", "unknown parameter 'abc'"});
  expect_bad({"analyze", "--tf", "1/(s+1)", "--step", "1:1"}, {"at least 2"});
  expect_bad({"analyze", "--tf", "1/(s+1)", "--nonsense"}, {"nonsense"});
  expect_bad({"analyze"}, {"--tf"});
  expect_bad({"analyze", "--tf", "1/(s+1)", "--ts", "0.1"}, {"--ts"});
}

TEST_F(Cli, UnwritablePlotLeavesNothing) {
  const Result r = run({"analyze", "--tf", "1/(s+1)", "--bode", (dir_ / "missing" / "b.png").string(), "--step-plot",
                        (dir_ / "s.png").string()});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(dir_));
}

const std::string kData = DMBD_TEST_DATA;

TEST_F(Cli, AnalyzeDiagramBetweenSignals) {
  // The worked example of docs/diagram-format.md: x/x_d has DC gain Kp / (k + Kp) = 900/1300.
  Result r = run({"analyze", kData + "/pd_loop.yaml", "--from", "x_d", "--to", "x", "--json", "--step", "1:501"});
  ASSERT_EQ(r.code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["dc_gain"].get<double>(), 900.0 / 1300.0, 1e-9);
  EXPECT_TRUE(j["stable"].get<bool>());
  EXPECT_TRUE(j["internally_stable"].get<bool>());
  EXPECT_EQ(j["from"], "x_d");
  // --param overrides reach the diagram: Kp = 400 gives 400/800.
  r = run({"analyze", kData + "/pd_loop.yaml", "--from", "x_d", "--to", "x", "--json", "--param", "Kp=400"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NEAR(nlohmann::json::parse(r.out)["dc_gain"].get<double>(), 0.5, 1e-9);
}

TEST_F(Cli, LoopAtAndSweep) {
  Result r = run({"analyze", kData + "/pd_loop.yaml", "--loop-at", "plant.out", "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_GT(j["gain_margin_db"].get<double>(), 0.0);  // a stable loop
  EXPECT_GT(j["phase_margin_deg"].get<double>(), 0.0);
  r = run({"analyze", kData + "/pd_loop.yaml", "--from", "x_d", "--to", "x", "--json", "--sweep", "Kp=100:1e4:7:log"});
  ASSERT_EQ(r.code, 0) << r.err;
  j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["sweep"].size(), 7u);
  EXPECT_DOUBLE_EQ(j["sweep"][0]["value"].get<double>(), 100.0);
  EXPECT_DOUBLE_EQ(j["sweep"][6]["value"].get<double>(), 1e4);
  for (const auto& p : j["sweep"]) {
    const double kp = p["value"].get<double>();
    EXPECT_NEAR(p["dc_gain"].get<double>(), kp / (400.0 + kp), 1e-9);
    EXPECT_EQ(p["stable"].get<bool>(), p["max_real_pole"].get<double>() < 0.0);
  }
}

TEST_F(Cli, DiagramErrorsNameFileLineColumn) {
  const Result r = run({"analyze", kData + "/bad/unknown_block_type.yaml", "--from", "u", "--to", "y"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("unknown_block_type.yaml:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(": error: unknown block type"), std::string::npos) << r.err;
  const Result s = run({"analyze", kData + "/pd_loop.yaml", "--from", "x_d", "--to", "nowhere"});
  EXPECT_EQ(s.code, 2);
  EXPECT_NE(s.err.find("unknown signal 'nowhere'"), std::string::npos) << s.err;
  const Result t = run({"analyze", kData + "/missing.yaml", "--from", "a", "--to", "b"});
  EXPECT_EQ(t.code, 2);
  EXPECT_NE(t.err.find("cannot read"), std::string::npos) << t.err;
}

TEST_F(Cli, DrawAndTune) {
  const auto png = dir_ / "d.png";
  Result r = run({"draw", kData + "/pd_loop.yaml", "--out", png.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_GT(fs::file_size(png), 5000u);
  r = run({"draw", kData + "/pd_loop.yaml", "--out", (dir_ / "no" / "d.png").string()});
  EXPECT_EQ(r.code, 2);
  // Tuning a PD loop on measurement: the result is stable and within the overshoot bound.
  r = run({"tune", kData + "/pd_on_measurement.yaml", "--from", "x_d", "--to", "x", "--p", "Kp", "--d", "Kd", "--json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["stable"].get<bool>());
  EXPECT_LE(j["overshoot_pct"].get<double>(), 0.5 + 1e-9);
  // D backed off 6 dB from the stability limit.
  EXPECT_NEAR(j["d"].get<double>(), j["d_critical"].get<double>() * std::pow(10.0, -6.0 / 20.0), 1e-9 * j["d"].get<double>());
}

}  // namespace
