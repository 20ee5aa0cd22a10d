#include "actuator_terms.hpp"

#include <algorithm>
#include <cmath>

namespace dmbd::model::detail {

namespace {

// ROTARY and ROTARY_SEA: the gear (r = 1, r' = 0: no velocity-product force), its friction
// along a, the output damping on q and (SEA) the torsion spring on s.
ActuatorTerms rotary_terms(const ActuatorParams& p, double qd, double s, double sd, double current_A) {
  const bool spring = p.has_spring();
  const double Jr = p.reflected_mass_kg(), Br = p.reflected_damping_Ns_per_m(), b = p.viscous_friction_Nms;
  const Eigen::Vector2d a(1.0, spring ? 1.0 : 0.0);
  const double w = qd + (spring ? sd : 0.0);
  const double motor = p.efficiency * p.force_per_amp_N_per_A() * current_A;
  const GearFriction fr = gear_friction(p, w);
  ActuatorTerms t;
  t.M = Jr * a * a.transpose();
  t.f = (motor - (Br + b) * w + fr.tau) * a;
  t.f[0] -= p.B_l_Ns_per_m * qd;
  t.D = (Br + b + fr.slope) * a * a.transpose();
  t.D(0, 0) += p.B_l_Ns_per_m;
  if (spring) {
    t.f[1] -= p.K_s_N_per_m * s + p.B_s_Ns_per_m * sd;
    t.D(1, 1) += p.B_s_Ns_per_m;
    t.K(1, 1) = p.K_s_N_per_m;
  }
  return t;
}

}  // namespace

GearFriction gear_friction(const ActuatorParams& p, double w) {
  const double tc = p.coulomb_friction_Nm, ws = p.coulomb_velocity_rad_s;
  if (!(tc > 0)) return {};
  if (std::abs(w) < ws) return {-tc * w / ws, tc / ws};
  return {w > 0 ? -tc : tc, 0.0};
}

// RFSEA and FSEA: the arithmetic of the VLCA model, kept exactly (DRACO's results are
// bit-identical across the rotary kinds' addition).
ActuatorTerms actuator_terms(const ActuatorParams& p, double q, double qd, double s, double sd, double current_A) {
  if (p.is_rotary()) return rotary_terms(p, qd, s, sd, current_A);
  const LinkagePoint l = p.linkage.at(q);
  const double r = l.moment_arm_m, dr = l.dmoment_arm_dq_m;
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

double motor_angle(const ActuatorParams& p, double q, double s) { return p.N_m_rad_per_m * (p.travel(q) + s); }

double motor_velocity(const ActuatorParams& p, double q, double qd, double sd) {
  return p.N_m_rad_per_m * (p.moment_arm(q) * qd + sd);
}

double actuator_kinetic_energy(const ActuatorParams& p, double q, double qd, double sd) {
  const double w = p.moment_arm(q) * qd + sd;
  return 0.5 * p.reflected_mass_kg() * w * w;
}

double actuator_potential_energy(const ActuatorParams& p, double s) {
  return p.has_spring() ? 0.5 * p.K_s_N_per_m * s * s : 0.0;
}

}  // namespace dmbd::model::detail
