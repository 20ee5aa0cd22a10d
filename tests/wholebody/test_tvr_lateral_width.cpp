// The TVR planner's lateral width (tvr.hpp, TvrParams::lateral_width_m): the pendulum's
// period-2 orbit of stepping in place is a fixed point of the rule for any t′_y, and with
// t′_y = T the step-to-step map is deadbeat (every perturbation gone after two steps).
// The pendulum is stepped with its own closed form (lipm_state_after), planned at each
// switch (time to switching 0), so the only error is rounding: 1e-12 m and m/s.
#include <gtest/gtest.h>

#include <cmath>

#include "dmbd/base/error.hpp"
#include "dmbd/wholebody/tvr.hpp"

namespace dmbd::wholebody::testing {
namespace {

constexpr double kWidth = 0.26, kPeriod = 0.38, kHeight = 0.78;

TvrParams orbit_params(double t_prime_y, double kappa_y) {
  TvrParams p;
  p.com_height_m = kHeight;
  p.t_prime_s = {kPeriod, t_prime_y};
  p.kappa = {0.0, kappa_y};
  p.lateral_width_m = kWidth;
  p.step_period_s = kPeriod;
  p.switching_speed_max_m_s = std::numeric_limits<double>::infinity();
  return p;
}

// The lateral state at a switch: the CoM, its velocity, the stance foot and its side.
struct Switch {
  double y, vy, foot;
  Side swing;
};

// Plans the next foothold at the switch, then lets the pendulum run a period over it.
Switch step(const TvrPlanner& planner, const Switch& s) {
  TvrInput in;
  in.com_m = {0.0, s.y};
  in.com_velocity_m_s = {0.0, s.vy};
  in.stance_foot_m = {0.0, s.foot};
  in.swing = s.swing;
  const TvrPlan plan = planner.plan(in);
  const LipmAxisState next = lipm_state_after(s.y, s.vy, plan.foothold_m.y(), planner.omega_per_s(), kPeriod);
  return {next.position_m, next.velocity_m_s, plan.foothold_m.y(), other(s.swing)};
}

// On the orbit: the left foot at +w/2 carries the robot, the CoM crosses the middle
// towards the right at (w/2) ω tanh(ωT/2).
Switch on_orbit(double omega) { return {0.0, -0.5 * kWidth * omega * std::tanh(0.5 * omega * kPeriod), 0.5 * kWidth, Side::Right}; }

TEST(TvrLateralWidth, TheOrbitIsAFixedPointForAnyReversalTime) {
  for (double t_prime : {0.19, 0.25, 0.38, 0.5}) {
    const TvrPlanner planner(orbit_params(t_prime, 0.0));
    Switch s = on_orbit(planner.omega_per_s());
    const Switch start = s;
    for (int k = 1; k <= 6; ++k) {
      s = step(planner, s);
      const double sign = k % 2 ? -1.0 : 1.0;  // odd steps stand on the right foot
      EXPECT_NEAR(s.foot, sign * 0.5 * kWidth, 1e-12) << "t' " << t_prime << " step " << k;
      EXPECT_NEAR(s.y, 0.0, 1e-12);
      EXPECT_NEAR(s.vy, sign * start.vy, 1e-12);  // towards the next stance foot
    }
  }
}

TEST(TvrLateralWidth, WithReversalAtOnePeriodTheMapIsDeadbeat) {
  const TvrPlanner planner(orbit_params(kPeriod, 0.0));
  const double omega = planner.omega_per_s();
  Switch s = on_orbit(omega);
  s.y += 0.04;   // pushed: 4 cm off and 0.15 m/s faster
  s.vy -= 0.15;
  s = step(planner, s);
  s = step(planner, s);
  // After two steps the state relative to the stance foot is the orbit's again (the
  // orbit's middle has moved: with κ_y = 0 nothing pulls it back).
  const double middle = s.foot - 0.5 * kWidth;  // the left foot stands at middle + w/2
  EXPECT_NEAR(s.y - middle, 0.0, 1e-12);
  EXPECT_NEAR(s.vy, on_orbit(omega).vy, 1e-12);
  // A third step keeps it there: the width is the orbit's.
  const Switch third = step(planner, s);
  EXPECT_NEAR(s.foot - third.foot, kWidth, 1e-12);
}

TEST(TvrLateralWidth, KappaPullsTheOrbitsMiddleBackToTheTarget) {
  const TvrPlanner planner(orbit_params(kPeriod, -0.25));
  Switch s = on_orbit(planner.omega_per_s());
  s.y += 0.10;
  s.foot += 0.10;  // the whole orbit 10 cm to the left of x_des = 0
  for (int k = 0; k < 40; ++k) s = step(planner, s);
  const double middle = s.foot + (s.swing == Side::Left ? 0.5 : -0.5) * kWidth;
  EXPECT_NEAR(middle, 0.0, 1e-4);
}

TEST(TvrLateralWidth, ANegativeWidthOrPeriodIsRefused) {
  TvrParams p = orbit_params(kPeriod, 0.0);
  p.lateral_width_m = -0.1;
  EXPECT_THROW(TvrPlanner{p}, InputError);
  p = orbit_params(kPeriod, 0.0);
  p.step_period_s = 0.0;
  EXPECT_THROW(TvrPlanner{p}, InputError);
}

}  // namespace
}  // namespace dmbd::wholebody::testing
