// The capture analysis of the stepping LIPM (wholebody/capture.hpp): its intervals
// against their hand-derived closed forms (Koolen et al. 2012's d_∞; the alternating
// lateral steps solved by hand), and against stepping the pendulum itself (the CoM's
// closed form of tvr.hpp, not the capture point's recursion): from just inside an
// interval a stepping strategy keeps the robot up for 40 steps, from just outside even
// the best step lets the capture point run away. The push's shift against the pendulum
// with the force as a shifted foot. Tolerances: 1e-12 m for closed forms (rounding of a
// few exponentials), 1e-9 m for the pendulum's closed form after 40 steps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "dmbd/base/error.hpp"
#include "dmbd/wholebody/capture.hpp"
#include "dmbd/wholebody/tvr.hpp"

namespace dmbd::wholebody::testing {
namespace {

// DRACO's stepping (draco-facts.md): the CoM at 0.78 m, a step every 0.38 s (double
// support 0.01 + lift 0.03 + swing 0.33 + landing 0.01), the TVR's step limits.
const double kOmega = std::sqrt(9.81 / 0.78);
constexpr double kStepS = 0.38;
const StepRange kSagittal{-0.4, 0.4};
const StepRange kLeftSwing{0.20, 0.55}, kRightSwing{-0.55, -0.20};

TEST(CaptureIntervals, OneRangeIsKoolensDInfinity) {
  const double beta = std::exp(-kOmega * kStepS);
  const auto c = capture_intervals(kOmega, kStepS, {kSagittal});
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].hi_m, 0.4 * beta / (1 - beta), 1e-12);
  EXPECT_NEAR(c[0].lo_m, -0.4 * beta / (1 - beta), 1e-12);
  const double r = 0.05;  // a CoP range widens it by r
  const auto cr = capture_intervals(kOmega, kStepS, {kSagittal}, r);
  EXPECT_NEAR(cr[0].hi_m, r + 0.4 * beta / (1 - beta), 1e-12);
}

TEST(CaptureIntervals, AlternatingLateralStepsByHand) {
  // hi_L = (hi_R + 0.55) β, hi_R = (hi_L − 0.20) β  ⇒  hi_L = (0.55 β − 0.20 β²) / (1 − β²);
  // lo_L = (lo_R + 0.20) β, lo_R = (lo_L − 0.55) β  ⇒  lo_L = (0.20 β − 0.55 β²) / (1 − β²).
  const double b = std::exp(-kOmega * kStepS);
  const auto c = capture_intervals(kOmega, kStepS, {kLeftSwing, kRightSwing});
  ASSERT_EQ(c.size(), 2u);
  const double hi_l = (0.55 * b - 0.20 * b * b) / (1 - b * b), lo_l = (0.20 * b - 0.55 * b * b) / (1 - b * b);
  EXPECT_NEAR(c[0].hi_m, hi_l, 1e-12);
  EXPECT_NEAR(c[0].lo_m, lo_l, 1e-12);
  EXPECT_NEAR(c[1].hi_m, (hi_l - 0.20) * b, 1e-12);  // mirror images of each other
  EXPECT_NEAR(c[1].lo_m, -c[0].hi_m, 1e-12);
}

TEST(CaptureIntervals, BeforeAStepIsTheRecursionOverTheTimeLeft) {
  const auto c = capture_intervals(kOmega, kStepS, {kSagittal});
  const CaptureInterval at_start = capture_interval_before(kOmega, kStepS, kSagittal, c[0]);
  EXPECT_NEAR(at_start.hi_m, c[0].hi_m, 1e-12);  // the fixed point
  const CaptureInterval fixed = capture_interval_before(kOmega, 0.1, {0.1, 0.1}, c[0]);  // a foothold already chosen
  EXPECT_NEAR(fixed.hi_m, (c[0].hi_m + 0.1) * std::exp(-kOmega * 0.1), 1e-12);
  EXPECT_NEAR(fixed.lo_m, (c[0].lo_m + 0.1) * std::exp(-kOmega * 0.1), 1e-12);
}

// The pendulum stepped every kStepS from a capture point `offset` ahead of its foot:
// at each touch-down the next foot goes where the capture point lands mid-way in the
// next interval, within the step's range. Returns the largest |ξ − p| at a touch-down.
double step_the_pendulum(double offset, const std::vector<StepRange>& cycle, int steps) {
  const auto c = capture_intervals(kOmega, kStepS, cycle);
  double foot = 0.0, x = 0.0, v = offset * kOmega, worst = std::abs(offset);
  for (int k = 0; k < steps && worst < 10.0; ++k) {
    const LipmAxisState s = lipm_state_after(x, v, foot, kOmega, kStepS);
    const double xi = s.position_m + s.velocity_m_s / kOmega;
    const StepRange& range = cycle[static_cast<std::size_t>(k) % cycle.size()];
    const CaptureInterval& next = c[static_cast<std::size_t>(k + 1) % c.size()];
    const double aim = xi - foot - 0.5 * (next.lo_m + next.hi_m);
    foot += std::clamp(aim, range.min_m, range.max_m);
    x = s.position_m;
    v = s.velocity_m_s;
    worst = std::max(worst, std::abs(xi - foot));
  }
  return worst;
}

TEST(CaptureIntervals, InsideIsCapturedOutsideRunsAway) {
  for (const auto& cycle : {std::vector<StepRange>{kSagittal}, std::vector<StepRange>{kLeftSwing, kRightSwing}}) {
    const auto c = capture_intervals(kOmega, kStepS, cycle);
    double bound = 0;
    for (const auto& i : c) bound = std::max({bound, std::abs(i.lo_m), std::abs(i.hi_m)});
    for (double edge : {c[0].lo_m, c[0].hi_m}) {
      const double inward = edge == c[0].hi_m ? -1.0 : 1.0;
      EXPECT_LE(step_the_pendulum(edge + inward * 1e-4, cycle, 40), bound + 1e-9) << "edge " << edge;
      EXPECT_GT(step_the_pendulum(edge - inward * 1e-4, cycle, 40), 10.0) << "edge " << edge;
    }
  }
}

TEST(CaptureIntervals, PushShiftIsThePendulumOverAShiftedFoot) {
  // ẍ = ω²(x − p) + F/m is the pendulum over the foot p − F/(mω²).
  const double F = 100, m = 37, tau = 0.2;
  const LipmAxisState s = lipm_state_after(0.0, 0.0, -F / (m * kOmega * kOmega), kOmega, tau);
  EXPECT_NEAR(push_capture_point_shift(F, tau, m, kOmega), s.position_m + s.velocity_m_s / kOmega, 1e-12);
}

TEST(CaptureIntervals, DracoCannotCaptureA100NPushAtTheStepStart) {
  // The figures quoted in docs/experiments.md ("balance", pushes): d_∞ = 0.1405 m for
  // ±0.4 m steps every 0.38 s on point feet; 100 N for 0.2 s on 37 kg moves ξ 0.222 m.
  const auto c = capture_intervals(kOmega, kStepS, {kSagittal});
  EXPECT_NEAR(c[0].hi_m, 0.1405, 5e-4);
  EXPECT_NEAR(push_capture_point_shift(100, 0.2, 37, kOmega), 0.2218, 5e-4);
  // The worst moment for a push to end: just after the mid-swing replan fixed the
  // foothold (in place), 0.165 s before touch-down. The largest 0.2 s push capturable
  // then is 35.3 N; a 100 N push is capturable only when it ends with between 0.251 s
  // and 0.165 s of the swing left (a foothold still free and ξ within reach).
  const double worst = capture_interval_before(kOmega, 0.165, {0.0, 0.0}, c[0]).hi_m;
  EXPECT_NEAR(worst / push_capture_point_shift(1.0, 0.2, 37, kOmega), 35.3, 0.1);
  const double shift = push_capture_point_shift(100, 0.2, 37, kOmega);
  EXPECT_NEAR(capture_interval_before(kOmega, 0.251, kSagittal, c[0]).hi_m, shift, 1e-3);
}

TEST(CaptureIntervals, BadInputThrows) {
  EXPECT_THROW(capture_intervals(0.0, kStepS, {kSagittal}), InputError);
  EXPECT_THROW(capture_intervals(kOmega, -1.0, {kSagittal}), InputError);
  EXPECT_THROW(capture_intervals(kOmega, kStepS, {}), InputError);
  EXPECT_THROW(capture_intervals(kOmega, kStepS, {{0.5, 0.1}}), InputError);
  EXPECT_THROW(capture_intervals(kOmega, kStepS, {kSagittal}, -0.1), InputError);
  EXPECT_THROW(push_capture_point_shift(100, 0.2, 0.0, kOmega), InputError);
}

}  // namespace
}  // namespace dmbd::wholebody::testing
