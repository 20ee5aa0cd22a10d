#include "actuator_terms.hpp"

namespace dmbd::model::detail {

ActuatorTerms actuator_terms(const ActuatorParams& p, double q, double qd, double s, double sd, double current_A) {
  const double r = p.linkage.moment_arm_m(q), dr = p.linkage.dmoment_arm_dq_m(q);
  const double Jr = p.reflected_mass_kg(), Br = p.reflected_damping_Ns_per_m();
  const Eigen::Vector2d a(r, 1.0);
  const double w = r * qd + sd;
  const double motor = p.efficiency * p.force_per_amp_N_per_A() * current_A;
  ActuatorTerms t;
  t.M = Jr * a * a.transpose();
  t.f = (motor - Br * w - Jr * dr * qd * qd) * a;
  t.f[0] -= p.B_l_Ns_per_m * r * r * qd;
  t.f[1] -= p.K_s_N_per_m * s + p.B_s_Ns_per_m * sd;
  t.D = Br * a * a.transpose();
  t.D(0, 0) += p.B_l_Ns_per_m * r * r;
  t.D(1, 1) += p.B_s_Ns_per_m;
  t.K(1, 1) = p.K_s_N_per_m;
  return t;
}

double motor_angle(const ActuatorParams& p, double q, double s) {
  return p.N_m_rad_per_m * (p.linkage.length_m(q) - p.linkage.length_m(0.0) + s);
}

double motor_velocity(const ActuatorParams& p, double q, double qd, double sd) {
  return p.N_m_rad_per_m * (p.linkage.moment_arm_m(q) * qd + sd);
}

double actuator_kinetic_energy(const ActuatorParams& p, double q, double qd, double sd) {
  const double w = p.linkage.moment_arm_m(q) * qd + sd;
  return 0.5 * p.reflected_mass_kg() * w * w;
}

double actuator_potential_energy(const ActuatorParams& p, double s) { return 0.5 * p.K_s_N_per_m * s * s; }

}  // namespace dmbd::model::detail
