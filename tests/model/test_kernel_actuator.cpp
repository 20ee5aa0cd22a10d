// One actuator's terms in reduced coordinates (model/src/actuator_terms.hpp), the knee
// RFSEA and the ankle FSEA of DRACO's table, against independent computations:
//   - M against the Hessian of the rotor's kinetic energy T(q, q', s') in (q', s'), and
//     the velocity-product force against Lagrange's equations evaluated from T by finite
//     differences (damping, springs and current zeroed);
//   - the power balance V.(f - M Vdot) = motor power - dissipation - dU/dt - dT/dt along
//     a motion, with the time derivatives by finite differences;
//   - D and K in closed form from the raw parameters and against finite differences of f;
//   - the readings against LinkageGeometry and against each other (d/dt motor_angle);
//   - the locked-output plant (q' = 0) against the raw parameters and docs/model.md's table.
#include "actuator_terms.hpp"
#include "robot_files.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

namespace dmbd::model::detail {
namespace {

const ActuatorParams& actuator(const std::string& joint) {
  static const std::vector<ActuatorParams> table = dmbd::test::draco_actuators();
  const auto it = std::find_if(table.begin(), table.end(), [&](const ActuatorParams& p) { return p.joint == joint; });
  if (it == table.end()) throw std::runtime_error("no actuator for " + joint);
  return *it;
}

// A state of each actuator inside its joint range, moving, with the elastomer loaded.
struct State {
  double q, qd, s, sd, i;
};

struct Case {
  const char* joint;
  ActuatorKind kind;
  State x;
};

const Case kCases[] = {
    {"l_knee", ActuatorKind::RFSEA, {1.2, 3.0, 2e-4, 0.02, 5.0}},
    {"l_ankle", ActuatorKind::FSEA, {-0.3, -4.0, -1.5e-4, 0.03, -3.0}},
};

// The conservative, undriven actuator: only the rotor's inertia remains.
ActuatorParams inertia_only(ActuatorParams p) {
  p.B_m_Nms = p.B_s_Ns_per_m = p.B_l_Ns_per_m = p.K_s_N_per_m = 0;
  return p;
}

ActuatorParams undamped(ActuatorParams p) {
  p.B_m_Nms = p.B_s_Ns_per_m = p.B_l_Ns_per_m = 0;
  return p;
}

double max_abs(const Eigen::MatrixXd& m) { return m.cwiseAbs().maxCoeff(); }

// dT/dV at (q, V) by central differences. T is quadratic in V, so any step is exact up
// to rounding; hv = 0.5 keeps rounding at eps T / hv.
Eigen::Vector2d dT_dV(const ActuatorParams& p, double q, const Eigen::Vector2d& V) {
  const double hv = 0.5;
  Eigen::Vector2d g;
  for (int j = 0; j < 2; ++j) {
    const Eigen::Vector2d d = hv * Eigen::Vector2d::Unit(j);
    const Eigen::Vector2d a = V + d, b = V - d;
    g[j] = (actuator_kinetic_energy(p, q, a[0], a[1]) - actuator_kinetic_energy(p, q, b[0], b[1])) / (2 * hv);
  }
  return g;
}

TEST(ActuatorLagrangian, MassMatrixIsTheHessianOfTheKineticEnergy) {
  for (const Case& k : kCases) {
    const ActuatorParams& p = actuator(k.joint);
    ASSERT_EQ(p.kind, k.kind);
    const State& x = k.x;
    const ActuatorTerms t = actuator_terms(p, x.q, x.qd, x.s, x.sd, x.i);
    // Hessian as the difference of gradients: exact for a quadratic, step 0.5.
    Eigen::Matrix2d H;
    const double hv = 0.5;
    for (int j = 0; j < 2; ++j) {
      const Eigen::Vector2d d = hv * Eigen::Vector2d::Unit(j);
      H.col(j) = (dT_dV(p, x.q, Eigen::Vector2d(x.qd, x.sd) + d) - dT_dV(p, x.q, Eigen::Vector2d(x.qd, x.sd) - d)) /
                 (2 * hv);
    }
    const double e = max_abs(H - t.M) / max_abs(t.M);
    EXPECT_LT(e, 1e-10) << k.joint;  // rounding: eps T / hv^2 ~ 1e-15 of T (~10 J) against M ~ 1..700
    std::printf("%s: M vs Hessian of T: %.2g relative (M = [%.5g %.5g; %.5g %.5g])\n", k.joint, e, t.M(0, 0),
                t.M(0, 1), t.M(1, 0), t.M(1, 1));
  }
}

// The velocity-product force from Lagrange's equations of T by finite differences:
// f_vp = -(d/dt dT/dV - dT/dQ) at Vdot = 0, d/dt dT/dV = (d2T/dV dQ) V. T does not
// depend on s (actuator_kinetic_energy takes no s), so only d/dq enters.
Eigen::Vector2d lagrange_velocity_force(const ActuatorParams& p, const State& x) {
  const double hq = 1e-5;  // truncation hq^2/6 x (r'''/r) ~ 2e-11; rounding eps T / (0.5 hq) ~ 4e-11 of T
  const Eigen::Vector2d V(x.qd, x.sd);
  const Eigen::Vector2d d2T_dVdq = (dT_dV(p, x.q + hq, V) - dT_dV(p, x.q - hq, V)) / (2 * hq);
  const double dT_dq = (actuator_kinetic_energy(p, x.q + hq, x.qd, x.sd) -
                        actuator_kinetic_energy(p, x.q - hq, x.qd, x.sd)) / (2 * hq);
  return -(d2T_dVdq * x.qd - Eigen::Vector2d(dT_dq, 0.0));
}

TEST(ActuatorLagrangian, VelocityProductForceMatchesLagrangesEquations) {
  for (const Case& k : kCases) {
    const ActuatorParams p = inertia_only(actuator(k.joint));
    const State& x = k.x;
    const Eigen::Vector2d f = actuator_terms(p, x.q, x.qd, x.s, x.sd, 0.0).f;
    const Eigen::Vector2d fl = lagrange_velocity_force(p, x);
    const double e = (f - fl).cwiseAbs().maxCoeff() / fl.cwiseAbs().maxCoeff();
    // Finite-difference error ~1e-10 of T per unit q' (T ~ 10 J, f_vp ~ 10-1000 N): 1e-7.
    EXPECT_LT(e, 1e-7) << k.joint;
    std::printf("%s: velocity-product force [%.6g %.6g] N vs Lagrange by differences [%.6g %.6g]: %.2g relative\n",
                k.joint, f[0], f[1], fl[0], fl[1], e);
  }
}

// Fourth-order central difference of g(t) at t = 0.
template <class G>
double time_derivative(G g, double h) {
  return (-g(2 * h) + 8 * g(h) - 8 * g(-h) + g(-2 * h)) / (12 * h);
}

// V.(f - M Vdot) minus (motor power - dissipation - dU/dt - dT/dt) along
// Q(t) = Q + V t + Vdot t^2/2, relative to the largest of the terms.
double power_balance_error(const ActuatorParams& p, const State& x, const Eigen::Vector2d& Vdot) {
  const ActuatorTerms t = actuator_terms(p, x.q, x.qd, x.s, x.sd, x.i);
  const Eigen::Vector2d V(x.qd, x.sd);
  const double lhs = V.dot(t.f - t.M * Vdot);
  auto T = [&](double tt) {
    return actuator_kinetic_energy(p, x.q + x.qd * tt + 0.5 * Vdot[0] * tt * tt, x.qd + Vdot[0] * tt,
                                   x.sd + Vdot[1] * tt);
  };
  auto U = [&](double tt) { return actuator_potential_energy(p, x.s + x.sd * tt + 0.5 * Vdot[1] * tt * tt); };
  // Step 1e-4 s: the truncation h^4/30 T^(5) is measured to fall as h^4 from 7e-10 of
  // the power at h = 1e-3 (knee, Vdot = (-20, 3)) to 2e-13 here; rounding eps T / h is
  // 2e-11 W against ~200 W. U is a quartic in t: exact.
  const double h = 1e-4, dT = time_derivative(T, h), dU = time_derivative(U, h);
  const double thetad = p.N_m_rad_per_m * (p.linkage.moment_arm_m(x.q) * x.qd + x.sd);  // rotor speed
  const double r = p.linkage.moment_arm_m(x.q);
  const double motor = p.efficiency * p.k_tau_Nm_per_A * x.i * thetad;
  const double loss = p.B_m_Nms * thetad * thetad + p.B_s_Ns_per_m * x.sd * x.sd +
                      p.B_l_Ns_per_m * r * r * x.qd * x.qd;
  const double rhs = motor - loss - dU - dT;
  const double scale = std::max({std::abs(lhs), std::abs(motor), std::abs(loss), std::abs(dU), std::abs(dT)});
  return std::abs(lhs - rhs) / scale;
}

TEST(ActuatorEnergy, PowerBalanceAlongAMotion) {
  // Lagrange: d/dt dT/dV - dT/dQ = M Vdot - f_vp, and V.(d/dt dT/dV - dT/dQ) = dT/dt
  // (T is quadratic in V), so V.(f - M Vdot) = V.(f - f_vp) - dT/dt: the velocity-product
  // force does work, V.f_vp = -1/2 V^T Mdot V, and it is what closes the balance.
  for (const Case& k : kCases) {
    for (const Eigen::Vector2d& Vdot : {Eigen::Vector2d(0, 0), Eigen::Vector2d(-20.0, 3.0)}) {
      const double e0 = power_balance_error(undamped(actuator(k.joint)), k.x, Vdot);
      const double e1 = power_balance_error(actuator(k.joint), k.x, Vdot);
      EXPECT_LT(e0, 1e-9) << k.joint;
      EXPECT_LT(e1, 1e-9) << k.joint;
      std::printf("%s, Vdot = [%g %g]: power balance %.2g relative undamped, %.2g with damping\n", k.joint,
                  Vdot[0], Vdot[1], e0, e1);
    }
    // The velocity-product force's power, nonzero: -J' r' q'^2 w.
    const ActuatorParams p = inertia_only(actuator(k.joint));
    const Eigen::Vector2d fvp = actuator_terms(p, k.x.q, k.x.qd, k.x.s, k.x.sd, 0.0).f;
    std::printf("%s: V.f_vp = %.6g W\n", k.joint, Eigen::Vector2d(k.x.qd, k.x.sd).dot(fvp));
  }
}

// -df/dQ and -df/dV by central differences.
void finite_difference_jacobians(const ActuatorParams& p, const State& x, Eigen::Matrix2d& Kfd, Eigen::Matrix2d& Dfd) {
  auto f = [&](double q, double qd, double s, double sd) { return actuator_terms(p, q, qd, s, sd, x.i).f; };
  const double hq = 1e-6, hs = 1e-5, hqd = 0.1, hsd = 0.01;
  Kfd.col(0) = -(f(x.q + hq, x.qd, x.s, x.sd) - f(x.q - hq, x.qd, x.s, x.sd)) / (2 * hq);
  Kfd.col(1) = -(f(x.q, x.qd, x.s + hs, x.sd) - f(x.q, x.qd, x.s - hs, x.sd)) / (2 * hs);
  Dfd.col(0) = -(f(x.q, x.qd + hqd, x.s, x.sd) - f(x.q, x.qd - hqd, x.s, x.sd)) / (2 * hqd);
  Dfd.col(1) = -(f(x.q, x.qd, x.s, x.sd + hsd) - f(x.q, x.qd, x.s, x.sd - hsd)) / (2 * hsd);
}

TEST(ActuatorJacobians, ClosedFormAndFiniteDifferences) {
  for (const Case& k : kCases) {
    const ActuatorParams& p = actuator(k.joint);
    const State& x = k.x;
    const ActuatorTerms t = actuator_terms(p, x.q, x.qd, x.s, x.sd, x.i);
    const double r = p.linkage.moment_arm_m(x.q), dr = p.linkage.dmoment_arm_dq_m(x.q);
    const double Bp = p.B_m_Nms * p.N_m_rad_per_m * p.N_m_rad_per_m, Jp = p.J_m_kgm2 * p.N_m_rad_per_m * p.N_m_rad_per_m;
    const Eigen::Vector2d a(r, 1.0);
    Eigen::Matrix2d D = Bp * a * a.transpose();
    D(0, 0) += p.B_l_Ns_per_m * r * r;
    D(1, 1) += p.B_s_Ns_per_m;
    EXPECT_LT(max_abs(t.D - D) / max_abs(D), 1e-14) << k.joint;  // the same products: rounding
    EXPECT_EQ(t.K(1, 1), p.K_s_N_per_m);
    EXPECT_EQ(t.K(0, 0), 0.0);  // geometric stiffness (r') kept out by design
    EXPECT_EQ(t.K(0, 1), 0.0);
    EXPECT_EQ(t.K(1, 0), 0.0);

    Eigen::Matrix2d Kfd, Dfd;
    finite_difference_jacobians(p, x, Kfd, Dfd);
    // f is linear in s and s' and quadratic in q': those differences are exact up to
    // rounding, eps |f| / h ~ 1e-9 N s/m against D ~ 1e3..3e4 and 1e-7 N/m against K_s ~ 1e6.
    const double es = (Kfd.col(1) - t.K.col(1)).cwiseAbs().maxCoeff() / p.K_s_N_per_m;
    const double esd = (Dfd.col(1) - t.D.col(1)).cwiseAbs().maxCoeff() / max_abs(t.D);
    // Column q': D leaves out the gyroscopic part 2 J' r' q' a of the velocity products.
    const Eigen::Vector2d gyro = 2 * Jp * dr * x.qd * a;
    const double eqd = (Dfd.col(0) - t.D.col(0) - gyro).cwiseAbs().maxCoeff() / max_abs(t.D);
    EXPECT_LT(es, 1e-10) << k.joint;
    EXPECT_LT(esd, 1e-10) << k.joint;
    EXPECT_LT(eqd, 1e-10) << k.joint;
    std::printf("%s: -df/ds, -df/ds' vs K, D columns: %.2g, %.2g; -df/dq' vs D(:,0) + 2 J' r' q' a: %.2g "
                "(omitted: gyroscopic |%.4g| N s/m, geometric -df/dq |%.4g| N/rad vs K_s %.4g N/m)\n",
                k.joint, es, esd, eqd, gyro.cwiseAbs().maxCoeff(), Kfd.col(0).cwiseAbs().maxCoeff(), p.K_s_N_per_m);
  }
}

TEST(ActuatorJacobians, DampingColumnMatchesAtRest) {
  // At q' = 0 the gyroscopic part vanishes and D is the whole -df/dV.
  for (const Case& k : kCases) {
    const ActuatorParams& p = actuator(k.joint);
    State x = k.x;
    x.qd = 0;
    const ActuatorTerms t = actuator_terms(p, x.q, x.qd, x.s, x.sd, x.i);
    Eigen::Matrix2d Kfd, Dfd;
    finite_difference_jacobians(p, x, Kfd, Dfd);
    const double e = max_abs(Dfd - t.D) / max_abs(t.D);
    EXPECT_LT(e, 1e-10) << k.joint;  // exact differences (quadratic and linear in V): rounding
    std::printf("%s at q' = 0: D vs -df/dV %.2g relative\n", k.joint, e);
  }
}

TEST(ActuatorReadings, MotorAngleVelocityAndEnergies) {
  for (const Case& k : kCases) {
    const ActuatorParams& p = actuator(k.joint);
    const State& x = k.x;
    const LinkageGeometry& g = p.linkage;
    const double N = p.N_m_rad_per_m;
    const double theta = N * (g.length_m(x.q) - g.length_m(0.0) + x.s);
    const double thetad = N * (g.moment_arm_m(x.q) * x.qd + x.sd);
    EXPECT_LT(std::abs(motor_angle(p, x.q, x.s) - theta), 1e-13 * std::max(1.0, std::abs(theta)));
    EXPECT_LT(std::abs(motor_velocity(p, x.q, x.qd, x.sd) - thetad), 1e-13 * std::abs(thetad));
    // Along q(t) = q + q' t, s(t) = s + s' t: truncation h^2/6 theta''' ~ 1e-11 relative,
    // rounding eps theta / h ~ 3e-9 rad/s against ~1e3 rad/s.
    const double h = 1e-5;
    const double fd = (motor_angle(p, x.q + x.qd * h, x.s + x.sd * h) - motor_angle(p, x.q - x.qd * h, x.s - x.sd * h)) /
                      (2 * h);
    const double ev = std::abs(fd - motor_velocity(p, x.q, x.qd, x.sd)) / std::abs(fd);
    EXPECT_LT(ev, 1e-8) << k.joint;
    // The rotor's kinetic energy 1/2 J_m theta_m'^2 (theta_m' from the difference: 2e-8).
    const double T = 0.5 * p.J_m_kgm2 * fd * fd;
    const double eT = std::abs(actuator_kinetic_energy(p, x.q, x.qd, x.sd) - T) / T;
    EXPECT_LT(eT, 2e-8) << k.joint;
    // The elastomer's energy: its derivative is the spring force K_s s (quadratic: exact).
    const double hs = 1e-5;
    const double dU = (actuator_potential_energy(p, x.s + hs) - actuator_potential_energy(p, x.s - hs)) / (2 * hs);
    EXPECT_LT(std::abs(dU - p.K_s_N_per_m * x.s), 1e-8 * p.K_s_N_per_m * std::abs(x.s)) << k.joint;
    std::printf("%s: theta_m %.6g rad, theta_m' %.6g rad/s, d/dt theta_m vs motor_velocity %.2g, T vs 1/2 J_m "
                "theta_m'^2 %.2g\n",
                k.joint, theta, thetad, ev, eT);
  }
}

// Natural frequency (Hz) and damping ratio of m s'' + c s' + k s.
void mode(double m, double c, double k, double& hz, double& zeta) {
  hz = std::sqrt(k / m) / (2 * M_PI);
  zeta = c / (2 * std::sqrt(k * m));
}

TEST(ActuatorLockedOutput, ReducesToThePapersPlant) {
  // docs/model.md section 1, "Locked output": knee 18.47 Hz / 0.1515, ankle 17.73 Hz /
  // 0.141, printed to 4 and 3-4 figures (tolerance half a unit in the last digit).
  struct Expected {
    const char* joint;
    double hz, dhz, zeta, dzeta;
  };
  for (const Expected& e : {Expected{"l_knee", 18.47, 0.005, 0.1515, 5e-5}, Expected{"l_ankle", 17.73, 0.005, 0.141, 5e-4}}) {
    const ActuatorParams& p = actuator(e.joint);
    const double N = p.N_m_rad_per_m, Jp = p.J_m_kgm2 * N * N, Bp = p.B_m_Nms * N * N;
    const double s = 3e-4, sd = -0.04, i = 7.0;
    const ActuatorTerms t = actuator_terms(p, 0.4, 0.0, s, sd, i);
    EXPECT_LT(std::abs(t.M(1, 1) - Jp), 1e-14 * Jp) << e.joint;  // J' only: the housing is the tree's
    const double f1 = p.efficiency * p.k_tau_Nm_per_A * N * i - Bp * sd - p.K_s_N_per_m * s - p.B_s_Ns_per_m * sd;
    EXPECT_LT(std::abs(t.f[1] - f1), 1e-12 * (std::abs(f1) + p.K_s_N_per_m * std::abs(s))) << e.joint;
    // (M_r + J') s'' + (B_s + B') s' + K_s s = eta k_tau N_m i, M_r = 0 for the FSEA.
    double hz, zeta;
    mode(p.M_r_kg + t.M(1, 1), t.D(1, 1), t.K(1, 1), hz, zeta);
    EXPECT_NEAR(hz, e.hz, e.dhz) << e.joint;
    EXPECT_NEAR(zeta, e.zeta, e.dzeta) << e.joint;
    std::printf("%s locked output: f_1 %.6g N (expected %.6g), %.4f Hz, damping ratio %.5f\n", e.joint, t.f[1], f1,
                hz, zeta);
  }
}

}  // namespace
}  // namespace dmbd::model::detail

// ---- the geared rotary kinds ------------------------------------------------------------

namespace dmbd::model::detail {
namespace {

ActuatorParams geared(ActuatorKind kind) {
  ActuatorParams p;
  p.kind = kind;
  p.J_m_kgm2 = 1.2e-5;
  p.B_m_Nms = 1e-5;
  p.N_m_rad_per_m = 100;
  p.k_tau_Nm_per_A = 0.05;
  p.efficiency = 0.8;
  p.K_s_N_per_m = 350;
  p.B_s_Ns_per_m = 0.8;
  p.viscous_friction_Nms = 0.1;
  p.coulomb_friction_Nm = 0.4;
  p.coulomb_velocity_rad_s = 2e-3;
  p.B_l_Ns_per_m = 0.05;
  return p;
}

// M = J' a a^T with a = (1, 1) (ROTARY_SEA) or (1, 0) (ROTARY); f from the closed form
// of docs/model.md; D = -df/dV by central differences inside the Coulomb cone (where the
// slope tau_c / w_s is part of D) and beyond it (where it is not); K = -df/dQ.
TEST(RotaryTerms, ClosedFormAndJacobians) {
  for (ActuatorKind kind : {ActuatorKind::ROTARY, ActuatorKind::ROTARY_SEA}) {
    const ActuatorParams p = geared(kind);
    const bool sea = kind == ActuatorKind::ROTARY_SEA;
    const double Jp = p.J_m_kgm2 * 1e4, Bp = p.B_m_Nms * 1e4, i = 3.0, q = 0.4;
    for (const double w_target : {5e-4, 0.3}) {  // inside and beyond w_s = 2e-3
      const double s = sea ? 0.01 : 0.0, sd = sea ? -0.2 : 0.0, qd = w_target - sd;
      const ActuatorTerms t = actuator_terms(p, q, qd, s, sd, i);
      const Eigen::Vector2d a(1.0, sea ? 1.0 : 0.0);
      const double w = qd + sd;
      const double coulomb = -0.4 * std::clamp(w / 2e-3, -1.0, 1.0);
      Eigen::Vector2d f = (0.8 * 0.05 * 100 * i - (Bp + 0.1) * w + coulomb) * a;
      f[0] -= 0.05 * qd;
      if (sea) f[1] -= 350 * s + 0.8 * sd;
      EXPECT_LT(max_abs(t.M - Jp * a * a.transpose()), 1e-15);
      EXPECT_LT((t.f - f).cwiseAbs().maxCoeff(), 1e-12 * f.cwiseAbs().maxCoeff());
      // Differences: f is piecewise linear in V, so a step inside one piece (1e-5 of
      // w_s away from its ends) is exact up to rounding.
      const double h = 1e-7;
      Eigen::Matrix2d Dfd = Eigen::Matrix2d::Zero();
      Dfd.col(0) = -(actuator_terms(p, q, qd + h, s, sd, i).f - actuator_terms(p, q, qd - h, s, sd, i).f) / (2 * h);
      if (sea) Dfd.col(1) = -(actuator_terms(p, q, qd, s, sd + h, i).f - actuator_terms(p, q, qd, s, sd - h, i).f) / (2 * h);
      EXPECT_LT(max_abs(Dfd - t.D), 1e-6 * max_abs(t.D)) << "w = " << w;
      const bool inside = std::abs(w) < 2e-3;
      EXPECT_EQ(t.D(0, 0), Bp + 0.1 + (inside ? 0.4 / 2e-3 : 0.0) + 0.05) << "w = " << w;
      Eigen::Matrix2d Kfd = Eigen::Matrix2d::Zero();
      if (sea) Kfd.col(1) = -(actuator_terms(p, q, qd, s + 1e-5, sd, i).f - actuator_terms(p, q, qd, s - 1e-5, sd, i).f) / 2e-5;
      Kfd.col(0) = -(actuator_terms(p, q + 1e-5, qd, s, sd, i).f - actuator_terms(p, q - 1e-5, qd, s, sd, i).f) / 2e-5;
      EXPECT_LT(max_abs(Kfd - t.K), 1e-6 * 350) << "w = " << w;
      EXPECT_EQ(t.K(1, 1), sea ? 350.0 : 0.0);
    }
  }
}

// The readings and energies of a gear: theta_m = N (q + s), theta_m' = N (q' + s'),
// T = 1/2 J_m theta_m'^2, U = 1/2 K s^2 (ROTARY: none).
TEST(RotaryTerms, ReadingsAndEnergies) {
  const ActuatorParams sea = geared(ActuatorKind::ROTARY_SEA), rigid = geared(ActuatorKind::ROTARY);
  EXPECT_DOUBLE_EQ(motor_angle(sea, 0.3, 0.01), 100 * 0.31);
  EXPECT_DOUBLE_EQ(motor_velocity(sea, 0.3, 2.0, -0.5), 150.0);
  EXPECT_DOUBLE_EQ(actuator_kinetic_energy(sea, 0.3, 2.0, -0.5), 0.5 * 1.2e-5 * 150.0 * 150.0);
  EXPECT_DOUBLE_EQ(actuator_potential_energy(sea, 0.01), 0.5 * 350 * 1e-4);
  EXPECT_EQ(actuator_potential_energy(rigid, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(motor_angle(rigid, 0.3, 0.0), 30.0);
}

}  // namespace
}  // namespace dmbd::model::detail
