// The TVR planner's plan (wholebody/tvr.hpp): a hand-computed case, κ's pull toward
// x_des, each step limit for either swing side, the orbital-energy sanity check, the
// switching-speed rule, and its parameter checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "dmbd/base/error.hpp"
#include "dmbd/wholebody/tvr.hpp"
#include "recorded_error.hpp"

namespace dmbd::wholebody::testing {
namespace {

const double kOmega = std::sqrt(9.81);

TvrParams no_kappa() {
  TvrParams p;
  p.kappa = {0.0, 0.0};
  return p;
}

TvrInput input(Eigen::Vector2d com, Eigen::Vector2d velocity, Eigen::Vector2d stance, Side swing, double t_s) {
  TvrInput in;
  in.com_m = com;
  in.com_velocity_m_s = velocity;
  in.stance_foot_m = stance;
  in.com_desired_m = com;
  in.swing = swing;
  in.time_to_switch_s = t_s;
  return in;
}

// A CoM over the stance foot moving at v: x_s = p + (v/ω) sinh ωT, ẋ_s = v cosh ωT and
// p′ = x_s + (ẋ_s/ω) coth ωt′ + κ (x_des − x_s), written in hyperbolic functions
// (the planner uses exponentials): 1e-12 m.
TEST(TvrPlanner, HandComputedCase) {
  const TvrPlanner planner;
  TvrInput in = input({0.0, -0.10}, {0.2, 0.3}, {0.0, -0.10}, Side::Left, 0.33);
  in.com_desired_m = {0.05, 0.0};
  const TvrPlan plan = planner.plan(in);
  ASSERT_EQ(plan.time_scale, 1.0);
  const Eigen::Vector2d t_prime(0.21, 0.20), kappa(-0.08, -0.13);
  double worst = 0;
  for (int i = 0; i < 2; ++i) {
    const double v = in.com_velocity_m_s[i], p = in.stance_foot_m[i];
    const double xs = p + v / kOmega * std::sinh(kOmega * 0.33), vs = v * std::cosh(kOmega * 0.33);
    const double foot = xs + vs / kOmega * std::cosh(kOmega * t_prime[i]) / std::sinh(kOmega * t_prime[i]) +
                        kappa[i] * (in.com_desired_m[i] - xs);
    EXPECT_NEAR(plan.switching_com_m[i], xs, 1e-12);
    EXPECT_NEAR(plan.switching_com_velocity_m_s[i], vs, 1e-12);
    EXPECT_NEAR(plan.foothold_unclamped_m[i], foot, 1e-12);
    worst = std::max({worst, std::abs(plan.switching_com_m[i] - xs), std::abs(plan.switching_com_velocity_m_s[i] - vs),
                      std::abs(plan.foothold_unclamped_m[i] - foot)});
  }
  RecordProperty("worst_error", text(worst));
  EXPECT_FALSE(plan.clamped_x || plan.clamped_y);
  EXPECT_EQ(plan.foothold_m, plan.foothold_unclamped_m);
  EXPECT_NEAR(planner.omega_per_s(), kOmega, 1e-15);
}

// κ adds exactly κ (x_des − x_s) to the foothold (1e-12 m): for κ < 0 the foot moves
// away from x_des, so the CoM, turning over it, heads back toward x_des (the LIPM
// consequence is checked in test_tvr_lipm.cpp).
TEST(TvrPlanner, KappaShiftsTheFootholdAwayFromTheDesiredPosition) {
  const TvrPlanner with;
  const TvrPlanner without(no_kappa());
  TvrInput in = input({0.0, -0.05}, {0.1, 0.25}, {0.0, -0.15}, Side::Left, 0.3);
  in.com_desired_m = {-0.2, 0.3};
  const TvrPlan a = with.plan(in), b = without.plan(in);
  for (int i = 0; i < 2; ++i) {
    const double error = in.com_desired_m[i] - a.switching_com_m[i];
    EXPECT_NEAR(a.foothold_unclamped_m[i] - b.foothold_unclamped_m[i], with.params().kappa[i] * error, 1e-12);
    EXPECT_LT((a.foothold_unclamped_m[i] - b.foothold_unclamped_m[i]) * error, 0.0) << "axis " << i;
  }
}

// Forward limits: the unclamped foothold beyond ±0.4 m lands exactly on the limit
// (1e-12 m); the other axis is not touched.
TEST(TvrPlanner, ForwardStepLimits) {
  const TvrPlanner planner(no_kappa());
  double worst = 0;
  for (double v : {1.0, -1.0}) {
    const TvrInput in = input({0.3, -0.15}, {v, 0.3}, {0.3, -0.15}, Side::Left, 0.3);
    const TvrPlan plan = planner.plan(in);
    ASSERT_GT(std::abs(plan.foothold_unclamped_m.x() - 0.3), 0.4);
    EXPECT_TRUE(plan.clamped_x);
    EXPECT_NEAR(plan.foothold_m.x(), 0.3 + (v > 0 ? 0.4 : -0.4), 1e-12);
    worst = std::max(worst, std::abs(plan.foothold_m.x() - (0.3 + (v > 0 ? 0.4 : -0.4))));
    EXPECT_EQ(plan.foothold_m.y(), plan.foothold_unclamped_m.y());
    EXPECT_FALSE(plan.clamped_y);
  }
  RecordProperty("worst_error_m", text(worst));
}

// Lateral limits, towards the swing side: a left foot at y_stance + [0.20, 0.55], a
// right foot at y_stance − [0.55, 0.20]. The CoM over the stance foot: too narrow
// (moving away from the swing side, or at rest) and too wide (fast toward it), each
// side: on the limit, 1e-12 m.
TEST(TvrPlanner, LateralStepLimits) {
  const TvrPlanner planner(no_kappa());
  struct Case {
    Side swing;
    double stance_y, velocity_y, expected_offset;
  };
  const Case cases[] = {{Side::Left, -0.15, -0.1, 0.20},
                        {Side::Left, -0.15, 0.0, 0.20},
                        {Side::Left, -0.15, 1.0, 0.55},
                        {Side::Right, 0.15, 0.1, -0.20},
                        {Side::Right, 0.15, 0.0, -0.20},
                        {Side::Right, 0.15, -1.0, -0.55}};
  double worst = 0;
  for (const Case& c : cases) {
    const TvrInput in = input({0.0, c.stance_y}, {0.0, c.velocity_y}, {0.0, c.stance_y}, c.swing, 0.3);
    const TvrPlan plan = planner.plan(in);
    EXPECT_TRUE(plan.clamped_y) << "stance y " << c.stance_y << " velocity " << c.velocity_y;
    EXPECT_NEAR(plan.foothold_m.y(), c.stance_y + c.expected_offset, 1e-12)
        << "stance y " << c.stance_y << " velocity " << c.velocity_y;
    EXPECT_FALSE(plan.clamped_x);
    worst = std::max(worst, std::abs(plan.foothold_m.y() - (c.stance_y + c.expected_offset)));
  }
  RecordProperty("worst_error_m", text(worst));
}

// Inside the limits nothing is clamped, for either side (the foothold is p′ itself).
TEST(TvrPlanner, InsideTheLimitsNothingIsClamped) {
  const TvrPlanner planner(no_kappa());
  const TvrPlan left = planner.plan(input({0.0, -0.15}, {0.1, 0.3}, {0.0, -0.15}, Side::Left, 0.3));
  const TvrPlan right = planner.plan(input({0.0, 0.15}, {-0.1, -0.3}, {0.0, 0.15}, Side::Right, 0.3));
  for (const TvrPlan& plan : {left, right}) {
    EXPECT_FALSE(plan.clamped_x || plan.clamped_y);
    EXPECT_EQ(plan.foothold_m, plan.foothold_unclamped_m);
  }
  EXPECT_GT(left.foothold_m.y() + 0.15, 0.20);
  EXPECT_LT(right.foothold_m.y() - 0.15, -0.20);
}

// Orbital energy: a CoM moving away from the stance foot (E = ½ẋ² − ½ω²(x − p)² > 0
// over it) gets a foothold beyond the switching CoM in the direction of motion, far
// enough that the energy over the new foot is negative (the CoM turns back before
// reaching it). Both axes, both directions, inside the step limits; κ = 0 and the
// facts' κ with x_des = x₀.
TEST(TvrPlanner, OrbitalEnergySanity) {
  for (const TvrParams& params : {no_kappa(), TvrParams{}}) {
    const TvrPlanner planner(params);
    for (double dir : {1.0, -1.0}) {
      const Side swing = dir > 0 ? Side::Left : Side::Right;
      const TvrInput in = input({0.0, 0.0}, {dir * 0.2, dir * 0.2}, {-dir * 0.03, -dir * 0.03}, swing, 0.3);
      const TvrPlan plan = planner.plan(in);
      ASSERT_FALSE(plan.clamped_x || plan.clamped_y);  // the law itself, not a step limit
      for (int i = 0; i < 2; ++i) {
        const double x0 = in.com_m[i] - in.stance_foot_m[i], v0 = in.com_velocity_m_s[i];
        ASSERT_GT(0.5 * v0 * v0 - 0.5 * kOmega * kOmega * x0 * x0, 0.0);
        const double xs = plan.switching_com_m[i], vs = plan.switching_com_velocity_m_s[i];
        const double beyond = dir * (plan.foothold_m[i] - xs);
        EXPECT_GT(beyond, 0.0) << "axis " << i << " direction " << dir;
        EXPECT_GT(dir * (plan.foothold_m[i] - in.stance_foot_m[i]), 0.0);
        const double r = xs - plan.foothold_m[i];
        const double energy = 0.5 * vs * vs - 0.5 * kOmega * kOmega * r * r;
        EXPECT_LT(energy, 0.0) << "axis " << i << " direction " << dir;
      }
    }
  }
}

// The switching-speed rule: |ẋ_s| above 1.3 m/s on either axis plans with 0.9 T; the
// plan then equals a plan asked for at 0.9 T with the rule off (exactly: the same
// arithmetic); the scaling happens once even if the speed is still too high.
TEST(TvrPlanner, TooFastASwitchingSpeedShortensTheTimeOnce) {
  const TvrPlanner planner;
  TvrParams off_params;
  off_params.switching_speed_max_m_s = std::numeric_limits<double>::infinity();
  const TvrPlanner off(off_params);
  for (const Eigen::Vector2d& velocity : {Eigen::Vector2d(1.0, 0.1), Eigen::Vector2d(0.1, -1.0)}) {
    TvrInput in = input({0.0, 0.0}, velocity, {0.0, 0.0}, Side::Left, 0.3);
    const TvrPlan unscaled = off.plan(in);
    ASSERT_GT(unscaled.switching_com_velocity_m_s.cwiseAbs().maxCoeff(), 1.3);
    const TvrPlan plan = planner.plan(in);
    EXPECT_EQ(plan.time_scale, 0.9);
    EXPECT_NEAR(plan.time_to_switch_s, 0.27, 1e-15);
    in.time_to_switch_s = plan.time_to_switch_s;
    const TvrPlan direct = off.plan(in);
    EXPECT_EQ(plan.switching_com_m, direct.switching_com_m);
    EXPECT_EQ(plan.switching_com_velocity_m_s, direct.switching_com_velocity_m_s);
    EXPECT_EQ(plan.foothold_m, direct.foothold_m);
  }
  // Still above 1.3 m/s after the scaling: scaled once, not twice.
  const TvrPlan fast = planner.plan(input({0.0, 0.0}, {3.0, 0.0}, {0.0, 0.0}, Side::Left, 0.3));
  EXPECT_GT(std::abs(fast.switching_com_velocity_m_s.x()), 1.3);
  EXPECT_NEAR(fast.time_to_switch_s, 0.27, 1e-15);
}

// Below the minimum (0 by default, so never: a CoM at rest keeps T); with a minimum of
// 0.2 m/s a slow axis plans with 1.1 T; within the band T is kept.
TEST(TvrPlanner, TooSlowASwitchingSpeedLengthensTheTime) {
  const TvrPlanner defaults;
  const TvrPlan rest = defaults.plan(input({0.0, 0.0}, {0.0, 0.0}, {0.0, 0.0}, Side::Left, 0.3));
  EXPECT_EQ(rest.time_scale, 1.0);
  EXPECT_EQ(rest.time_to_switch_s, 0.3);
  TvrParams params;
  params.switching_speed_min_m_s = 0.2;
  const TvrPlanner planner(params);
  const TvrPlan slow = planner.plan(input({0.0, 0.0}, {0.05, 0.3}, {0.0, -0.1}, Side::Left, 0.3));
  EXPECT_EQ(slow.time_scale, 1.1);
  EXPECT_NEAR(slow.time_to_switch_s, 0.33, 1e-15);
  const TvrPlan within = planner.plan(input({0.0, 0.0}, {0.2, 0.3}, {0.0, -0.1}, Side::Left, 0.3));
  EXPECT_EQ(within.time_scale, 1.0);
}

// A negative time to switching counts as 0: the switching state is the current one.
TEST(TvrPlanner, NegativeTimeCountsAsZero) {
  const TvrPlanner planner;
  const TvrInput in = input({0.01, 0.02}, {0.3, -0.2}, {0.0, 0.1}, Side::Right, -0.05);
  const TvrPlan plan = planner.plan(in);
  EXPECT_EQ(plan.time_to_switch_s, 0.0);
  EXPECT_NEAR((plan.switching_com_m - in.com_m).norm(), 0.0, 1e-15);
  EXPECT_NEAR((plan.switching_com_velocity_m_s - in.com_velocity_m_s).norm(), 0.0, 1e-15);
}

TEST(TvrPlanner, RejectsParametersOutOfRange) {
  auto with = [](auto change) {
    TvrParams p;
    change(p);
    return p;
  };
  EXPECT_THROW(TvrPlanner(with([](TvrParams& p) { p.com_height_m = 0.0; })), InputError);
  EXPECT_THROW(TvrPlanner(with([](TvrParams& p) { p.gravity_m_s2 = -9.81; })), InputError);
  EXPECT_THROW(TvrPlanner(with([](TvrParams& p) { p.t_prime_s.y() = 0.0; })), InputError);
  EXPECT_THROW(TvrPlanner(with([](TvrParams& p) { p.kappa.x() = std::nan(""); })), InputError);
  EXPECT_THROW(TvrPlanner(with([](TvrParams& p) { p.step_x_min_m = 0.5; })), InputError);
  EXPECT_THROW(TvrPlanner(with([](TvrParams& p) { p.step_lateral_min_m = 0.6; })), InputError);
  EXPECT_THROW(TvrPlanner(with([](TvrParams& p) { p.switching_speed_min_m_s = 2.0; })), InputError);
  EXPECT_THROW(TvrPlanner(with([](TvrParams& p) { p.fast_time_scale = 0.0; })), InputError);
  EXPECT_NO_THROW(TvrPlanner(TvrParams{}));
}

}  // namespace
}  // namespace dmbd::wholebody::testing
