// The balance experiment's pendulum verdict on a push (metrics pushes[i].lipm,
// sim/src/push_capture.hpp) on a synthetic log whose phases follow the phase machine's
// default durations (double support 0–0.01 s, lift to 0.04 s, swing to 0.37 s, the
// left foot swinging from the right foot at the origin): the capture intervals are
// worked out here by hand (Koolen's d_∞ for the sagittal steps, the alternating lateral
// steps solved in closed form), independently of wholebody/capture.cpp, and the CoM
// placed 1 mm inside or outside them. Tolerance: 1e-12 m on the reported intervals.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "dmbd/base/error.hpp"
#include "dmbd/control/balance_controller.hpp"
#include "dmbd/experiments/experiment.hpp"
#include "dmbd/scenario/evaluate.hpp"
#include "dmbd/scenario/scenario.hpp"
#include "dmbd/scenario/scenario.hpp"

#include "push_log.hpp"

namespace {

using namespace push_log;

dmbd::scenario::Scenario scenario() {
  dmbd::scenario::Scenario s;
  s.file = "push.yaml";
  s.experiment.type = "balance";
  s.experiment.number = {{"start_s", 0.0}};
  s.variants.resize(1);
  s.variants[0].name = "v";
  s.variants[0].duration_s = 1.0;  // the log stops at 0.6 s
  dmbd::control::BalanceSetup b;
  b.tvr.com_height_m = kHeight;
  b.tvr.gravity_m_s2 = kG;
  s.variants[0].bus_controllers.push_back(std::make_shared<dmbd::control::BalanceSetup>(b));
  for (double end : {kEndA, kEndB, 0.9}) {  // the last ends after the run
    dmbd::sim::ForceSpec f;
    f.link = "torso";
    f.direction_W = Eigen::Vector3d(0.6, 0.8, 0.0);
    f.source.kind = dmbd::sim::Source::Kind::Steps;
    f.source.steps = {{end - 0.004, 100.0}, {end, 0.0}};
    s.variants[0].forces.push_back(f);
  }
  return s;
}

const nlohmann::json& pushes(const dmbd::experiments::ExperimentResult& res) { return res.metrics.at("balance").at("v").at("pushes"); }

void expect_interval(const nlohmann::json& j, const Interval& i, const char* what) {
  EXPECT_NEAR(j.at(0).get<double>(), i.lo, 1e-12) << what;
  EXPECT_NEAR(j.at(1).get<double>(), i.hi, 1e-12) << what;
}

TEST(SimPushCapture, AFreeStepInDoubleSupportAndAFixedOneLateInTheSwing) {
  const auto res = dmbd::scenario::evaluate_experiment(scenario(), {log(false)});
  const auto& p = pushes(res);
  ASSERT_EQ(p.size(), 3u);
  const auto& a = p[0].at("lipm");
  EXPECT_TRUE(a.at("capturable").get<bool>());
  EXPECT_NEAR(a.at("margin_m").get<double>(), 1e-3, 1e-9);  // x 1 mm inside, y mid-way
  EXPECT_FALSE(a.at("foothold_fixed").get<bool>());
  EXPECT_NEAR(a.at("time_to_touch_down_s").get<double>(), 0.365, 1e-9);
  expect_interval(a.at("interval_x_m"), kAx, "A, x");
  expect_interval(a.at("interval_y_m"), kAy, "A, y");
  const auto& b = p[1].at("lipm");
  EXPECT_FALSE(b.at("capturable").get<bool>());  // 1 mm beyond the fixed foothold's reach
  EXPECT_NEAR(b.at("margin_m").get<double>(), -1e-3, 1e-9);
  EXPECT_TRUE(b.at("foothold_fixed").get<bool>());
  EXPECT_NEAR(b.at("time_to_touch_down_s").get<double>(), 0.07, 1e-9);
  expect_interval(b.at("interval_x_m"), kBx, "B, x");
  expect_interval(b.at("interval_y_m"), kBy, "B, y");
  EXPECT_TRUE(p[2].at("lipm").at("capturable").is_null());  // after the log's end
}

TEST(SimPushCapture, OneMillimetreOutsideIsNotCapturable) {
  const auto res = dmbd::scenario::evaluate_experiment(scenario(), {log(true)});
  EXPECT_FALSE(pushes(res)[0].at("lipm").at("capturable").get<bool>());
}

TEST(SimPushCapture, TheShiftOfThePushItself) {
  // 100 N for 4 ms along (0.6, 0.8, 0): all of it horizontal.
  const auto res = dmbd::scenario::evaluate_experiment(scenario(), {log(false)});
  const double expected = 100.0 / (kMass * kOmega * kOmega) * (std::exp(kOmega * 0.004) - 1.0);
  EXPECT_NEAR(pushes(res)[0].at("lipm").at("push_cp_shift_m").get<double>(), expected, 1e-9);
}

// A push ending 0.10 s into the run, 0.06 s into the swing (before the mid-swing
// replan: the foothold is free), 0.27 s before touch-down, with the swing foot's limits
// 0.5 m/s and 5 m/s²: the foot at rest at (−0.05, 0.25) can still land within 0.085 m
// of where it is (0.1 s up to 0.5 m/s, 0.07 s at it, 0.1 s down), so the step's ranges
// shrink to x in [−0.135, 0.035] and y in [0.20, 0.335] (the lateral limit's 0.20 m
// inside the reach's 0.165), and the intervals with them.
dmbd::scenario::Scenario scenario_with_reach(double speed, double accel) {
  dmbd::scenario::Scenario s = scenario();
  s.variants[0].forces.resize(1);
  s.variants[0].forces[0].source.steps = {{0.096, 100.0}, {0.100, 0.0}};
  s.experiment.number["swing_speed_max_m_s"] = speed;
  s.experiment.number["swing_accel_max_m_s2"] = accel;
  return s;
}

TEST(SimPushCapture, TheSwingFootsReachNarrowsAFreeStep) {
  const auto res = dmbd::scenario::evaluate_experiment(scenario_with_reach(0.5, 5.0), {log(false)});
  const auto& l = pushes(res).at(0).at("lipm");
  EXPECT_FALSE(l.at("foothold_fixed").get<bool>());
  EXPECT_NEAR(l.at("time_to_touch_down_s").get<double>(), 0.27, 1e-9);
  EXPECT_TRUE(l.at("reachable").get<bool>());
  expect_interval(l.at("reach_x_m"), {-0.135, 0.035}, "reach x");
  expect_interval(l.at("reach_y_m"), {0.165, 0.335}, "reach y");
  expect_interval(l.at("interval_x_m"), sagittal(0.27, -0.135, 0.035), "x within reach");
  expect_interval(l.at("interval_y_m"), lateral(0.27, 0.20, 0.335), "y within reach");
  // ξ sits 1 mm inside the unlimited interval's top at 0.365 s, far beyond the reach's.
  EXPECT_FALSE(l.at("capturable").get<bool>());
  // Without the limits the same push is judged on the whole step range.
  dmbd::scenario::Scenario unlimited = scenario_with_reach(0.5, 5.0);
  unlimited.experiment.number.erase("swing_speed_max_m_s");
  unlimited.experiment.number.erase("swing_accel_max_m_s2");
  const auto unlimited_res = dmbd::scenario::evaluate_experiment(unlimited, {log(false)});
  const auto& u = pushes(unlimited_res).at(0).at("lipm");
  EXPECT_FALSE(u.contains("reachable"));
  expect_interval(u.at("interval_x_m"), sagittal(0.27, -0.4, 0.4), "x, no reach");
}

TEST(SimPushCapture, AFootThatCannotReachAnyAllowedFootholdIsNotCapturable) {
  // The foot at y = 0.10 with 0.05 m/s at most: it lands within 0.013 m of it, short of
  // the 0.20 m the lateral limit asks.
  const auto res = dmbd::scenario::evaluate_experiment(scenario_with_reach(0.05, 5.0), {log(false, 0.10)});
  const auto& l = pushes(res).at(0).at("lipm");
  EXPECT_FALSE(l.at("reachable").get<bool>());
  EXPECT_FALSE(l.at("capturable").get<bool>());
  EXPECT_TRUE(l.at("interval_y_m").is_null());
  // Only one of the two limits is a located mistake of the scenario.
  dmbd::scenario::Scenario half = scenario_with_reach(0.5, 5.0);
  half.experiment.number.erase("swing_accel_max_m_s2");
  EXPECT_THROW(dmbd::scenario::evaluate_experiment(half, {log(false)}), dmbd::InputError);
}

}  // namespace
