// `dmbd analyze`: certified stability verdicts and poles near the unit circle and the
// imaginary axis (issue 28, rows 1, 1b, 3 and 4). Golden values from closed forms:
// ZOH maps a pole p to e^{pT} and keeps the DC gain; the z-polynomial's value at 1 is
// computed exactly (Python fractions) for its DC gain.
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

class AnalyzeCertified : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("dmbd_certified_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  dmbd::cli_testing::Result run(std::vector<std::string> args) {
    args.insert(args.begin(), "analyze");
    return dmbd::cli_testing::run_dmbd(args, dir_);
  }
  json analyze(std::vector<std::string> args) {
    args.push_back("--json");
    const dmbd::cli_testing::Result r = run(args);
    EXPECT_EQ(r.code, 0) << r.err;
    return r.code == 0 ? json::parse(r.out) : json::object();
  }
  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  fs::path dir_;
};

// Row 1: was "not stable" with poles 0.999998 and 0.999999 (the discrete denominator's
// roots, a pole at exactly 1 by a 1e-12 coefficient tolerance).
TEST_F(AnalyzeCertified, ZohOfTwoSlowLagsIsStableWithItsExactPoles) {
  const json j = analyze({"--tf", "1/((s+0.01)*(s+0.02))", "--c2d", "zoh", "--ts", "1e-4"});
  EXPECT_EQ(j["stability"], "stable");
  EXPECT_NEAR(j["dc_gain"].get<double>(), 5000.0, 5000.0 * 1e-12);
  const json& d = j["discrete"];
  EXPECT_TRUE(d["stable"].get<bool>());
  ASSERT_EQ(d["poles"].size(), 2u);
  EXPECT_NEAR(d["poles"][0][0].get<double>(), std::exp(-0.02e-4), 1e-15);
  EXPECT_NEAR(d["poles"][1][0].get<double>(), std::exp(-0.01e-4), 1e-15);
  const dmbd::cli_testing::Result r = run({"--tf", "1/((s+0.01)*(s+0.02))", "--c2d", "zoh", "--ts", "1e-4"});
  EXPECT_NE(r.out.find("), stable"), std::string::npos) << r.out;
}

// Row 1b: 1/(s^2 + 10 s + 100) at 1e-7 s has its poles 5e-7 inside the circle.
TEST_F(AnalyzeCertified, ZohAtTinySampleTimeKeepsPolesInsideTheCircle) {
  const json d = analyze({"--tf", "1/(s^2+10*s+100)", "--c2d", "zoh", "--ts", "1e-7"})["discrete"];
  EXPECT_TRUE(d["stable"].get<bool>());
  ASSERT_EQ(d["poles"].size(), 2u);
  for (const json& p : d["poles"])
    EXPECT_NEAR(std::hypot(p[0].get<double>(), p[1].get<double>()), std::exp(-5e-7), 1e-15);
}

// Row 1b, in z: the coefficients as written have no root at 1 (their sum is
// 9.999778782798785e-13, exactly); was "marginally stable", a pole at exactly 1, DC
// gain infinite.
TEST_F(AnalyzeCertified, AZPolynomialOneMinusFiveE7FromTheCircleIsStable) {
  const json j = analyze({"--tf", "1/(z^2-1.9999989999994998*z+0.9999990000004998)", "--ts", "1e-7"});
  EXPECT_EQ(j["stability"], "stable");
  ASSERT_FALSE(j["dc_gain"].is_null());
  EXPECT_NEAR(j["dc_gain"].get<double>(), 1000022122209.5028, 1000022122209.5028 * 1e-12);
  for (const json& p : j["poles"]) {
    const double m = std::hypot(p[0].get<double>(), p[1].get<double>());
    EXPECT_NEAR(m, 1.0 - 5e-7, 1e-9);
  }
}

// Row 3: a power of a factor keeps the factor: twenty poles exactly at -1 (were
// scattered from -0.75 to -1.33 by the roots of the expanded polynomial).
TEST_F(AnalyzeCertified, APowerOfAFactorKeepsItsRootsExactly) {
  const json j = analyze({"--tf", "1/(s+1)^20"});
  ASSERT_EQ(j["poles"].size(), 20u);
  for (const json& p : j["poles"]) {
    EXPECT_EQ(p[0].get<double>(), -1.0);
    EXPECT_EQ(p[1].get<double>(), 0.0);
  }
  EXPECT_EQ(j["stability"], "stable");
  EXPECT_EQ(j["dc_gain"].get<double>(), 1.0);
}

// The verdict of the coefficients exactly as written: 1 - 2^-53 is a pole inside;
// z^2 - 1.6 z + 0.6 (the doubles 1.6 and 0.6) has a root at 1 + 2.8e-16 (mpmath,
// 50 digits), outside; (z - 1)(z - 0.6) written as factors has its pole at 1
// structurally. Where the certified enclosure straddles the boundary the verdict is
// "undecided", printed and in JSON: s^2 + 1e-300 s + 1 has its poles 5e-301 left of the
// axis, far below what an enclosure of a root of modulus 1 resolves.
TEST_F(AnalyzeCertified, VerdictsOfTheCoefficientsAsWrittenOrUndecided) {
  EXPECT_EQ(analyze({"--tf", "1/(z - 0.99999999999999989)", "--ts", "1"})["stability"], "stable");
  EXPECT_EQ(analyze({"--tf", "1/(z^2 - 1.6*z + 0.6)", "--ts", "1"})["stability"], "unstable");
  EXPECT_EQ(analyze({"--tf", "1/((z - 1)*(z - 0.6))", "--ts", "1"})["stability"], "marginal");
  const json j = analyze({"--tf", "1/(s^2 + 1e-300*s + 1)"});
  EXPECT_EQ(j["stability"], "undecided");
  EXPECT_FALSE(j["stable"].get<bool>());
  EXPECT_NE(run({"--tf", "1/(s^2 + 1e-300*s + 1)"}).out.find("stability undecided at this precision"), std::string::npos);
}

// Row 4: a discrete loop with an integrator, broken at the outer loop and at the inner
// one: the integrator is exactly z = 1 at every break point (DC gain infinite, no
// bandwidth), never 0.9999999999999999 with a DC gain of 5e14.
TEST_F(AnalyzeCertified, AnIntegratorInACascadeIsExactAtEveryBreakPoint) {
  const fs::path d = write("cascade.yaml", R"yaml(
name: cascade
sample_time: 0.001
parameters: {Kp: 20, Kv: 5, Ki: 50}
inputs: {r: {}}
outputs: {y: {}}
blocks:
  e_pos: {type: sum, signs: "+-"}
  Cp:    {type: gain, k: Kp}
  e_vel: {type: sum, signs: "+-"}
  Cv:    {type: pid, P: Kv, I: Ki, D: 0.01, tau: 0.0023}
  plant: {type: tf, expr: "0.001/(z - 0.99)"}
  pos:   {type: integrator}
connections:
  - r -> e_pos.in1
  - e_pos -> Cp
  - Cp -> e_vel.in1
  - e_vel -> Cv
  - Cv -> plant
  - plant -> [e_vel.in2, pos]
  - pos -> [y, e_pos.in2]
)yaml");
  for (const char* at : {"Cp.out", "e_pos.out", "pos.out"}) {
    const json j = analyze({d.string(), "--loop-at", at});
    EXPECT_TRUE(j["dc_gain"].is_null()) << at;
    EXPECT_TRUE(j["bandwidth_hz"].is_null()) << at;
    EXPECT_EQ(j["stability"], "marginal") << at;
    int at_one = 0;
    for (const json& p : j["poles"]) at_one += p[0].get<double>() == 1.0 && p[1].get<double>() == 0.0;
    EXPECT_EQ(at_one, 1) << at;
  }
}

}  // namespace
