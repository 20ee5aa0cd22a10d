// LinkageGeometry and LinkageTable: derivatives against finite differences, the spline
// table against the exact N_l, and DRACO's linkages over their joint ranges.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "robot_files.hpp"
#include "dmbd/model/actuator.hpp"
#include "dmbd/model/error.hpp"

namespace dm = dmbd::model;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Joint ranges of this project's URDF (rad); the right leg mirrors roll (and yaw,
// symmetric). Hip roll left [-0.283, 0.907]; ankle: foot flat = 0.
const std::map<std::string, std::pair<double, double>>& draco_ranges() {
  static const std::map<std::string, std::pair<double, double>> r = {
      {"l_hip_yaw", {-0.75, 0.75}},    {"r_hip_yaw", {-0.75, 0.75}},     {"l_hip_roll", {-0.283, 0.907}},
      {"r_hip_roll", {-0.907, 0.283}}, {"l_hip_pitch", {-1.266, 1.004}}, {"r_hip_pitch", {-1.266, 1.004}},
      {"l_knee", {0.0, 2.14}},         {"r_knee", {0.0, 2.14}},          {"l_ankle", {-0.845, 0.705}},
      {"r_ankle", {-0.845, 0.705}}};
  return r;
}

std::vector<double> grid(double lo, double hi, int n) {
  std::vector<double> q(n);
  for (int i = 0; i < n; ++i) q[i] = lo + (hi - lo) * i / (n - 1);
  return q;
}

// Two test geometries: the knee's, and a mirrored one (sign -1) with a not-small b/a.
dm::LinkageGeometry knee_geometry() { return {0.30, 0.052, kPi / 2 - 1.07, 1.0}; }
dm::LinkageGeometry mirrored_geometry() { return {0.20, 0.09, 1.9, -1.0}; }

}  // namespace

// r = dx/dq against a central difference of length_m. The difference's truncation error
// is h^2/6 |x'''| ~ 1e-12 m and its round-off eps x / h ~ 1e-13 m for h = 1e-4 rad, so
// 1e-9 m (2e-8 of a 5 cm arm) is a safe bound that a wrong sign or factor cannot meet.
TEST(Linkage, MomentArmIsTheDerivativeOfLength) {
  for (const dm::LinkageGeometry& g : {knee_geometry(), mirrored_geometry()}) {
    const double h = 1e-4;
    for (double q : grid(-0.5, 1.2, 35)) {
      const double fd = (g.length_m(q + h) - g.length_m(q - h)) / (2 * h);
      EXPECT_NEAR(g.moment_arm_m(q), fd, 1e-9) << "q = " << q << " sign = " << g.sign;
    }
  }
}

// dr/dq against a central difference of moment_arm_m (same error budget, one order up).
TEST(Linkage, MomentArmDerivativeIsTheSecondDerivativeOfLength) {
  for (const dm::LinkageGeometry& g : {knee_geometry(), mirrored_geometry()}) {
    const double h = 1e-4;
    for (double q : grid(-0.5, 1.2, 35)) {
      const double fd = (g.moment_arm_m(q + h) - g.moment_arm_m(q - h)) / (2 * h);
      EXPECT_NEAR(g.dmoment_arm_dq_m(q), fd, 1e-8) << "q = " << q << " sign = " << g.sign;
      // and from the length alone (second difference; round-off eps x / h^2 ~ 1e-8 at h = 1e-4)
      const double fd2 = (g.length_m(q + h) - 2 * g.length_m(q) + g.length_m(q - h)) / (h * h);
      EXPECT_NEAR(g.dmoment_arm_dq_m(q), fd2, 5e-7) << "q = " << q;
    }
  }
}

TEST(Linkage, NlIsTheInverseMomentArmAndFollowsTheSign) {
  const dm::LinkageGeometry k = knee_geometry(), m = mirrored_geometry();
  for (double q : grid(-0.3, 1.5, 19)) {
    EXPECT_DOUBLE_EQ(k.N_l(q) * k.moment_arm_m(q), 1.0);
    EXPECT_DOUBLE_EQ(m.N_l(q) * m.moment_arm_m(q), 1.0);
    EXPECT_GT(k.moment_arm_m(q), 0.0);  // gamma in (0, pi), sign +1
    EXPECT_LT(m.moment_arm_m(q), 0.0);  // gamma in (0, pi), sign -1: extension turns the joint negative
  }
  // Knee at mid-range (gamma = pi/2): r = ab / sqrt(a^2 + b^2) exactly.
  EXPECT_NEAR(k.moment_arm_m(1.07), 0.30 * 0.052 / std::hypot(0.30, 0.052), 1e-15);
}

// Virtual work: a constant actuator force F through a finite joint motion does the work
// F (x(q1) - x(q0)) = integral of tau = F r(q) over q. Simpson's rule with 2000 panels
// has error (q1-q0)^5 / (180 n^4) max|r''''| ~ 1e-16 m: 1e-12 relative is safe.
TEST(Linkage, VirtualWorkTorqueTimesAngleEqualsForceTimesTravel) {
  const double F = 1234.5;
  for (const dm::LinkageGeometry& g : {knee_geometry(), mirrored_geometry()}) {
    const double q0 = -0.2, q1 = 1.3;
    const int n = 2000;
    const double h = (q1 - q0) / n;
    double w = 0;
    for (int i = 0; i <= n; ++i) {
      const double c = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
      w += c * F * g.moment_arm_m(q0 + i * h);
    }
    w *= h / 3;
    const double work_actuator = F * (g.length_m(q1) - g.length_m(q0));
    EXPECT_NEAR(w, work_actuator, 1e-12 * std::abs(work_actuator)) << "sign " << g.sign;
    // and in the small: tau dq = F dx for one step dq = 1e-6 rad. Truncation dq^2 x'''/24
    // ~ 1e-14 relative; round-off of the length difference eps x / (r dq) ~ 1e-9 relative.
    const double q = 0.4, dq = 1e-6;
    const double tau_dq = F * g.moment_arm_m(q) * dq;
    EXPECT_NEAR(tau_dq, F * (g.length_m(q + dq / 2) - g.length_m(q - dq / 2)), 1e-8 * std::abs(tau_dq));
  }
}

// The closed-form inverse of the length against the forward length, on both test
// geometries and on a linkage whose gamma lies in (2 pi, 3 pi) (the branch k = 1, which
// only the guess can select). Round trip: q -> x(q) - x(0) -> q over gamma in
// [0.5, pi - 0.5] (a linkage's working range stays off its singular ends 0 and pi).
// acos loses eps / sin(gamma) of gamma and the length's round-off eps x / r: 1e-12 rad
// covers both with two orders to spare; a wrong branch is off by at least 1 rad. The
// guess is up to 0.4 rad off, on the same side of the singular ends (the side, not the
// distance, is what selects the branch: Newton's method from it converges there too).
TEST(Linkage, AngleForLengthChangeInvertsTheLengthOnTheGuessedBranch) {
  const dm::LinkageGeometry wound{0.07, 0.25, 2 * kPi + 1.6, 1.0};
  for (const dm::LinkageGeometry& g : {knee_geometry(), mirrored_geometry(), wound}) {
    const double turns = 2 * kPi * std::floor(g.gamma0_rad / (2 * kPi));
    for (double gamma : grid(0.5, kPi - 0.5, 31)) {
      const double q = g.sign * (turns + gamma - g.gamma0_rad);
      const double dx = g.length_m(q) - g.length_m(0.0);
      for (double off : {-0.4, 0.0, 0.4})
        EXPECT_NEAR(g.angle_for_length_change(dx, q + off), q, 1e-12) << "q = " << q << " sign = " << g.sign;
    }
  }
  // Beyond the linkage's reach: the nearest end of its stroke (gamma = pi: the longest).
  const dm::LinkageGeometry k = knee_geometry();
  const double q_pi = kPi - k.gamma0_rad;
  EXPECT_NEAR(k.angle_for_length_change(1.0, 1.0), q_pi, 1e-12);
}

// at(q) is the three single evaluations at once, bit for bit.
TEST(Linkage, AtGivesLengthMomentArmAndItsDerivativeTogether) {
  for (const dm::LinkageGeometry& g : {knee_geometry(), mirrored_geometry()})
    for (double q : grid(-0.5, 1.2, 17)) {
      const dm::LinkagePoint p = g.at(q);
      EXPECT_EQ(p.length_m, g.length_m(q));
      EXPECT_EQ(p.moment_arm_m, g.moment_arm_m(q));
      EXPECT_EQ(p.dmoment_arm_dq_m, g.dmoment_arm_dq_m(q));
    }
}

// The firmware-style table against the exact N_l, on a grid 10x finer than the table's
// and offset from its knots. Measured (200 samples, every DRACO linkage over its range):
// max relative error 6.7e-5 (hip pitch, whose N_l climbs to 51 rad/m at the range ends),
// in the first and last intervals, where the natural spline's zero-curvature end
// condition is wrong (N_l'' is largest there); 20 knots in from the ends it is 5.0e-9
// (the O(h^4) interior error). Bounds: 1e-4 overall, 1e-8 away from the ends; the end
// error falls as h^2 - checked by doubling the samples.
TEST(LinkageTable, InterpolatesTheExactNlOnAFineGrid) {
  const auto acts = dmbd::test::draco_actuators();
  double worst = 0, worst_inner = 0;
  std::string worst_joint;
  for (const auto& a : acts) {
    const auto [lo, hi] = draco_ranges().at(a.joint);
    const dm::LinkageTable t(a.linkage, lo, hi, 200);
    const double h = (hi - lo) / 199;
    double e_all = 0, e_inner = 0;
    for (double q : grid(lo, hi, 1991 * 2 + 1)) {
      const double exact = a.linkage.N_l(q);
      const double e = std::abs(t.N_l(q) - exact) / std::abs(exact);
      e_all = std::max(e_all, e);
      if (q > lo + 20 * h && q < hi - 20 * h) e_inner = std::max(e_inner, e);
    }
    if (e_all > worst) worst_joint = a.joint;
    worst = std::max(worst, e_all);
    worst_inner = std::max(worst_inner, e_inner);
    // At the knots the table is exact (up to rounding).
    for (int i = 0; i < 200; i += 17)
      EXPECT_NEAR(t.N_l(lo + i * h), a.linkage.N_l(lo + i * h), 1e-12 * std::abs(a.linkage.N_l(lo + i * h)));
    // Doubling the samples divides the end error by about 4 (h^2): at least by 3.
    const dm::LinkageTable t2(a.linkage, lo, hi, 399);
    double e2 = 0;
    for (double q : grid(lo, hi, 1991 * 2 + 1))
      e2 = std::max(e2, std::abs(t2.N_l(q) - a.linkage.N_l(q)) / std::abs(a.linkage.N_l(q)));
    EXPECT_LT(e2, e_all / 3) << a.joint;
  }
  std::printf("[ measured ] LinkageTable(200): max relative error %.3g (%s), %.3g away from the ends\n", worst,
              worst_joint.c_str(), worst_inner);
  EXPECT_LT(worst, 1e-4);
  EXPECT_LT(worst_inner, 1e-8);
}

TEST(LinkageTable, ClampsOutsideItsRange) {
  const dm::LinkageGeometry g = knee_geometry();
  const dm::LinkageTable t(g, 0.0, 2.14, 50);
  EXPECT_DOUBLE_EQ(t.N_l(-1.0), t.N_l(0.0));
  EXPECT_DOUBLE_EQ(t.N_l(5.0), t.N_l(2.14));
  EXPECT_NEAR(t.N_l(0.0), g.N_l(0.0), 1e-12 * g.N_l(0.0));
  EXPECT_EQ(t.values().size(), 50u);
  EXPECT_DOUBLE_EQ(t.q_lo(), 0.0);
  EXPECT_DOUBLE_EQ(t.q_hi(), 2.14);
}

TEST(LinkageTable, TwoSamplesInterpolateLinearly) {
  const dm::LinkageGeometry g = knee_geometry();
  const dm::LinkageTable t(g, 0.5, 1.5, 2);
  EXPECT_NEAR(t.N_l(0.75), 0.75 * g.N_l(0.5) + 0.25 * g.N_l(1.5), 1e-12);
}

TEST(LinkageTable, RejectsSingularRangesAndBadArguments) {
  const dm::LinkageGeometry g = knee_geometry();  // gamma = 0.5008 + q: singular at q = -0.5008
  EXPECT_THROW(dm::LinkageTable(g, -0.6, 1.0, 100), dm::ModelError);
  EXPECT_THROW(dm::LinkageTable(g, 0.0, kPi - 0.4, 100), dm::ModelError);  // gamma reaches pi
  EXPECT_THROW(dm::LinkageTable(g, 0.0, 1.0, 1), dm::ModelError);
  EXPECT_THROW(dm::LinkageTable(g, 1.0, 1.0, 10), dm::ModelError);
  try {
    dm::LinkageTable(g, -0.6, 1.0, 100);
  } catch (const dm::ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("singular"), std::string::npos) << e.what();
  }
}

// DRACO's linkages over this project's joint ranges: travel (facts: roughly 0.09-0.15 m),
// moment arms, distance from the singular configurations, and the mirror symmetry.
TEST(DracoLinkage, TravelMomentArmAndMarginOverEachJointRange) {
  const auto acts = dmbd::test::draco_actuators();
  ASSERT_EQ(acts.size(), 10u);
  for (const auto& a : acts) {
    const auto [lo, hi] = draco_ranges().at(a.joint);
    const dm::LinkageGeometry& g = a.linkage;
    const double travel = std::abs(g.length_m(hi) - g.length_m(lo));
    double r_min = 1e9, r_max = 0, x_min = 1e9;
    for (double q : grid(lo, hi, 2001)) {
      r_min = std::min(r_min, std::abs(g.moment_arm_m(q)));
      r_max = std::max(r_max, std::abs(g.moment_arm_m(q)));
      x_min = std::min(x_min, g.length_m(q));
    }
    const double r_mid = std::abs(g.moment_arm_m(0.5 * (lo + hi)));
    const double g_lo = g.gamma0_rad + g.sign * lo, g_hi = g.gamma0_rad + g.sign * hi;
    const double margin = std::min({g_lo, g_hi, kPi - g_lo, kPi - g_hi});
    std::printf(
        "[ measured ] %-11s travel %.4f m, moment arm mid %.4f min %.4f max %.4f m, N_l mid %.2f max %.2f rad/m, "
        "gamma [%.3f, %.3f] (margin %.3f rad), length %.3f..%.3f m\n",
        a.joint.c_str(), travel, r_mid, r_min, r_max, 1 / r_mid, 1 / r_min, std::min(g_lo, g_hi), std::max(g_lo, g_hi),
        margin, x_min, x_min + travel);
    EXPECT_GE(travel, 0.09) << a.joint;
    EXPECT_LE(travel, 0.15) << a.joint;
    // Moment arm: 2-9 cm everywhere (>= 2 cm keeps N_l <= 51 rad/m at the range ends);
    // hip roll needs ~8 cm at mid-range to make 0.09 m over only 1.19 rad (travel <= r_max dq).
    EXPECT_GE(r_min, 0.019) << a.joint;
    EXPECT_LE(r_max, 0.09) << a.joint;
    EXPECT_GE(r_mid, 0.03) << a.joint;
    // gamma stays inside (0, pi) with at least 0.4 rad (23 deg) to spare.
    EXPECT_GE(margin, 0.4) << a.joint;
    // The retracted actuator must hold its stroke plus the screw and motor: >= 1.8x travel.
    EXPECT_GE(x_min, 1.8 * travel) << a.joint;
    // The table over the range builds (not singular).
    EXPECT_NO_THROW(dm::LinkageTable(g, lo, hi, 200)) << a.joint;
  }
}

TEST(DracoLinkage, RightLegMirrorsTheLeft) {
  const auto acts = dmbd::test::draco_actuators();
  auto find = [&](const std::string& j) -> const dm::ActuatorParams& {
    auto it = std::find_if(acts.begin(), acts.end(), [&](const dm::ActuatorParams& p) { return p.joint == j; });
    EXPECT_NE(it, acts.end()) << j;
    return *it;
  };
  for (const std::string side_free : {"hip_yaw", "hip_roll", "hip_pitch", "knee", "ankle"}) {
    const auto& l = find("l_" + side_free);
    const auto& r = find("r_" + side_free);
    // roll and yaw axes flip under the y mirror (q_right = -q_left), pitch axes do not.
    const bool flips = side_free == "hip_yaw" || side_free == "hip_roll";
    const auto [lo, hi] = draco_ranges().at(l.joint);
    for (double q : grid(lo, hi, 41)) {
      const double q_r = flips ? -q : q;
      EXPECT_NEAR(r.linkage.length_m(q_r), l.linkage.length_m(q), 1e-15) << side_free;
      EXPECT_NEAR(r.linkage.moment_arm_m(q_r), flips ? -l.linkage.moment_arm_m(q) : l.linkage.moment_arm_m(q), 1e-15)
          << side_free;
    }
    EXPECT_EQ(r.kind, l.kind);
    EXPECT_EQ(r.N_m_rad_per_m, l.N_m_rad_per_m);
    EXPECT_EQ(r.K_s_N_per_m, l.K_s_N_per_m);
    EXPECT_EQ(r.B_s_Ns_per_m, l.B_s_Ns_per_m);
    EXPECT_EQ(r.B_l_Ns_per_m, l.B_l_Ns_per_m);
    EXPECT_EQ(r.M_r_kg, l.M_r_kg);
    EXPECT_EQ(r.k_tau_Nm_per_A, l.k_tau_Nm_per_A);
    EXPECT_EQ(r.current_limit_A, l.current_limit_A);
    EXPECT_EQ(r.force_limit_N, l.force_limit_N);
    EXPECT_EQ(r.thermal.R_winding_ohm, l.thermal.R_winding_ohm);
    EXPECT_EQ(r.thermal.R_ha_liquid_K_per_W, l.thermal.R_ha_liquid_K_per_W);
    EXPECT_EQ(r.potentiometer.lo, flips ? -l.potentiometer.hi : l.potentiometer.lo);
    EXPECT_EQ(r.potentiometer.hi, flips ? -l.potentiometer.lo : l.potentiometer.hi);
  }
}
