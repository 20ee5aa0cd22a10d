// `dmbd analyze` on delays and sampled-data loops (issue 17): exp(-s*T) in --tf (a
// Padé approximant in s, z^-n in z, exact under --c2d), --minreal, the sweep's
// per-value verdicts, and a discrete diagram around a continuous plant.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

namespace fs = std::filesystem;
using dmbd::cli_testing::Result;
using nlohmann::json;

class AnalyzeSampled : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dmbd_sampled_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  Result run(const std::vector<std::string>& args) { return dmbd::cli_testing::run_dmbd(args, dir_); }
  json run_json(std::vector<std::string> args) {
    args.push_back("--json");
    const Result r = run(args);
    EXPECT_EQ(r.code, 0) << r.err;
    return r.code == 0 ? json::parse(r.out) : json();
  }
  void expect_error(const std::vector<std::string>& args, const std::string& fragment) {
    const Result r = run(args);
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(fragment), std::string::npos) << r.err;
  }
  fs::path dir_;
};

const std::string kSampled = std::string(DMBD_TEST_DATA) + "/sampled/";

TEST_F(AnalyzeSampled, ADelayInSIsItsPadeApproximantOfTheChosenOrder) {
  const json j3 = run_json({"analyze", "--tf", "exp(-s*T)/(s + 1)", "--param", "T=0.01"});
  EXPECT_EQ(j3["order"].get<int>(), 4);  // the lag and Padé order 3
  EXPECT_EQ(j3["pade_order"].get<int>(), 3);
  EXPECT_DOUBLE_EQ(j3["delay_s"].get<double>(), 0.01);
  const json j5 = run_json({"analyze", "--tf", "exp(-s*T)/(s + 1)", "--param", "T=0.01", "--pade", "5"});
  EXPECT_EQ(j5["order"].get<int>(), 6);
  // The phase margin of the delayed unity-gain lag 10/(s+1): 180 - 90 - atan(w_c) ... the
  // Padé approximant's phase at w_c = sqrt(99) is the delay's to 1e-6 degrees at order 5.
  const json pm = run_json({"analyze", "--tf", "10*exp(-s*0.01)/(s + 1)", "--pade", "5"});
  const double wc = std::sqrt(99.0);
  const double want = 180.0 - std::atan(wc) * 180.0 / M_PI - wc * 0.01 * 180.0 / M_PI;
  EXPECT_NEAR(pm["phase_margin_deg"].get<double>(), want, 1e-6);
}

TEST_F(AnalyzeSampled, ADelayInZIsWholeSamplesAndCDiscretisesItExactly) {
  const json z = run_json({"analyze", "--tf", "exp(-s*0.003)*0.5/(z - 0.5)", "--ts", "0.001"});
  EXPECT_EQ(z["order"].get<int>(), 4);
  EXPECT_EQ(z["delay_samples"].get<int>(), 3);
  EXPECT_NEAR(z["dc_gain"].get<double>(), 1.0, 1e-12);
  expect_error({"analyze", "--tf", "exp(-s*0.0025)/(z - 0.5)", "--ts", "0.001"}, "not a whole number of samples");
  // ZOH of 30/(s + 30) behind 2.5 ms at 1 ms: the modified z-transform, d = 2, m = 0.5:
  // 30 z^-2 [(1 - e^{-a m T}) z + (e^{-a m T} - e^{-a T})] / (a z (z - e^{-a T})), a = 30.
  const json c = run_json({"analyze", "--tf", "30*exp(-s*0.0025)/(s + 30)", "--c2d", "zoh", "--ts", "0.001"});
  const auto num = c["discrete"]["num"].get<std::vector<double>>(), den = c["discrete"]["den"].get<std::vector<double>>();
  const double a = 30.0, T = 0.001, em = std::exp(-a * 0.5 * T), e1 = std::exp(-a * T);
  const std::complex<double> zz(0.4, 0.7);
  auto poly = [](const std::vector<double>& d, std::complex<double> x) {
    std::complex<double> v = 0.0;
    for (double k : d) v = v * x + k;
    return v;
  };
  const std::complex<double> want = std::pow(zz, -2) * ((1.0 - em) * zz + (em - e1)) / (zz * (zz - e1));
  // Coefficients printed to 17 digits: 1e-12 relative.
  EXPECT_NEAR(std::abs(poly(num, zz) / poly(den, zz) - want), 0.0, 1e-12 * std::abs(want));
  expect_error({"analyze", "--tf", "30*exp(-s*0.0025)/(s + 30)", "--c2d", "tustin", "--ts", "0.001"},
               "--c2d zoh discretises any delay exactly");
  expect_error({"analyze", "--tf", "1/(s + 1)", "--pade", "4"}, "--pade applies to a delay");
  expect_error({"analyze", "--tf", "exp(-s*0.1)/(s + 1)", "--pade", "x"}, "expected an order 0..20");
}

TEST_F(AnalyzeSampled, MinrealCancelsPairsWithinItsTolerance) {
  const std::vector<std::string> tf{"analyze", "--tf", "(s + 1.0001)/((s + 1)*(s + 5))"};
  const json kept = run_json(tf);
  EXPECT_EQ(kept["order"].get<int>(), 2);  // 1e-4 apart: more than the 1e-7 that cancels by itself
  std::vector<std::string> loose = tf;
  loose.insert(loose.end(), {"--minreal", "1e-3"});
  const json cut = run_json(loose);
  EXPECT_EQ(cut["order"].get<int>(), 1);
  ASSERT_EQ(cut["minreal"]["cancelled"].size(), 1u);
  EXPECT_NEAR(cut["minreal"]["cancelled"][0][0].get<double>(), -1.0, 1e-12);
  EXPECT_NEAR(cut["dc_gain"].get<double>(), 1.0001 / 5.0, 1e-12);
  std::vector<std::string> tight = tf;
  tight.insert(tight.end(), {"--minreal", "1e-5"});
  EXPECT_EQ(run_json(tight)["order"].get<int>(), 2);
  expect_error({"analyze", "--tf", "1/(s+1)", "--minreal", "-1"}, "relative tolerance");
}

TEST_F(AnalyzeSampled, ASampledLoopIsReportedAndItsSweepListsEveryVerdict) {
  const json j = run_json({"analyze", kSampled + "motor_loop.yaml", "--loop-at", "C.out"});
  ASSERT_EQ(j["sampled_plants"].size(), 1u);
  EXPECT_EQ(j["sampled_plants"][0]["block"], "plant");
  EXPECT_DOUBLE_EQ(j["sampled_plants"][0]["input_delays_s"][0].get<double>(), 0.0004);
  EXPECT_FALSE(j["continuous"].get<bool>());
  const Result r = run({"analyze", kSampled + "motor_loop.yaml", "--from", "q_d", "--to", "q", "--sweep", "P=10:2000:4:log"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("sampled plant 'plant': zero-order hold and sampler at 0.001 s, exact"), std::string::npos) << r.out;
  int lines = 0, unstable = 0;
  for (size_t p = r.out.find("\n  P = "); p != std::string::npos; p = r.out.find("\n  P = ", p + 1)) {
    ++lines;
    unstable += r.out.compare(r.out.find(": ", p) + 2, 8, "unstable") == 0;
  }
  EXPECT_EQ(lines, 4);
  EXPECT_GE(unstable, 1) << r.out;  // P = 2000 is far past the loop's gain margin
  EXPECT_NE(r.out.find("  P = 10: stable"), std::string::npos) << r.out;
}

TEST_F(AnalyzeSampled, CodeGenerationRefusesASampledPlant) {
  fs::create_directories(dir_ / "gen");
  expect_error({"codegen", kSampled + "motor_loop.yaml", "--rate", "1000", "--out", (dir_ / "gen").string()}, "sampled plant");
}

}  // namespace
