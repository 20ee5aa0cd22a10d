// `dmbd analyze` on the cases of issue 13, items 1 and 11: loops with integrators
// broken with --loop-at, a discrete loop with a pole at z = 1, a discrete L/(1 + L)
// written out, and a diagram of 1000 first-order filters. Each figure is checked
// against its closed form.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_support.hpp"
#include "chain_diagram.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class AnalyzeStructure : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("dmbd_structure_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  json analyze(const std::vector<std::string>& args) {
    std::vector<std::string> full{"analyze"};
    full.insert(full.end(), args.begin(), args.end());
    full.push_back("--json");
    const dmbd::cli_testing::Result r = dmbd::cli_testing::run_dmbd(full, dir_);
    EXPECT_EQ(r.code, 0) << r.err;
    return r.code == 0 ? json::parse(r.out) : json::object();
  }
  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }

  fs::path dir_;
};

const char* kPdOnMass = R"yaml(
name: pd_mass
parameters: {M: 2.0}
inputs: {r: {}}
outputs: {y: {}}
blocks:
  err: {type: sum, signs: "+-"}
  C:   {type: pd, P: 100, D: 20, tau: 0.001}
  P:   {type: tf, expr: "1/(M*s^2)"}
connections:
  - r -> err.in1
  - err -> C
  - C -> P
  - P -> [y, err.in2]
)yaml";

TEST_F(AnalyzeStructure, LoopAtAPlantWithIntegratorsHasPolesExactlyAtTheOrigin) {
  // L = (100 + 20 s/(0.001 s + 1))/(2 s^2) at either break. Before: poles at ~1e-13,
  // DC gains of 1e13..1e18, bandwidths of 1e-9 Hz, a -340 dB gain margin at 4e-9 Hz,
  // and "stable" at some breaks. Now: [0, 0] twice exactly, DC gain and bandwidth
  // null, not stable, no phase crossover (the phase stays above -180 deg: -180 + atan
  // terms of the lead); PM = 180 + angle L(j wc) at |L| = 1 (the same at both breaks,
  // 1e-9 deg).
  const fs::path d = write("pd_mass.yaml", kPdOnMass);
  std::vector<double> pm;
  for (const char* at : {"C.out", "err.in2"}) {
    const json j = analyze({d.string(), "--loop-at", at});
    ASSERT_TRUE(j.contains("poles")) << at;
    int at_origin = 0;
    for (const auto& p : j["poles"]) at_origin += p[0].get<double>() == 0.0 && p[1].get<double>() == 0.0;
    EXPECT_EQ(at_origin, 2) << at;
    EXPECT_TRUE(j["dc_gain"].is_null()) << at;
    EXPECT_TRUE(j["bandwidth_hz"].is_null()) << at;
    EXPECT_FALSE(j["stable"].get<bool>()) << at;
    EXPECT_EQ(j["stability"], "unstable") << at;
    EXPECT_TRUE(j["phase_crossovers"].empty()) << at;
    EXPECT_TRUE(j["gain_margin_db"].is_null()) << at;
    pm.push_back(j["phase_margin_deg"].get<double>());
  }
  // Closed form: |L(jw)| = 1 solved by bisection here, PM = atan(20.1 w/100) - atan(0.001 w).
  auto mag = [](double w) {
    return std::abs((100.0 + std::complex<double>(0, 20.0 * w) / (std::complex<double>(0, 0.001 * w) + 1.0)) / (2.0 * w * w));
  };
  double lo = 0.1, hi = 100.0;
  for (int k = 0; k < 200; ++k) (mag(0.5 * (lo + hi)) > 1.0 ? lo : hi) = 0.5 * (lo + hi);
  const double wc = 0.5 * (lo + hi);
  const double want = (std::atan(20.1 * wc / 100.0) - std::atan(0.001 * wc)) * 180.0 / M_PI;
  for (double p : pm) EXPECT_NEAR(p, want, 1e-9);
}

TEST_F(AnalyzeStructure, DiscreteLoopWithAPoleAtOneHasNoCrossoverAtDc) {
  // dmbd analyze --tf '0.1*(z-0.9)/((z-1)*(z-0.6))' --ts 0.001: before, a phase
  // crossover at 0 Hz with GM -279 dB. L is infinite at DC: the only phase crossover is
  // Nyquist, L(-1) = 0.1 (-1.9)/((-2)(-1.6)) = -0.059375, GM = -20 log10 0.059375
  // (1e-9 dB); the pole at z = 1 is exactly 1; marginal (a simple pole on the circle).
  const json j = analyze({"--tf", "0.1*(z-0.9)/((z-1)*(z-0.6))", "--ts", "0.001"});
  ASSERT_EQ(j["phase_crossovers"].size(), 1u);
  EXPECT_NEAR(j["phase_crossovers"][0]["freq_hz"].get<double>(), 500.0, 1e-9);
  EXPECT_NEAR(j["gain_margin_db"].get<double>(), -20.0 * std::log10(0.059375), 1e-9);
  EXPECT_EQ(j["poles"].back()[0].get<double>(), 1.0);
  EXPECT_EQ(j["stability"], "marginal");
  EXPECT_FALSE(j["stable"].get<bool>());
  EXPECT_TRUE(j["dc_gain"].is_null());
  EXPECT_TRUE(j["bandwidth_hz"].is_null());
}

TEST_F(AnalyzeStructure, DiscreteClosedLoopWrittenOutCancelsItsPoleAtOne) {
  // L/(1 + L) written as one expression keeps (z - 1)(z - 0.6) above and below. Before:
  // a pole at 0.99999999993 reported "stable" with a 1.8e-11 Hz bandwidth and GM at
  // 0 Hz. Now the pole at 1 is a hidden mode (common to both), the transfer
  // (0.1 z - 0.09)/(z^2 - 1.5 z + 0.51) times (z - 0.6)/(z - 0.6) is stable, DC gain 1
  // (1e-12), and its step figures exist; the bandwidth equals that of the diagram's
  // closed loop (1e-9 relative: two formulations).
  const std::string l = "0.1*(z-0.9)/((z-1)*(z-0.6))";
  const json j = analyze({"--tf", "(" + l + ")/(1 + " + l + ")", "--ts", "0.001", "--step", "0.5:2"});
  EXPECT_TRUE(j["stable"].get<bool>());
  ASSERT_EQ(j["hidden_poles"].size(), 1u);
  EXPECT_EQ(j["hidden_poles"][0][0].get<double>(), 1.0);
  for (const auto& p : j["poles"]) EXPECT_LT(std::hypot(p[0].get<double>(), p[1].get<double>()), 0.98);
  EXPECT_NEAR(j["dc_gain"].get<double>(), 1.0, 1e-12);
  for (const char* k : {"rise_time_s", "settling_time_s", "overshoot_pct", "final_value"})
    EXPECT_FALSE(j["step"][k].is_null()) << k;
  const fs::path d = write("dloop.yaml", R"yaml(
name: dloop
sample_time: 0.001
inputs: {r: {}}
outputs: {y: {}}
blocks:
  err: {type: sum, signs: "+-"}
  L:   {type: tf, expr: "0.1*(z-0.9)/((z-1)*(z-0.6))"}
connections:
  - r -> err.in1
  - err -> L
  - L -> [y, err.in2]
)yaml");
  const json c = analyze({d.string(), "--from", "r", "--to", "y"});
  EXPECT_NEAR(j["bandwidth_hz"].get<double>(), c["bandwidth_hz"].get<double>(), 1e-9 * c["bandwidth_hz"].get<double>());
  EXPECT_GT(j["bandwidth_hz"].get<double>(), 1.0);
}

TEST_F(AnalyzeStructure, ChainOfThousandFirstOrderFilters) {
  // 1000 blocks 10/(s + 10) from u to y (before: "non-finite coefficient" from 200
  // blocks on). Poles -10 x 1000, DC gain 1 (1e-12), no margins (not a loop), bandwidth at w = 10 sqrt(10^(0.3/1000) - 1) (1e-9 relative); Bode at 1 Hz
  // is -10000 log10(1 + (2 pi/10)^2) dB with phase -1000 atan(2 pi/10) (1e-9 relative);
  // the step rises around 1000 tau = 100 s.
  const fs::path d = write("chain.yaml", dmbd::test::chain_diagram(1000, "{type: tf, expr: \"10/(s+10)\"}"));
  const json j = analyze({d.string(), "--from", "u", "--to", "y", "--freq", "1", "--step", "200:401"});
  ASSERT_EQ(j["poles"].size(), 1000u);
  for (const auto& p : j["poles"]) EXPECT_EQ(p, json::array({-10.0, 0.0}));
  EXPECT_TRUE(j["zeros"].empty());
  EXPECT_EQ(j["states"], 1000);
  EXPECT_NEAR(j["dc_gain"].get<double>(), 1.0, 1e-12);
  // A transfer between two signals is no loop: no margins at all (issue 28, row 14; the
  // chain had no gain crossover, |G| < 1 for w > 0).
  EXPECT_FALSE(j.contains("gain_crossovers"));
  EXPECT_EQ(j["loop_transfer"], false);
  const double bw = 10.0 * std::sqrt(std::pow(10.0, 0.3 / 1000.0) - 1.0) / (2.0 * M_PI);
  EXPECT_NEAR(j["bandwidth_hz"].get<double>(), bw, 1e-9 * bw);
  const double x = 2.0 * M_PI / 10.0, mag = -10000.0 * std::log10(1.0 + x * x), ph = -1000.0 * std::atan(x) * 180.0 / M_PI;
  EXPECT_NEAR(j["bode"]["mag_db"][0].get<double>(), mag, 1e-9 * std::abs(mag));
  EXPECT_NEAR(j["bode"]["phase_deg"][0].get<double>(), ph, 1e-9 * std::abs(ph));
  const double rise = j["step"]["rise_time_s"].get<double>();
  EXPECT_GT(rise, 5.0);   // 10-90 % of an Erlang(1000, 10): about 2 x 1.28 sqrt(1000)/10 = 8.1 s
  EXPECT_LT(rise, 10.0);
  EXPECT_NEAR(j["step"]["final_value"].get<double>(), 1.0, 1e-12);
}

}  // namespace
