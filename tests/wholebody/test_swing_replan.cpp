// The swing trajectory's replan (wholebody/swing.hpp): p, v, a continuous at the replan
// instant, the path before it kept, the landing on the new target with the planned
// landing velocity, derivatives still finite differences of position, two replans in a
// row, and the replans refused; with the horizontal part ahead (horizontal_fraction < 1)
// a replan's horizontal change arriving by f T (by T after f T), the vertical by T, and
// f = 1 blending as before. Worst errors are recorded as test properties
// (--gtest_output=xml).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "dmbd/wholebody/swing.hpp"
#include "recorded_error.hpp"

namespace dmbd::wholebody::testing {
namespace {

const double kT = 0.33, kReplan = 0.5 * kT;
const Eigen::Vector3d kLiftOff(0.0, -0.14, 0.0), kTarget(0.05, -0.33, 0.0);
const Eigen::Vector3d kMoved(0.11, -0.41, 0.0);  // the mid-swing replan's target

SwingTrajectory swing() {
  SwingTrajectory s;
  s.start(kLiftOff, kTarget, kT);
  return s;
}

double distance(const SwingSample& a, const SwingSample& b, int order) {
  if (order == 0) return (a.position_m - b.position_m).norm();
  if (order == 1) return (a.velocity_m_s - b.velocity_m_s).norm();
  return (a.acceleration_m_s2 - b.acceleration_m_s2).norm();
}

// At the replan instant the new path has the old one's p, v and a (1e-15: the blend
// adds exactly zero there); just after it, it departs no faster than the blend's leading
// terms allow: ‖Δp‖ ≤ 10 δ ε³/D³, ‖Δv‖ ≤ 30 δ ε²/D³, ‖Δa‖ ≤ 60 δ ε/D³ (D = T − t_r,
// δ = ‖new − old target‖; the minimum-jerk s(τ), s′, s″ lie below 10τ³, 30τ², 60τ).
TEST(SwingReplan, PositionVelocityAndAccelerationAreContinuous) {
  const SwingTrajectory old_path = swing();
  SwingTrajectory s = swing();
  ASSERT_TRUE(s.replan(kReplan, kMoved));
  double worst = 0;
  for (int order = 0; order < 3; ++order) {
    const double d = distance(s.at(kReplan), old_path.at(kReplan), order);
    EXPECT_LE(d, 1e-15) << "order " << order;
    worst = std::max(worst, d);
  }
  RecordProperty("worst_jump_at_replan", text(worst));
  const double delta = (kMoved - kTarget).norm(), D = kT - kReplan;
  const double coefficient[3] = {10.0, 30.0, 60.0};
  for (double eps : {1e-3, 1e-5, 1e-7}) {
    for (int order = 0; order < 3; ++order) {
      const double bound = coefficient[order] * delta * std::pow(eps, 3 - order) / (D * D * D);
      EXPECT_LE(distance(s.at(kReplan + eps), old_path.at(kReplan + eps), order), bound * (1 + 1e-9) + 1e-15)
          << "order " << order << " eps " << eps;
    }
  }
}

// Before the replan instant the path is the old one, exactly.
TEST(SwingReplan, ThePathBeforeTheReplanIsKept) {
  const SwingTrajectory old_path = swing();
  SwingTrajectory s = swing();
  ASSERT_TRUE(s.replan(kReplan, kMoved));
  auto expect_kept = [&](double t) {
    for (int order = 0; order < 3; ++order) EXPECT_EQ(distance(s.at(t), old_path.at(t), order), 0.0) << t;
  };
  for (int k = 0; k <= 50; ++k) expect_kept(k * kReplan / 50);
  for (double before : {1e-3, 1e-4, 1e-6, 1e-9}) expect_kept(kReplan - before);
}

// After the replan the foot lands on the new target (1e-12 m) with the planned landing
// velocity (0, 0, −0.5) m/s (1e-10) and no acceleration (1e-8 m/s²); target_m() says so.
TEST(SwingReplan, LandsOnTheNewTarget) {
  SwingTrajectory s = swing();
  ASSERT_TRUE(s.replan(kReplan, kMoved));
  const SwingSample end = s.at(kT);
  EXPECT_LT((end.position_m - kMoved).norm(), 1e-12);
  EXPECT_LT((end.velocity_m_s - Eigen::Vector3d(0, 0, -0.5)).norm(), 1e-10);
  EXPECT_LT(end.acceleration_m_s2.norm(), 1e-8);
  EXPECT_EQ(s.target_m(), kMoved);
  EXPECT_EQ(s.replans(), 1);
  RecordProperty("landing_error_m", text((end.position_m - kMoved).norm()));
}

// The replanned path's velocity and acceleration are still the central differences of
// its position and velocity (step 1e-6 s, away from the knots and the replan instant by
// 1e-4 s; tolerances as for the spline alone: 1e-7 m/s, 1e-5 m/s²).
TEST(SwingReplan, DerivativesAreFiniteDifferences) {
  SwingTrajectory s = swing();
  ASSERT_TRUE(s.replan(kReplan + 0.013, kMoved));
  const double h = 1e-6;
  double worst_v = 0, worst_a = 0;
  for (int k = 0; k <= 330; ++k) {
    const double t = 1e-4 + k * (kT - 2e-4) / 330.0;
    if (std::abs(std::remainder(t, kT / 4)) < 1e-4 || std::abs(t - kReplan - 0.013) < 1e-4) continue;
    const SwingSample plus = s.at(t + h), minus = s.at(t - h), here = s.at(t);
    worst_v = std::max(worst_v, ((plus.position_m - minus.position_m) / (2 * h) - here.velocity_m_s).norm());
    worst_a = std::max(worst_a, ((plus.velocity_m_s - minus.velocity_m_s) / (2 * h) - here.acceleration_m_s2).norm());
  }
  EXPECT_LT(worst_v, 1e-7);
  EXPECT_LT(worst_a, 1e-5);
  RecordProperty("worst_velocity_error_m_s", text(worst_v));
  RecordProperty("worst_acceleration_error_m_s2", text(worst_a));
}

// Two replans: continuous at both instants (1e-15), landing on the second target.
TEST(SwingReplan, TwoReplansInARow) {
  SwingTrajectory s = swing();
  ASSERT_TRUE(s.replan(0.12, kMoved));
  const SwingTrajectory once = s;
  const Eigen::Vector3d second(0.08, -0.37, 0.01);
  ASSERT_TRUE(s.replan(0.2, second));
  for (int order = 0; order < 3; ++order) EXPECT_LE(distance(s.at(0.2), once.at(0.2), order), 1e-15);
  EXPECT_EQ(distance(s.at(0.15), once.at(0.15), 0), 0.0);
  EXPECT_LT((s.at(kT).position_m - second).norm(), 1e-12);
  EXPECT_LT((s.at(kT).velocity_m_s - Eigen::Vector3d(0, 0, -0.5)).norm(), 1e-10);
}

// A replan with no time left (t ≥ T), or beyond kMaxReplans, is refused and changes
// nothing; one at a negative time blends from lift-off (which stays at rest).
TEST(SwingReplan, RefusedAndEarlyReplans) {
  SwingTrajectory s = swing();
  EXPECT_FALSE(s.replan(kT, kMoved));
  EXPECT_FALSE(s.replan(kT + 0.1, kMoved));
  EXPECT_EQ(s.replans(), 0);
  EXPECT_EQ(s.target_m(), kTarget);
  EXPECT_LT((s.at(kT).position_m - kTarget).norm(), 1e-12);
  for (int k = 0; k < SwingTrajectory::kMaxReplans; ++k) ASSERT_TRUE(s.replan(0.05 * k, kTarget + 0.01 * k * kMoved));
  EXPECT_FALSE(s.replan(0.3, kMoved));
  EXPECT_EQ(s.replans(), SwingTrajectory::kMaxReplans);

  SwingTrajectory early = swing();
  ASSERT_TRUE(early.replan(-0.1, kMoved));
  const SwingSample lift = early.at(0.0);
  EXPECT_LT((lift.position_m - kLiftOff).norm(), 1e-12);
  EXPECT_LT(lift.velocity_m_s.norm(), 1e-10);
  EXPECT_LT(lift.acceleration_m_s2.norm(), 1e-8);
  EXPECT_LT((early.at(kT).position_m - kMoved).norm(), 1e-12);
}

// --- With the horizontal part ahead (horizontal_fraction f < 1) ------------------------

const double kF = 0.6, kFT = kF * kT;  // x and y arrive at f T = 0.198 s
const Eigen::Vector3d kMovedUp(0.11, -0.41, 0.012);  // a replan target 12 mm higher

SwingTrajectory swing(double f) {
  SwingParams params;
  params.horizontal_fraction = f;
  SwingTrajectory s(params);
  s.start(kLiftOff, kTarget, kT);
  return s;
}

// The minimum-jerk blend s(τ), τ clamped to [0, 1], as the header writes it.
double blend(double t, double start, double end) {
  const double tau = std::clamp((t - start) / (end - start), 0.0, 1.0);
  return tau * tau * tau * (10.0 - 15.0 * tau + 6.0 * tau * tau);
}

// A replan at t_r = 0.1 s < f T: p, v, a continuous at t_r (1e-12); x and y on the new
// target at rest from f T on (1e-12 m, 1e-10 m/s, 1e-8 m/s², as for the landing); z the
// old height plus the 12 mm change blended from t_r to T (1e-12 m), landing with the
// planned velocity.
TEST(SwingReplan, BeforeFTTheHorizontalChangeArrivesByFT) {
  const SwingTrajectory old_path = swing(kF);
  SwingTrajectory s = swing(kF);
  const double t_r = 0.1;
  ASSERT_TRUE(s.replan(t_r, kMovedUp));
  for (int order = 0; order < 3; ++order) EXPECT_LE(distance(s.at(t_r), old_path.at(t_r), order), 1e-12) << order;
  for (const double t : {kFT, 0.25, kT}) {
    const SwingSample at = s.at(t);
    EXPECT_LT((at.position_m.head<2>() - kMovedUp.head<2>()).norm(), 1e-12) << "t " << t;
    EXPECT_LT(at.velocity_m_s.head<2>().norm(), 1e-10) << "t " << t;
    EXPECT_LT(at.acceleration_m_s2.head<2>().norm(), 1e-8) << "t " << t;
  }
  EXPECT_GT((s.at(0.15).position_m.head<2>() - kMovedUp.head<2>()).norm(), 1e-3);  // on its way at 0.15 s
  const double dz = kMovedUp.z() - kTarget.z();
  for (int k = 0; k <= 50; ++k) {
    const double t = t_r + k * (kT - t_r) / 50;
    EXPECT_NEAR(s.at(t).position_m.z(), old_path.at(t).position_m.z() + dz * blend(t, t_r, kT), 1e-12) << "t " << t;
  }
  // At f T the height's change is under way, not complete (s(0.43) = 0.39 of it).
  EXPECT_GT(std::abs(s.at(kFT).position_m.z() - old_path.at(kFT).position_m.z() - dz), 0.5 * dz);
  EXPECT_LT((s.at(kT).position_m - kMovedUp).norm(), 1e-12);
  EXPECT_LT((s.at(kT).velocity_m_s - Eigen::Vector3d(0, 0, -0.5)).norm(), 1e-10);
}

// A replan at t_r = 0.25 s > f T (the foot already over the old target): the horizontal
// change blends in by T instead, from rest at t_r (x, y = old target + δ s(τ), 1e-12 m).
TEST(SwingReplan, AfterFTTheHorizontalChangeArrivesByT) {
  const SwingTrajectory old_path = swing(kF);
  SwingTrajectory s = swing(kF);
  const double t_r = 0.25;
  ASSERT_TRUE(s.replan(t_r, kMoved));
  for (int order = 0; order < 3; ++order) EXPECT_LE(distance(s.at(t_r), old_path.at(t_r), order), 1e-12) << order;
  const Eigen::Vector2d delta = (kMoved - kTarget).head<2>();
  for (int k = 0; k <= 40; ++k) {
    const double t = t_r + k * (kT - t_r) / 40;
    const Eigen::Vector2d expected = kTarget.head<2>() + blend(t, t_r, kT) * delta;
    EXPECT_LT((s.at(t).position_m.head<2>() - expected).norm(), 1e-12) << "t " << t;
  }
  EXPECT_LT((s.at(kT).position_m - kMoved).norm(), 1e-12);
}

// With f = 1 a replan is blended as before the option: the old path plus δ s(τ) over
// [t_r, T] in all three axes (1e-12 m), and bit for bit a default-constructed
// trajectory's replan, at 331 times.
TEST(SwingReplan, FractionOneBlendsAsWithoutTheOption) {
  const SwingTrajectory old_path = swing(1.0);
  SwingTrajectory one = swing(1.0), plain = swing();
  ASSERT_TRUE(one.replan(kReplan, kMovedUp));
  ASSERT_TRUE(plain.replan(kReplan, kMovedUp));
  const Eigen::Vector3d delta = kMovedUp - kTarget;
  for (int k = 0; k <= 330; ++k) {
    const double t = k * kT / 330.0;
    const Eigen::Vector3d expected = old_path.at(t).position_m + blend(t, kReplan, kT) * delta;
    ASSERT_LT((one.at(t).position_m - expected).norm(), 1e-12) << "t " << t;
    for (int order = 0; order < 3; ++order) ASSERT_EQ(distance(one.at(t), plain.at(t), order), 0.0) << "t " << t;
  }
}

}  // namespace
}  // namespace dmbd::wholebody::testing
