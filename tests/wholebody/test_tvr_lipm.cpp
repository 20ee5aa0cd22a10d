// The TVR planner (wholebody/tvr.hpp) in the linear inverted pendulum itself: the closed
// switching state against an RK4 integration of ẍ = ω²(x − p); the CoM's velocity,
// switched onto the planned foothold with κ = 0, reverses exactly t′ after touch-down
// (closed form and integrated); κ turns the CoM toward x_des and makes the step-to-step
// map contract (with κ = 0 a position offset persists). Worst errors are recorded as
// test properties (--gtest_output=xml).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include "dmbd/wholebody/tvr.hpp"
#include "recorded_error.hpp"

namespace dmbd::wholebody::testing {
namespace {

const double kOmega = std::sqrt(9.81 / 1.0);

// RK4 of ẍ = ω²(x − p) over t_s in `steps` equal steps.
LipmAxisState rk4(LipmAxisState s, double foot_m, double t_s, int steps) {
  const double dt = t_s / steps, w2 = kOmega * kOmega;
  auto accel = [&](double x) { return w2 * (x - foot_m); };
  for (int k = 0; k < steps; ++k) {
    const double x = s.position_m, v = s.velocity_m_s;
    const double k1x = v, k1v = accel(x);
    const double k2x = v + 0.5 * dt * k1v, k2v = accel(x + 0.5 * dt * k1x);
    const double k3x = v + 0.5 * dt * k2v, k3v = accel(x + 0.5 * dt * k2x);
    const double k4x = v + dt * k3v, k4v = accel(x + dt * k3x);
    s.position_m += dt / 6.0 * (k1x + 2 * k2x + 2 * k3x + k4x);
    s.velocity_m_s += dt / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v);
  }
  return s;
}

struct Case {
  double x0_m, v0_m_s, foot_m, t_s;
};
// Moving away from the foot, toward it (turning before T or not), at rest off it, on it.
const std::array<Case, 6> kCases{{{0.05, 0.30, 0.0, 0.33},
                                  {-0.12, 0.45, 0.10, 0.40},
                                  {0.20, -0.25, -0.10, 0.165},
                                  {0.03, -0.50, 0.10, 0.30},
                                  {0.30, 0.0, 0.25, 0.25},
                                  {1.10, 0.80, 1.10, 0.50}}};

// The state's size for relative errors: |x − p| + |ẋ|/ω (1 mm floor).
double scale(const LipmAxisState& s, double foot_m) {
  return std::max(std::abs(s.position_m - foot_m) + std::abs(s.velocity_m_s) / kOmega, 1e-3);
}

// Closed form vs RK4 with 20000 steps (truncation ~(ωΔt)⁴ ≈ 1e-18 per step; rounding
// over 20000 steps ~1e-12): 1e-9 relative to the state's size.
TEST(TvrLipm, SwitchingStateMatchesRk4) {
  double worst = 0;
  for (const Case& c : kCases) {
    const LipmAxisState closed = lipm_state_after(c.x0_m, c.v0_m_s, c.foot_m, kOmega, c.t_s);
    const LipmAxisState num = rk4({c.x0_m, c.v0_m_s}, c.foot_m, c.t_s, 20000);
    const double err = (std::abs(closed.position_m - num.position_m) +
                        std::abs(closed.velocity_m_s - num.velocity_m_s) / kOmega) /
                       scale(num, c.foot_m);
    EXPECT_LT(err, 1e-9) << "x0 " << c.x0_m << " v0 " << c.v0_m_s;
    worst = std::max(worst, err);
  }
  RecordProperty("worst_relative_error", text(worst));
}

// The planner's switching state is that closed form, per axis (1e-15 relative: the same
// arithmetic).
TEST(TvrLipm, PlannerSwitchingStateIsTheClosedForm) {
  TvrPlanner planner;
  TvrInput in;
  in.com_m = {0.05, -0.12};
  in.com_velocity_m_s = {0.30, 0.45};
  in.stance_foot_m = {0.0, -0.10};
  in.time_to_switch_s = 0.33;
  const TvrPlan plan = planner.plan(in);
  ASSERT_EQ(plan.time_scale, 1.0);
  for (int i = 0; i < 2; ++i) {
    const LipmAxisState s = lipm_state_after(in.com_m[i], in.com_velocity_m_s[i], in.stance_foot_m[i], kOmega, 0.33);
    EXPECT_NEAR(plan.switching_com_m[i], s.position_m, 1e-15);
    EXPECT_NEAR(plan.switching_com_velocity_m_s[i], s.velocity_m_s, 1e-15);
  }
}

// κ = 0: ẋ(t′) = ẋ_s [cosh ωt′ − coth(ωt′) sinh ωt′] = 0; evaluated, the rounding of
// the exponentials leaves ≤ 1e-12 relative to ẋ_s.
TEST(TvrLipm, VelocityReversesTPrimeAfterTouchDownClosedForm) {
  double worst = 0;
  for (const Case& c : kCases) {
    const LipmAxisState s = lipm_state_after(c.x0_m, c.v0_m_s, c.foot_m, kOmega, c.t_s);
    if (s.velocity_m_s == 0.0) continue;
    for (double t_prime : {0.20, 0.21, 0.35}) {
      const double p = reversal_foothold(s.position_m, s.velocity_m_s, kOmega, t_prime, 0.0, 0.0);
      const double v = lipm_state_after(s.position_m, s.velocity_m_s, p, kOmega, t_prime).velocity_m_s;
      const double rel = std::abs(v / s.velocity_m_s);
      EXPECT_LT(rel, 1e-12) << "t' " << t_prime;
      worst = std::max(worst, rel);
    }
  }
  RecordProperty("worst_relative_velocity_at_t_prime", text(worst));
}

// The whole step integrated: RK4 over the stance foot for T, the planner's foothold
// (κ = 0, no step limit active), RK4 over it for t′ (20000 steps each). At t′ the
// velocity is ≤ 1e-9 of ẋ_s; the reversal time t′ − ẋ/ẍ (one Newton step) is within
// 1e-9 s of t′; the velocity has opposite signs 1 ms before and after.
TEST(TvrLipm, VelocityReversesTPrimeAfterTouchDownIntegrated) {
  TvrParams params;
  params.kappa = {0.0, 0.0};
  const TvrPlanner planner(params);
  TvrInput in;
  in.com_m = {0.02, -0.11};
  in.com_velocity_m_s = {0.25, 0.25};
  in.stance_foot_m = {0.0, -0.12};
  in.swing = Side::Left;
  in.time_to_switch_s = 0.33;
  const TvrPlan plan = planner.plan(in);
  ASSERT_FALSE(plan.clamped_x || plan.clamped_y);
  ASSERT_EQ(plan.time_scale, 1.0);
  double worst_v = 0, worst_t = 0;
  for (int i = 0; i < 2; ++i) {
    const double t_prime = params.t_prime_s[i], p = plan.foothold_m[i];
    const LipmAxisState s = rk4({in.com_m[i], in.com_velocity_m_s[i]}, in.stance_foot_m[i], 0.33, 20000);
    const LipmAxisState at = rk4(s, p, t_prime, 20000);
    const double accel = kOmega * kOmega * (at.position_m - p);
    const double t_reverse = t_prime - at.velocity_m_s / accel;
    const double rel_v = std::abs(at.velocity_m_s / s.velocity_m_s);
    EXPECT_LT(rel_v, 1e-9) << "axis " << i;
    EXPECT_NEAR(t_reverse, t_prime, 1e-9) << "axis " << i;
    const double before = rk4(s, p, t_prime - 1e-3, 20000).velocity_m_s;
    const double after = rk4(s, p, t_prime + 1e-3, 20000).velocity_m_s;
    EXPECT_LT(before * after, 0.0) << "axis " << i;
    EXPECT_GT(before * s.velocity_m_s, 0.0) << "axis " << i;  // still moving the old way before t′
    worst_v = std::max(worst_v, rel_v);
    worst_t = std::max(worst_t, std::abs(t_reverse - t_prime));
  }
  RecordProperty("worst_relative_velocity_at_t_prime", text(worst_v));
  RecordProperty("worst_reversal_time_error_s", text(worst_t));
}

// κ ≠ 0: t′ after touch-down ẋ(t′) = −ω κ (x_des − x_s) sinh(ωt′), which for κ < 0 has
// the sign of x_des − x_s (the CoM is moving toward x_des). Against RK4 to 1e-9 m/s.
TEST(TvrLipm, KappaTurnsTheComTowardTheDesiredPosition) {
  double worst = 0;
  for (double x_des : {-0.3, 0.25}) {
    for (double kappa : {-0.08, -0.13}) {
      const double xs = 0.1, vs = 0.4, t_prime = 0.21;
      const double p = reversal_foothold(xs, vs, kOmega, t_prime, kappa, x_des);
      const LipmAxisState at = rk4({xs, vs}, p, t_prime, 20000);
      const double expected = -kOmega * kappa * (x_des - xs) * std::sinh(kOmega * t_prime);
      EXPECT_NEAR(at.velocity_m_s, expected, 1e-9);
      EXPECT_GT(at.velocity_m_s * (x_des - xs), 0.0) << "x_des " << x_des << " kappa " << kappa;
      worst = std::max(worst, std::abs(at.velocity_m_s - expected));
    }
  }
  RecordProperty("worst_velocity_error_m_s", text(worst));
}

// One step of stepping in the LIPM, per axis: from the switching state (x_s, ẋ_s) onto
// p′ (no limits) for a step of `step_s`, to the next switching state.
LipmAxisState next_switching_state(const LipmAxisState& s, double kappa, double t_prime, double x_des, double step_s) {
  const double p = reversal_foothold(s.position_m, s.velocity_m_s, kOmega, t_prime, kappa, x_des);
  return lipm_state_after(s.position_m, s.velocity_m_s, p, kOmega, step_s);
}

// The step-to-step map of (x_s − x_des, ẋ_s) is linear; its matrix by columns.
Eigen::Matrix2d step_map(double kappa, double t_prime, double step_s) {
  Eigen::Matrix2d m;
  const LipmAxisState e1 = next_switching_state({1.0, 0.0}, kappa, t_prime, 0.0, step_s);
  const LipmAxisState e2 = next_switching_state({0.0, 1.0}, kappa, t_prime, 0.0, step_s);
  m << e1.position_m, e2.position_m, e1.velocity_m_s, e2.velocity_m_s;
  return m;
}

// A step of 0.38 s (DS 0.01 + lift 0.03 + swing 0.33 + landing 0.01). With κ = 0 the
// map has the eigenvalue 1 for a pure position offset (1e-12: nothing pulls the CoM
// back); with the facts' κ its spectral radius is below 1 (0.93 for x, 0.89 for y), and
// 40 steps from an offset of 0.1 m leave less than a tenth of it, where κ = 0 leaves it.
TEST(TvrLipm, KappaMakesTheStepToStepMapContract) {
  const double step_s = 0.38;
  const std::array<double, 2> t_prime{0.21, 0.20}, kappa{-0.08, -0.13};
  for (int i = 0; i < 2; ++i) {
    const Eigen::Matrix2d neutral = step_map(0.0, t_prime[i], step_s);
    EXPECT_NEAR(neutral(0, 0), 1.0, 1e-12);
    EXPECT_NEAR(neutral(1, 0), 0.0, 1e-12);
    const double radius = step_map(kappa[i], t_prime[i], step_s).eigenvalues().cwiseAbs().maxCoeff();
    EXPECT_LT(radius, 0.95) << "axis " << i;
    RecordProperty("spectral_radius_axis_" + std::to_string(i), text(radius));
    LipmAxisState pulled{0.1, 0.0}, free{0.1, 0.0};
    for (int k = 0; k < 40; ++k) {
      pulled = next_switching_state(pulled, kappa[i], t_prime[i], 0.0, step_s);
      free = next_switching_state(free, 0.0, t_prime[i], 0.0, step_s);
    }
    const double left = std::abs(pulled.position_m) + std::abs(pulled.velocity_m_s) / kOmega;
    EXPECT_LT(left, 0.01) << "axis " << i;
    RecordProperty("offset_left_after_40_steps_m_axis_" + std::to_string(i), text(left));
    EXPECT_NEAR(free.position_m, 0.1, 1e-9) << "axis " << i;
  }
}

}  // namespace
}  // namespace dmbd::wholebody::testing
