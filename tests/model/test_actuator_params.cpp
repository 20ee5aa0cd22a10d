// DRACO's actuator table (robots/draco/actuators.yaml) against its sources, and the
// locked-output current -> force transfer function
//   P_inf(s) = k_tau N_m K_r / ((M_r + J_m N_m^2) s^2 + (B_r + B_m N_m^2) s + K_r)
// (docs/paper-actuators.md section 1, "M_l -> inf") checked against a time-domain
// integration of the actuator's own equations in motor coordinates.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "robot_files.hpp"
#include "dmbd/blocks/transfer_function.hpp"
#include "dmbd/model/actuator.hpp"

namespace dm = dmbd::model;
namespace db = dmbd::blocks;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::map<std::string, dm::ActuatorParams> by_joint() {
  std::map<std::string, dm::ActuatorParams> m;
  for (const auto& a : dmbd::test::draco_actuators()) m[a.joint] = a;
  return m;
}

// ---- the locked-output plant, integrated -------------------------------------------
// Motor coordinates, the output rod held still (x_l = 0), the screw rigid:
//   rotor      J_m th'' + B_m th' = k_tau i - F_s / N_m        (screw torque F_s/N_m: virtual work, N_m in rad/m)
//   elastomer  M_r x''  + B_s x' + K_s x = F_s                  (RFSEA: housing on the elastomer;
//                                                                FSEA: M_r = 0, nut on the spring)
//   screw      th'' / N_m - x'' = 0                              (th / N_m = x_l + x = x)
// solved for (th'', x'', F_s) at every stage (nothing is eliminated by hand), RK4 on
// (th, th', x, x'); sensed force F = K_s x. RK4 preserves the linear screw constraint
// exactly, so there is no drift. Returns the gain (N/A) and phase (rad) of F for
// i = sin(w t) by projecting F on sin and cos over whole periods after the transient.
struct Response {
  double gain, phase;
};

Response locked_output_response(const dm::ActuatorParams& p, double f_hz) {
  const double J = p.J_m_kgm2, Bm = p.B_m_Nms, N = p.N_m_rad_per_m, M = p.M_r_kg, B = p.B_s_Ns_per_m, K = p.K_s_N_per_m,
               kt = p.k_tau_Nm_per_A;
  Eigen::Matrix3d A;
  A << J, 0, 1.0 / N,  //
      0, M, -1,        //
      1.0 / N, -1, 0;
  const Eigen::PartialPivLU<Eigen::Matrix3d> lu(A);
  const double w = 2 * kPi * f_hz;
  using State = Eigen::Vector4d;  // th, th', x, x'
  auto f = [&](double t, const State& y) {
    const Eigen::Vector3d rhs(kt * std::sin(w * t) - Bm * y[1], -B * y[3] - K * y[2], 0.0);
    const Eigen::Vector3d acc = lu.solve(rhs);
    return State(y[1], acc[0], y[3], acc[1]);
  };
  // Transient: the slowest free mode decays as exp(-b t / 2m) with m = M_r + J N^2,
  // b = B_s + B_m N^2: wait 25 of its time constants (exp(-25) = 1.4e-11).
  const double m = M + J * N * N, b = B + Bm * N * N;
  const double settle_s = 25.0 / (b / (2 * m));
  const int steps_per_period = 2000, measure_periods = 4;
  const int settle_periods = static_cast<int>(std::ceil(settle_s * f_hz));
  const double dt = 1.0 / (f_hz * steps_per_period);
  State y = State::Zero();
  double s = 0, c = 0;
  const long total = static_cast<long>(settle_periods + measure_periods) * steps_per_period;
  const long start = static_cast<long>(settle_periods) * steps_per_period;
  for (long k = 0; k < total; ++k) {
    const double t = k * dt;
    if (k >= start) {  // rectangle rule over whole periods: exact for a sinusoid
      s += K * y[2] * std::sin(w * t);
      c += K * y[2] * std::cos(w * t);
    }
    const State k1 = f(t, y), k2 = f(t + dt / 2, y + dt / 2 * k1), k3 = f(t + dt / 2, y + dt / 2 * k2),
                k4 = f(t + dt, y + dt * k3);
    y += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  const double n = static_cast<double>(total - start);
  s *= 2 / n;
  c *= 2 / n;  // F = G sin(wt + phi) = G cos(phi) sin + G sin(phi) cos
  return {std::hypot(s, c), std::atan2(c, s)};
}

// The formula, built from ActuatorParams' reflected quantities (a different code path
// from the integration above, which uses J_m, B_m and N_m directly).
db::TransferFunction p_inf(const dm::ActuatorParams& p) {
  const double M_r = p.kind == dm::ActuatorKind::RFSEA ? p.M_r_kg : 0.0;
  return db::TransferFunction::from_descending(
      {p.force_per_amp_N_per_A() * p.K_s_N_per_m},
      {M_r + p.reflected_mass_kg(), p.B_s_Ns_per_m + p.reflected_damping_Ns_per_m(), p.K_s_N_per_m});
}

}  // namespace

TEST(DracoActuators, TenJointsWithTheirKinds) {
  const auto acts = dmbd::test::draco_actuators();
  ASSERT_EQ(acts.size(), 10u);
  const std::vector<std::string> expected = {"l_hip_yaw", "l_hip_roll", "l_hip_pitch", "l_knee", "l_ankle",
                                             "r_hip_yaw", "r_hip_roll", "r_hip_pitch", "r_knee", "r_ankle"};
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(acts[i].joint, expected[i]);
    const bool ankle = expected[i].find("ankle") != std::string::npos;
    EXPECT_EQ(acts[i].kind, ankle ? dm::ActuatorKind::FSEA : dm::ActuatorKind::RFSEA) << expected[i];
    if (ankle) {
      EXPECT_EQ(acts[i].M_r_kg, 0.0);
    }
    EXPECT_DOUBLE_EQ(acts[i].efficiency, 0.9);  // facts: drive efficiency about 0.9
  }
}

// The knee: Table I of the paper (J_m, B_m, M_r, B_r, K_r, B_l) and the firmware's N_m,
// k_tau, winding resistance and limits. B_r is Table I's 1.6e4 N s/m, not the
// firmware's 2.5e4 (where sources disagree, the paper wins).
TEST(DracoActuators, KneeIsTableI) {
  const auto m = by_joint();
  for (const std::string j : {"l_knee", "r_knee"}) {
    const dm::ActuatorParams& k = m.at(j);
    EXPECT_EQ(k.kind, dm::ActuatorKind::RFSEA);
    EXPECT_DOUBLE_EQ(k.J_m_kgm2, 1.6e-5);     // Table I
    EXPECT_DOUBLE_EQ(k.B_m_Nms, 2.0e-4);      // Table I
    EXPECT_DOUBLE_EQ(k.M_r_kg, 1.3);          // Table I
    EXPECT_DOUBLE_EQ(k.B_s_Ns_per_m, 1.6e4);  // Table I B_r
    EXPECT_DOUBLE_EQ(k.K_s_N_per_m, 9.5e6);   // Table I K_r
    EXPECT_DOUBLE_EQ(k.B_l_Ns_per_m, 2.0e4);  // Table I B_l
    EXPECT_DOUBLE_EQ(k.N_m_rad_per_m, 6632);  // firmware
    EXPECT_DOUBLE_EQ(k.k_tau_Nm_per_A, 0.0448);
    EXPECT_DOUBLE_EQ(k.thermal.R_winding_ohm, 1.03);
    EXPECT_DOUBLE_EQ(k.current_limit_A, 22);
    EXPECT_DOUBLE_EQ(k.force_limit_N, 8000);
    // Reflected rotor: J_m N_m^2 = 703.7 kg, B_m N_m^2 = 8797 N s/m, k_tau N_m = 297.1 N/A
    // (docs/paper-actuators.md section 1, "Units").
    EXPECT_NEAR(k.reflected_mass_kg(), 703.7, 0.05);
    EXPECT_NEAR(k.reflected_damping_Ns_per_m(), 8797, 0.5);
    EXPECT_NEAR(k.force_per_amp_N_per_A(), 297.1, 0.05);
  }
}

// Every other joint against the firmware table of the facts.
TEST(DracoActuators, FirmwareValuesPerJoint) {
  struct Row {
    const char* j;
    double N_m, K, B, kt, R, i_max, f_max;
  };
  const Row rows[] = {{"hip_yaw", 5864, 2.4e6, 2.5e4, 0.0486, 4.49, 8, 8000},
                      {"hip_roll", 3316, 6.5e6, 2.5e4, 0.0448, 1.03, 20, 8000},
                      {"hip_pitch", 3316, 6.5e6, 2.5e4, 0.0448, 1.03, 19, 8000},
                      {"knee", 6632, 9.5e6, 1.6e4 /* Table I, firmware 2.5e4 */, 0.0448, 1.03, 22, 8000},
                      {"ankle", 3142, 1.96e6, 3.0e3, 0.0276, 0.386, 15, 5000}};
  const auto m = by_joint();
  for (const Row& r : rows) {
    for (const std::string side : {"l_", "r_"}) {
      const dm::ActuatorParams& a = m.at(side + r.j);
      EXPECT_DOUBLE_EQ(a.N_m_rad_per_m, r.N_m) << a.joint;
      EXPECT_DOUBLE_EQ(a.K_s_N_per_m, r.K) << a.joint;
      EXPECT_DOUBLE_EQ(a.B_s_Ns_per_m, r.B) << a.joint;
      EXPECT_DOUBLE_EQ(a.k_tau_Nm_per_A, r.kt) << a.joint;
      EXPECT_DOUBLE_EQ(a.thermal.R_winding_ohm, r.R) << a.joint;
      EXPECT_DOUBLE_EQ(a.current_limit_A, r.i_max) << a.joint;
      EXPECT_DOUBLE_EQ(a.force_limit_N, r.f_max) << a.joint;
    }
  }
}

// The knee's P_inf in numbers, as docs/paper-actuators.md section 1 prints it:
// 4.0035e6 / (s^2 + 35.17 s + 13474.5), 18.5 Hz, DC gain 297.1 N/A. (That page rounds the
// damping ratio to 0.152; from its own coefficients it is 35.17 / (2 sqrt(13474.5)) = 0.1515.)
TEST(LockedOutput, KneeFormulaMatchesTheDerivedPlant) {
  const db::TransferFunction P = p_inf(by_joint().at("l_knee"));
  ASSERT_EQ(P.order(), 2);
  EXPECT_NEAR(P.num().coeffs().back() / 4.0035e6, 1.0, 1e-4);  // printed to 5 digits
  const auto& d = P.den().coeffs();                            // monic, ascending
  EXPECT_NEAR(d[1], 35.17, 0.005);
  EXPECT_NEAR(d[0], 13474.5, 0.05);
  const double wn = std::sqrt(d[0]), zeta = d[1] / (2 * wn);
  EXPECT_NEAR(wn / (2 * kPi), 18.5, 0.05);
  EXPECT_NEAR(zeta, 0.1515, 0.0001);
  EXPECT_NEAR(*P.dc_gain(), 297.1, 0.05);
}

// The formula against the integrated ODE, for the knee and a hip (RFSEA) and the ankle
// (FSEA, M_r = 0), below, at and above the elastomer resonance and at the DOB's 60 Hz.
// Error budget: RK4 at 2000 steps per period and <= 0.1 rad per step for the free mode
// ~1e-10; the transient left after 25 time constants ~1e-11 of the response; the
// projection over whole periods is exact. Measured: relative gain error <= 2e-10,
// phase error <= 1e-10 rad. Bounds 1e-7 and 1e-7 rad; an N_m-power or M_r slip moves
// the gain by percent or more at these frequencies.
TEST(LockedOutput, FormulaMatchesIntegratedActuatorOde) {
  const auto m = by_joint();
  double worst_gain = 0, worst_phase = 0;
  for (const std::string j : {"l_knee", "l_hip_roll", "l_hip_yaw", "l_ankle"}) {
    const dm::ActuatorParams& p = m.at(j);
    const db::TransferFunction P = p_inf(p);
    const double fn = std::sqrt(P.den().coeffs()[0]) / (2 * kPi);
    for (double f : {2.0, fn, 2.5 * fn, 60.0}) {
      const Response r = locked_output_response(p, f);
      const std::complex<double> g = P.evaluate({0.0, 2 * kPi * f});
      const double e_gain = std::abs(r.gain / std::abs(g) - 1.0);
      const double e_phase = std::abs(std::remainder(r.phase - std::arg(g), 2 * kPi));
      worst_gain = std::max(worst_gain, e_gain);
      worst_phase = std::max(worst_phase, e_phase);
      EXPECT_LT(e_gain, 1e-7) << j << " at " << f << " Hz: ODE " << r.gain << " N/A, formula " << std::abs(g);
      EXPECT_LT(e_phase, 1e-7) << j << " at " << f << " Hz: ODE " << r.phase << " rad, formula " << std::arg(g);
    }
  }
  std::printf("[ measured ] P_inf vs RK4: max relative gain error %.3g, max phase error %.3g rad\n", worst_gain,
              worst_phase);
}
