// `dmbd analyze`: margins only where the transfer is a loop (issue 28, row 14), and the
// blocks the linear analysis replaces by their linear part named (row 13: a pid with
// output limits is analysed as its unsaturated law).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_support.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using dmbd::cli_testing::Result;
using dmbd::cli_testing::run_dmbd;

const std::string kData = DMBD_TEST_DATA;
const char* const kMarginKeys[] = {"gain_margin_db", "phase_crossover_hz", "phase_margin_deg", "gain_crossover_hz",
                                   "gain_crossovers", "phase_crossovers"};

class AnalyzeLoop : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("dmbd_loop_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  Result run(const std::vector<std::string>& args) { return run_dmbd(args, dir_); }
  json analyze(std::vector<std::string> args) {
    args.insert(args.begin(), "analyze");
    args.push_back("--json");
    const Result r = run(args);
    EXPECT_EQ(r.code, 0) << r.err;
    return r.code == 0 ? json::parse(r.out) : json::object();
  }
  fs::path dir_;
};

// A closed loop from --from to --to is no loop: before, its "gain margin" (the closed
// loop x_d -> x of pd_loop.yaml taken as an open loop) was printed and marked as a
// phase crossover on the Bode plot. Now no margin keys, loop_transfer false, and the
// summary says why and where the margins are.
TEST_F(AnalyzeLoop, ATransferBetweenTwoSignalsHasNoMargins) {
  const json j = analyze({kData + "/pd_loop.yaml", "--from", "x_d", "--to", "x"});
  EXPECT_EQ(j["loop_transfer"], false);
  for (const char* k : kMarginKeys) EXPECT_FALSE(j.contains(k)) << k;
  EXPECT_TRUE(j["stable"].get<bool>());
  EXPECT_FALSE(j["bandwidth_hz"].is_null());  // a closed loop's bandwidth stays
  const fs::path bode = dir_ / "bode.png";
  const Result r = run({"analyze", kData + "/pd_loop.yaml", "--from", "x_d", "--to", "x", "--bode", bode.string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out.find("gain margin"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("margins: none (a transfer between two signals is not a loop; --loop-at SIGNAL gives the loop's margins)"),
            std::string::npos)
      << r.out;
  EXPECT_GT(fs::file_size(bode), 10000u);
}

// A loop (--loop-at) and a --tf (taken as a loop transfer function, as python-control's
// margin() takes any transfer) keep their margins: 10/(s (s+1) (s+5)) has GM
// 20 log10(3) dB at sqrt(5) rad/s (1e-9).
TEST_F(AnalyzeLoop, LoopsAndTransferFunctionsKeepTheirMargins) {
  json j = analyze({kData + "/pd_loop.yaml", "--loop-at", "plant.out"});
  EXPECT_EQ(j["loop_transfer"], true);
  for (const char* k : kMarginKeys) EXPECT_TRUE(j.contains(k)) << k;
  EXPECT_GT(j["phase_margin_deg"].get<double>(), 0.0);
  j = analyze({"--tf", "10/(s*(s+1)*(s+5))"});
  EXPECT_EQ(j["loop_transfer"], true);
  EXPECT_NEAR(j["gain_margin_db"].get<double>(), 20.0 * std::log10(3.0), 1e-9);
  EXPECT_NEAR(j["phase_crossover_hz"].get<double>(), std::sqrt(5.0) / (2.0 * M_PI), 1e-9);
  const Result r = run({"analyze", "--tf", "10/(s*(s+1)*(s+5))"});
  EXPECT_NE(r.out.find("gain margin: 9.54243 dB"), std::string::npos) << r.out;
}

// A pid with output limits and anti-windup and a saturation: the analysis is that of the
// unsaturated law (the same poles and DC gain as without the limits, exactly: the same
// linear model), and says so in the JSON and in the summary.
TEST_F(AnalyzeLoop, ALimitedPidIsAnalysedAsItsUnsaturatedLawAndSaysSo) {
  auto write = [&](const std::string& name, const std::string& extra) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << "name: pi_loop\ninputs:\n  r: {}\noutputs:\n  y: {}\nblocks:\n"
                        "  err: {type: sum, signs: \"+-\"}\n"
                        "  C: {type: pid, P: 2, I: 5" << extra << "}\n"
                        "  plant: {type: tf, expr: \"1/(s + 1)\"}\n"
                        "connections:\n  - r -> err.in1\n  - err -> C\n  - C -> plant\n  - plant -> [y, err.in2]\n";
    return p.string();
  };
  const std::string limited = write("limited.yaml", ", output_limits: [-3, 3], anti_windup: back_calculation, Kt: 4");
  const json a = analyze({limited, "--from", "r", "--to", "y"});
  const json b = analyze({write("free.yaml", ""), "--from", "r", "--to", "y"});
  EXPECT_EQ(a["poles"], b["poles"]);
  EXPECT_EQ(a["dc_gain"], b["dc_gain"]);
  ASSERT_EQ(a["linearised"].size(), 1u);
  EXPECT_EQ(a["linearised"][0]["block"], "C");
  EXPECT_EQ(a["linearised"][0]["type"], "pid");
  EXPECT_TRUE(b["linearised"].empty());
  const Result r = run({"analyze", limited, "--loop-at", "C.out"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("linearised: pid 'C' analysed as the unsaturated law P + I/s + D s/(tau s + 1) (its output_limits and "
                       "anti_windup back_calculation left out)"),
            std::string::npos)
      << r.out;
}

}  // namespace
