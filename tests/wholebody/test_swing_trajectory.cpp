// The swing foot's cubic B-spline (wholebody/swing.hpp): its end points and end
// velocities and accelerations, the mid-point height at T/2, velocity and acceleration
// against finite differences, clamping outside [0, T], the foot staying above the
// ground, the configurable height and landing velocity, the horizontal part ahead of the
// vertical one (horizontal_fraction), and the parameter checks. Worst errors are recorded
// as test properties (--gtest_output=xml).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>

#include "dmbd/base/error.hpp"
#include "dmbd/wholebody/swing.hpp"
#include "recorded_error.hpp"

namespace dmbd::wholebody::testing {
namespace {

const double kT = 0.33;
// A left foot stepping forward and outward, lifting off from and landing on the ground;
// and one that lifts off 1 cm high and lands 5 mm low.
const Eigen::Vector3d kLiftOff(0.02, 0.14, 0.0), kTarget(0.12, 0.31, 0.0);
const Eigen::Vector3d kLiftOffHigh(-0.05, -0.12, 0.01), kTargetLow(0.03, -0.29, -0.005);

SwingTrajectory make(const Eigen::Vector3d& from, const Eigen::Vector3d& to, SwingParams params = {}) {
  SwingTrajectory s(params);
  s.start(from, to, kT);
  return s;
}

// Lift-off at the start point, from rest; landing on the target with velocity
// (0, 0, −0.5) m/s and no acceleration. Positions 1e-12 m; velocities 1e-10 m/s and
// accelerations 1e-8 m/s² (control points from a 7 × 7 solve whose rows scale as 1,
// 1/h and 1/h², h = T/4: rounding ~1e-16 × 1/h²).
TEST(SwingTrajectory, EndPointsAndEndVelocities) {
  double worst_p = 0, worst_v = 0, worst_a = 0;
  for (const auto& [from, to] : {std::pair{kLiftOff, kTarget}, std::pair{kLiftOffHigh, kTargetLow}}) {
    const SwingTrajectory s = make(from, to);
    const SwingSample a = s.at(0.0), b = s.at(kT);
    worst_p = std::max({worst_p, (a.position_m - from).norm(), (b.position_m - to).norm()});
    worst_v = std::max({worst_v, a.velocity_m_s.norm(), (b.velocity_m_s - Eigen::Vector3d(0, 0, -0.5)).norm()});
    worst_a = std::max({worst_a, a.acceleration_m_s2.norm(), b.acceleration_m_s2.norm()});
  }
  EXPECT_LT(worst_p, 1e-12);
  EXPECT_LT(worst_v, 1e-10);
  EXPECT_LT(worst_a, 1e-8);
  RecordProperty("worst_position_error_m", text(worst_p));
  RecordProperty("worst_velocity_error_m_s", text(worst_v));
  RecordProperty("worst_acceleration_error_m_s2", text(worst_a));
}

// At T/2 the foot is half-way horizontally and 0.11 m above the ground (the mean of the
// lift-off and landing heights): 1e-12 m.
TEST(SwingTrajectory, MidPointHeight) {
  double worst = 0;
  for (const auto& [from, to] : {std::pair{kLiftOff, kTarget}, std::pair{kLiftOffHigh, kTargetLow}}) {
    const Eigen::Vector3d mid = make(from, to).at(0.5 * kT).position_m;
    EXPECT_NEAR(mid.x(), 0.5 * (from.x() + to.x()), 1e-12);
    EXPECT_NEAR(mid.y(), 0.5 * (from.y() + to.y()), 1e-12);
    EXPECT_NEAR(mid.z(), 0.5 * (from.z() + to.z()) + 0.11, 1e-12);
    const Eigen::Vector3d expected = 0.5 * (from + to) + Eigen::Vector3d(0.0, 0.0, 0.11);
    worst = std::max(worst, (mid - expected).norm());
  }
  RecordProperty("worst_error_m", text(worst));
}

// The height and the landing velocity are parameters.
TEST(SwingTrajectory, HeightAndLandingVelocityAreConfigurable) {
  SwingParams params;
  params.mid_height_m = 0.07;
  params.landing_vertical_velocity_m_s = -0.2;
  const SwingTrajectory s = make(kLiftOff, kTarget, params);
  EXPECT_NEAR(s.at(0.5 * kT).position_m.z(), 0.07, 1e-12);
  EXPECT_NEAR(s.at(kT).velocity_m_s.z(), -0.2, 1e-10);
  EXPECT_NEAR(s.at(kT).velocity_m_s.head<2>().norm(), 0.0, 1e-10);
}

// Velocity = central difference of position, acceleration = central difference of
// velocity, step 1e-6 s, at 331 times across (0, T) less those within 1e-4 s of a knot
// (kT/4 apart: there the jerk jumps and a central difference errs by O(step)).
// Truncation ≤ (1e-6)²/6 × the jerk (~1e3 m/s³): ~2e-10 m/s, and none for the
// acceleration of a cubic piece; rounding ~1e-16 × |p| / 1e-6 ≈ 1e-10 m/s and
// ~1e-16 × |v| / 1e-6 ≈ 1e-10 m/s². Tolerances 1e-7 m/s and 1e-5 m/s².
TEST(SwingTrajectory, DerivativesAreFiniteDifferences) {
  const double h = 1e-6;
  double worst_v = 0, worst_a = 0;
  for (const auto& [from, to] : {std::pair{kLiftOff, kTarget}, std::pair{kLiftOffHigh, kTargetLow}}) {
    const SwingTrajectory s = make(from, to);
    for (int k = 0; k <= 330; ++k) {
      const double t = 1e-4 + k * (kT - 2e-4) / 330.0;
      const double to_knot = std::abs(std::remainder(t, kT / 4));
      if (to_knot < 1e-4) continue;
      const SwingSample plus = s.at(t + h), minus = s.at(t - h), here = s.at(t);
      worst_v = std::max(worst_v, ((plus.position_m - minus.position_m) / (2 * h) - here.velocity_m_s).norm());
      const Eigen::Vector3d a_fd = (plus.velocity_m_s - minus.velocity_m_s) / (2 * h);
      worst_a = std::max(worst_a, (a_fd - here.acceleration_m_s2).norm());
    }
  }
  EXPECT_LT(worst_v, 1e-7);
  EXPECT_LT(worst_a, 1e-5);
  RecordProperty("worst_velocity_error_m_s", text(worst_v));
  RecordProperty("worst_acceleration_error_m_s2", text(worst_a));
}

// The acceleration is continuous across the knots (a cubic B-spline is C²): the jump
// over ±1e-9 s around each interior knot is below 1e-5 m/s² (the jerk, ~1e3 m/s³, times
// 2e-9 s).
TEST(SwingTrajectory, AccelerationIsContinuousAtTheKnots) {
  const SwingTrajectory s = make(kLiftOff, kTarget);
  for (int k = 1; k < 4; ++k) {
    const double t = k * kT / 4;
    const SwingSample before = s.at(t - 1e-9), after = s.at(t + 1e-9);
    EXPECT_LT((after.acceleration_m_s2 - before.acceleration_m_s2).norm(), 1e-5) << "knot " << k;
    EXPECT_LT((after.velocity_m_s - before.velocity_m_s).norm(), 1e-7) << "knot " << k;
  }
}

// Outside [0, T] the time is clamped: exactly the samples at 0 and at T.
TEST(SwingTrajectory, TimesOutsideTheSwingAreClamped) {
  const SwingTrajectory s = make(kLiftOff, kTarget);
  for (double t : {-0.5, -1e-9}) {
    EXPECT_EQ(s.at(t).position_m, s.at(0.0).position_m);
    EXPECT_EQ(s.at(t).velocity_m_s, s.at(0.0).velocity_m_s);
    EXPECT_EQ(s.at(t).acceleration_m_s2, s.at(0.0).acceleration_m_s2);
  }
  for (double t : {kT + 1e-9, 2.0}) {
    EXPECT_EQ(s.at(t).position_m, s.at(kT).position_m);
    EXPECT_EQ(s.at(t).velocity_m_s, s.at(kT).velocity_m_s);
    EXPECT_EQ(s.at(t).acceleration_m_s2, s.at(kT).acceleration_m_s2);
  }
}

// The foot never dips below the lower of its lift-off and landing heights (1e-12 m) and
// rises no more than 2 cm above the mid-point height (sampled every 0.33 ms).
TEST(SwingTrajectory, StaysAboveTheGround) {
  double peak = -1.0;
  for (const auto& [from, to] : {std::pair{kLiftOff, kTarget}, std::pair{kLiftOffHigh, kTargetLow}}) {
    const SwingTrajectory s = make(from, to);
    double lowest = std::numeric_limits<double>::infinity(), highest = -lowest;
    for (int k = 0; k <= 1000; ++k) {
      const double z = s.at(k * kT / 1000).position_m.z();
      lowest = std::min(lowest, z);
      highest = std::max(highest, z);
    }
    const double ground = std::min(from.z(), to.z()), mid = 0.5 * (from.z() + to.z()) + 0.11;
    EXPECT_GE(lowest, ground - 1e-12);
    EXPECT_LT(highest, mid + 0.02);
    peak = std::max(peak, highest - mid);
  }
  RecordProperty("peak_above_mid_point_m", text(peak));
}

// start() begins a new swing: the earlier one's target and replans are forgotten.
TEST(SwingTrajectory, StartBeginsANewSwing) {
  SwingTrajectory s;
  s.start(kLiftOff, kTarget, kT);
  ASSERT_TRUE(s.replan(0.5 * kT, kTarget + Eigen::Vector3d(0.05, 0.0, 0.0)));
  s.start(kLiftOffHigh, kTargetLow, 0.4);
  EXPECT_EQ(s.replans(), 0);
  EXPECT_EQ(s.target_m(), kTargetLow);
  EXPECT_EQ(s.duration_s(), 0.4);
  EXPECT_NEAR((s.at(0.4).position_m - kTargetLow).norm(), 0.0, 1e-12);
}

// --- Horizontal ahead of vertical (horizontal_fraction f < 1) --------------------------

const double kF = 0.6;  // x and y arrive at f T = 0.198 s

SwingParams horizontal_fraction(double f) {
  SwingParams params;
  params.horizontal_fraction = f;
  return params;
}

// x and y are on the target at f T from rest (velocity 0, acceleration 0), and stay there
// at rest until T (tolerances as for the landing above: 1e-12 m, 1e-10 m/s, 1e-8 m/s²);
// half-way at f T/2 (1e-12 m); before f T not yet there.
TEST(SwingTrajectory, HorizontalFractionArrivesAtFTAndStays) {
  for (const auto& [from, to] : {std::pair{kLiftOff, kTarget}, std::pair{kLiftOffHigh, kTargetLow}}) {
    const SwingTrajectory s = make(from, to, horizontal_fraction(kF));
    for (const double t : {kF * kT, kF * kT + 1e-6, 0.25, 0.3, kT - 1e-9, kT}) {
      const SwingSample at = s.at(t);
      EXPECT_LT((at.position_m.head<2>() - to.head<2>()).norm(), 1e-12) << "t " << t;
      EXPECT_LT(at.velocity_m_s.head<2>().norm(), 1e-10) << "t " << t;
      EXPECT_LT(at.acceleration_m_s2.head<2>().norm(), 1e-8) << "t " << t;
    }
    const Eigen::Vector2d mid = s.at(0.5 * kF * kT).position_m.head<2>();
    EXPECT_LT((mid - 0.5 * (from + to).head<2>()).norm(), 1e-12);
    EXPECT_GT((s.at(0.9 * kF * kT).position_m.head<2>() - to.head<2>()).norm(), 1e-4);  // still on its way
    const SwingSample lift = s.at(0.0);
    EXPECT_LT((lift.position_m - from).norm(), 1e-12);
    EXPECT_LT(lift.velocity_m_s.norm(), 1e-10);
    EXPECT_LT(lift.acceleration_m_s2.norm(), 1e-8);
  }
}

// The height does not depend on f: z, ż, z̈ as with f = 1 at 331 times (1e-12).
TEST(SwingTrajectory, HorizontalFractionLeavesTheHeightAlone) {
  const SwingTrajectory early = make(kLiftOffHigh, kTargetLow, horizontal_fraction(kF));
  const SwingTrajectory full = make(kLiftOffHigh, kTargetLow);
  for (int k = 0; k <= 330; ++k) {
    const double t = k * kT / 330.0;
    const SwingSample a = early.at(t), b = full.at(t);
    ASSERT_NEAR(a.position_m.z(), b.position_m.z(), 1e-12) << "t " << t;
    ASSERT_NEAR(a.velocity_m_s.z(), b.velocity_m_s.z(), 1e-12) << "t " << t;
    ASSERT_NEAR(a.acceleration_m_s2.z(), b.acceleration_m_s2.z(), 1e-12) << "t " << t;
  }
  EXPECT_NEAR(early.at(0.5 * kT).position_m.z(), 0.5 * (kLiftOffHigh.z() + kTargetLow.z()) + 0.11, 1e-12);
}

// Velocity and acceleration are the central differences of position and velocity with
// f < 1 too (the horizontal spline over f T scaled by its own duration), away from the
// knots of both splines (multiples of T/4 and of f T/4) by 1e-4 s; tolerances as above.
TEST(SwingTrajectory, HorizontalFractionDerivativesAreFiniteDifferences) {
  const SwingTrajectory s = make(kLiftOff, kTarget, horizontal_fraction(kF));
  const double h = 1e-6;
  double worst_v = 0, worst_a = 0;
  for (int k = 0; k <= 330; ++k) {
    const double t = 1e-4 + k * (kT - 2e-4) / 330.0;
    if (std::abs(std::remainder(t, kT / 4)) < 1e-4 || std::abs(std::remainder(t, kF * kT / 4)) < 1e-4) continue;
    const SwingSample plus = s.at(t + h), minus = s.at(t - h), here = s.at(t);
    worst_v = std::max(worst_v, ((plus.position_m - minus.position_m) / (2 * h) - here.velocity_m_s).norm());
    worst_a = std::max(worst_a, ((plus.velocity_m_s - minus.velocity_m_s) / (2 * h) - here.acceleration_m_s2).norm());
  }
  EXPECT_LT(worst_v, 1e-7);
  EXPECT_LT(worst_a, 1e-5);
  RecordProperty("worst_velocity_error_m_s", text(worst_v));
  RecordProperty("worst_acceleration_error_m_s2", text(worst_a));
}

// f = 1 (the default) is the path without the option: the same samples, bit for bit, as
// a default-constructed trajectory at 331 times.
TEST(SwingTrajectory, HorizontalFractionOneIsTheDefault) {
  const SwingTrajectory one = make(kLiftOff, kTarget, horizontal_fraction(1.0)), plain = make(kLiftOff, kTarget);
  for (int k = 0; k <= 330; ++k) {
    const double t = k * kT / 330.0;
    ASSERT_EQ(one.at(t).position_m, plain.at(t).position_m) << "t " << t;
    ASSERT_EQ(one.at(t).velocity_m_s, plain.at(t).velocity_m_s) << "t " << t;
    ASSERT_EQ(one.at(t).acceleration_m_s2, plain.at(t).acceleration_m_s2) << "t " << t;
  }
}

TEST(SwingTrajectory, RejectsAHorizontalFractionOutsideZeroToOne) {
  for (const double f : {0.0, -0.1, 1.0 + 1e-12, 2.0, std::nan(""), std::numeric_limits<double>::infinity()})
    EXPECT_THROW(SwingTrajectory{horizontal_fraction(f)}, InputError) << f;
  EXPECT_NO_THROW(SwingTrajectory{horizontal_fraction(1.0)});
  EXPECT_NO_THROW(SwingTrajectory{horizontal_fraction(0.05)});
}

TEST(SwingTrajectory, RejectsBadDurationsAndParameters) {
  SwingTrajectory s;
  EXPECT_THROW(s.start(kLiftOff, kTarget, 0.0), InputError);
  EXPECT_THROW(s.start(kLiftOff, kTarget, -0.1), InputError);
  EXPECT_THROW(s.start(kLiftOff, kTarget, std::nan("")), InputError);
  SwingParams bad;
  bad.mid_height_m = std::numeric_limits<double>::infinity();
  EXPECT_THROW(SwingTrajectory{bad}, InputError);
}

}  // namespace
}  // namespace dmbd::wholebody::testing
