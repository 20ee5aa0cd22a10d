// Where a swinging foot can still land (swing_reach.hpp): the closed form against hand
// computed trapezoid and triangle profiles, and against a brute force over bang-bang
// profiles (no admissible profile lands farther than the bound, and the optimal one lands
// on it); the foot that cannot stop in time; bad limits refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "dmbd/base/error.hpp"
#include "dmbd/wholebody/swing_reach.hpp"

namespace {

using dmbd::wholebody::swing_reach;

// Trapezoids and triangles worked out by hand (V = 1 m/s, A = 10 m/s²).
TEST(SwingReach, TrapezoidAndTriangleProfilesByHand) {
  // From rest, 0.5 s: up 0.1 s (0.05 m), 0.3 s at 1 m/s, down 0.1 s (0.05 m): 0.4 m each way.
  auto r = swing_reach(0.2, 0.0, 0.5, 1.0, 10.0);
  EXPECT_NEAR(r.hi_m, 0.2 + 0.4, 1e-15);
  EXPECT_NEAR(r.lo_m, 0.2 - 0.4, 1e-15);
  // Moving forward at 0.5 m/s: forward, up 0.05 s (0.0375 m), 0.35 s at 1 m/s, down 0.1 s
  // (0.05 m): 0.4375 m; backward (the mirror: from −0.5 m/s), up 0.15 s from −0.5 to 1 m/s
  // (0.0375 m), 0.25 s at 1 m/s, down 0.1 s (0.05 m): 0.3375 m.
  r = swing_reach(0.0, 0.5, 0.5, 1.0, 10.0);
  EXPECT_NEAR(r.hi_m, 0.4375, 1e-15);
  EXPECT_NEAR(r.lo_m, -0.3375, 1e-15);
  // Too little time to reach the speed limit: a triangle to v_p = (A t + v0)/2 = 0.5 m/s
  // in 0.05 s and back: 0.025 m.
  r = swing_reach(0.0, 0.0, 0.1, 1.0, 10.0);
  EXPECT_NEAR(r.hi_m, 0.025, 1e-15);
  // No time: the foot lands where it is.
  r = swing_reach(0.3, 0.0, 0.0, 1.0, 10.0);
  EXPECT_EQ(r.lo_m, 0.3);
  EXPECT_EQ(r.hi_m, 0.3);
}

// A foot too fast to stop in the time left lands where full braking takes it.
TEST(SwingReach, AFootThatCannotStopLandsWhereFullBrakingTakesIt) {
  const auto r = swing_reach(0.0, 0.8, 0.05, 1.0, 10.0);  // needs 0.08 s to stop
  EXPECT_NEAR(r.lo_m, 0.8 * 0.05 - 0.5 * 10 * 0.05 * 0.05, 1e-15);
  EXPECT_EQ(r.lo_m, r.hi_m);
}

// Brute force: 20000 random profiles of 50 piecewise-constant accelerations in [−A, A],
// the speed held within V, the last part forced to brake to rest where it can; of those
// ending at rest (|v| < 1e-9), none lands beyond the bounds (to 1e-12), and the best
// comes within 2 % of them.
TEST(SwingReach, NoAdmissibleProfileLandsFartherAndTheBestComesClose) {
  const double V = 0.9, A = 12.0, t = 0.3, v0 = -0.4;
  const auto r = swing_reach(0.0, v0, t, V, A);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = 50;
  const double dt = t / n;
  double best_hi = -1e9, best_lo = 1e9;
  int at_rest = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const double bias = u(rng);
    double x = 0, v = v0;
    for (int k = 0; k < n; ++k) {
      const double left = t - k * dt;
      double a = A * std::clamp(bias + 0.3 * u(rng), -1.0, 1.0);
      if (std::abs(v) >= A * (left - dt)) a = -std::copysign(std::min(A, std::abs(v) / dt), v);  // brake to rest in time
      double v1 = std::clamp(v + a * dt, -V, V);
      x += 0.5 * (v + v1) * dt;  // exact for a constant acceleration between the clamps
      v = v1;
    }
    if (std::abs(v) > 1e-9) continue;
    ++at_rest;
    EXPECT_LE(x, r.hi_m + 1e-12);
    EXPECT_GE(x, r.lo_m - 1e-12);
    best_hi = std::max(best_hi, x);
    best_lo = std::min(best_lo, x);
  }
  ASSERT_GT(at_rest, 1000);
  EXPECT_GT(best_hi, r.hi_m - 0.02 * (r.hi_m - r.lo_m));
  EXPECT_LT(best_lo, r.lo_m + 0.02 * (r.hi_m - r.lo_m));
}

TEST(SwingReach, BadLimitsAreRefused) {
  EXPECT_THROW(swing_reach(0, 0, 0.1, 0.0, 10), dmbd::InputError);
  EXPECT_THROW(swing_reach(0, 0, 0.1, 1.0, -1), dmbd::InputError);
  EXPECT_THROW(swing_reach(0, 0, -0.1, 1.0, 10), dmbd::InputError);
  EXPECT_THROW(swing_reach(0, 1.5, 0.1, 1.0, 10), dmbd::InputError);
  EXPECT_THROW(swing_reach(0, NAN, 0.1, 1.0, 10), dmbd::InputError);
}

}  // namespace
