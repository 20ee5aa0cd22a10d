// The shipped operational-space-control scenarios (paper Sec. IV-A, Fig. 6), whole:
// osc_table.yaml (the paper's and the authors' paths, with and without the disturbance
// observer, on the robot's output damping), osc_table_amplitude.yaml (the paper's 1.4 Hz path, amplitude swept, on Table I's) and
// osc_table_damping.yaml (the robot's output damping swept).
// What is asserted is what docs/experiments.md reports: the authors' path is followed
// within issue 14's figures with the DOB, the DOB lowers every joint's torque error, the
// paper's 0.3 m at 1.4 Hz is followed within Fig. 6's figures on the robot's output
// damping, and on Table I's it is beyond the hip pitch actuator's current (the largest
// amplitude followed within the limits there is 0.15 m).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "dmbd/scenario/run_directory.hpp"
#include "sim_test_support.hpp"

namespace dmbd::scenario {
using namespace dmbd::sim;          // NOLINT: the engine's names in these tests
using namespace dmbd::control;      // NOLINT
using namespace dmbd::experiments;  // NOLINT
namespace {

using dmbd::sim::test::TempDir;

ScenarioRun run_shipped(const TempDir& dir, const std::string& name) {
  return run_scenario(load_scenario(std::string(DMBD_SOURCE_DIR) + "/examples/scenarios/" + name + ".yaml"), dir.file("out"));
}

double rms(const nlohmann::json& m, const char* axis) { return m["ankle_rms_error_m"][axis].get<double>(); }

void print(const std::string& name, const nlohmann::json& m) {
  std::printf("%-12s ankle RMS x %.2f y %.2f z %.2f mm, max %.1f mm, saturated %.3f, tick median %.1f us\n", name.c_str(),
              1e3 * rms(m, "x"), 1e3 * rms(m, "y"), 1e3 * rms(m, "z"), 1e3 * m["ankle_max_error_m"].get<double>(),
              m["current_saturation_fraction"].get<double>(), m["osc_tick_us"]["median"].get<double>());
}

// Issue 14's figures, on the path the leg can follow: the ankle within 5 % of the
// forward amplitude (7.5 mm of 0.15 m) and 5 mm laterally and vertically; each joint's
// torque error within 10 % of its peak command, or, for a command that peaks below 2 N m,
// within the sensed force's noise floor of about 0.05-0.2 N m (0.2 N m: there the ratio
// says nothing; `torques`: at small amplitudes every joint but the hip pitch and knee is
// down there); no current at its limit.
void expect_followed(const nlohmann::json& m, double amplitude_m, bool torques = true) {
  EXPECT_LE(rms(m, "x"), 0.05 * amplitude_m);
  EXPECT_LE(rms(m, "y"), 5e-3);
  EXPECT_LE(rms(m, "z"), 5e-3);
  EXPECT_EQ(m["current_saturation_fraction"].get<double>(), 0.0);
  if (!torques) return;
  for (const auto& [joint, err] : m["torque_rms_error_Nm"].items())
    EXPECT_LE(err.get<double>(), std::max(0.1 * m["torque_peak_Nm"][joint].get<double>(), 0.2)) << joint;
}

TEST(OscShippedScenarios, TableTestFollowsTheAuthorsPathAndTheDobLowersEveryTorqueError) {
  TempDir dir;
  const auto r = run_shipped(dir, "osc_table");
  const auto& osc = r.metrics["osc"];
  for (const char* v : {"paper_dob", "paper_pd", "authors_dob", "authors_pd"}) {
    ASSERT_TRUE(osc.contains(v)) << v;
    print(v, osc[v]);
  }
  expect_followed(osc["authors_dob"], 0.15);
  for (const char* path : {"paper", "authors"}) {
    const auto& dob = osc[std::string(path) + "_dob"]["torque_rms_error_Nm"];
    const auto& pd = osc[std::string(path) + "_pd"]["torque_rms_error_Nm"];
    ASSERT_EQ(dob.size(), 5u);  // the moving leg's five joints
    for (const auto& [joint, err] : dob.items()) EXPECT_LT(err.get<double>(), pd[joint].get<double>()) << path << " " << joint;
  }
  // Fig. 6 on the robot's output damping (the actuator file's load set `robot`): the
  // paper's 0.3 m at 1.4 Hz followed within 15 mm forward and 5 mm laterally and
  // vertically, no current at its limit (measured 4.1 / 4.4 / 2.0 mm; on Table I's
  // damping the hip pitch's current saturated in 66 % of the window).
  expect_followed(osc["paper_dob"], 0.3);
  for (const auto& run : r.runs) EXPECT_GT(run.real_time_factor, 1.0) << run.name;
}

TEST(OscShippedScenarios, TheLargestAmplitudeFollowedAt1p4HzIs0p15m) {
  TempDir dir;
  const auto r = run_shipped(dir, "osc_table_amplitude");
  const auto& osc = r.metrics["osc"];
  for (const auto& [name, m] : osc.items()) print(name, m);
  for (const char* a : {"0.05m", "0.10m", "0.15m"}) {
    SCOPED_TRACE(a);
    expect_followed(osc[a], std::stod(a), std::string(a) == "0.15m");
  }
  for (const char* a : {"0.175m", "0.20m", "0.25m", "0.30m"}) EXPECT_GT(osc[a]["current_saturation_fraction"].get<double>(), 0.0) << a;
}

// osc_table_damping.yaml (every joint's B_l at s times its file value): Fig. 6's figures
// hold at s = 0.2 and 0.25 and fail at 0.3 (a current at its limit) and at 1 (Table I's
// value); at s = 0.2 the run is osc_table.yaml's paper_dob (on the load set `robot`,
// 0.2 times the stand's) bit for bit, and the OSC's feedforward reads the plant's own B_l.
TEST(OscShippedScenarios, TheDampingSweepHoldsFig6UpToAQuarterOfTableIsBlAndTheTableRunsAtAFifth) {
  TempDir dir;
  const std::string examples = std::string(DMBD_SOURCE_DIR) + "/examples/scenarios/";
  Scenario s = load_scenario(examples + "osc_table_damping.yaml");
  auto keep = [](Scenario& x, const std::vector<std::string>& names) {
    std::vector<VariantSetup> kept;
    for (const auto& n : names)
      for (const auto& v : x.variants)
        if (v.name == n) kept.push_back(v);
    ASSERT_EQ(kept.size(), names.size());
    x.variants = kept;
  };
  keep(s, {"s0.2/paper_dob", "s0.25/paper_dob", "s0.3/paper_dob", "s1/paper_dob"});
  const ScenarioRun r = run_scenario(s, dir.file("sweep"));
  for (const auto& [name, m] : r.metrics["osc"].items()) print(name, m);
  const auto& line = r.metrics["sweeps"]["damping_fig6"]["lines"]["paper_dob"];
  EXPECT_EQ(line["holds"], (std::vector<bool>{true, true, false, false})) << line.dump();
  EXPECT_GT(r.metrics["osc"]["s0.3/paper_dob"]["current_saturation_fraction"].get<double>(), 0.0);
  Scenario table = load_scenario(examples + "osc_table.yaml");
  keep(table, {"paper_dob"});
  const ScenarioRun t = run_scenario(table, dir.file("table"));
  const Log& a = r.runs[0].log;
  const Log& b = t.runs[0].log;
  ASSERT_EQ(a.columns(), b.columns());
  for (int k = 0; k < static_cast<int>(a.columns()); ++k) {
    ASSERT_EQ(a.name(k), b.name(k));
    EXPECT_EQ(a.column(k), b.column(k)) << a.name(k);
  }
}

}  // namespace
}  // namespace dmbd::scenario
