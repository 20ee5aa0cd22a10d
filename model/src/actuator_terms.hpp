#pragma once
// Internal to model/: one actuator in reduced coordinates, every kind.
//
// The VLCAs (RFSEA, FSEA):
// Coordinates: the joint angle q it drives and the spring deflection s (RFSEA: the
// elastomer compression x_r under the housing; FSEA: the nut-to-output deflection delta).
// The rigid ball screw makes the rotor angle a function of them,
//   theta_m = N_m (x(q) - x(0) + s),   rotor speed theta_m' = N_m w,  w = r(q) q' + s',
// (RFSEA: theta_m / N_m = x_l + x_r; FSEA: the nut travel x_n = x(q) - x(0) + delta),
// so the rotor needs no coordinate and no constraint: its kinetic energy
// 1/2 J' w^2, J' = J_m N_m^2 (the reflected rotor, 704 kg at the knee), adds
// J' a a^T to the mass matrix over (q, s) with a = (r, 1), and its Lagrange equations
// add the velocity-product force -J' r'(q) q'^2 a. The motor force eta k_tau N_m i and
// the rotor damping -B' w (B' = B_m N_m^2) act along a (virtual work of the screw);
// the elastomer -K_s s - B_s s' acts on s; the output damping -B_l r^2 q' on q.
// (MuJoCo's joint/tendon armature and Drake's reflected inertia are the same idea with
// a constant ratio; here the ratio is the linkage's r(q).) The RFSEA's housing, the
// reaction mass M_r that rides on s, is a point mass handled with the multibody tree
// (plant_dynamics.cpp). The rotor's spin is taken relative to its housing only (its
// coupling to the links' rotation, 1/(N_m r) ~ 0.3 % of the term kept, is neglected, as
// in the anchors' armature models). docs/model.md, section 6.
//
// The geared rotary kinds are the same form with a gear for the linkage, r = 1, r' = 0:
// theta_m = N (q + s), w = q' + s' (the gear output's speed; ROTARY has no s, w = q'),
// a = (1, 1) (ROTARY: a = (1, 0), only the q entries are used). Their gear friction acts
// along a, at the gear's output: viscous -b w, and Coulomb regularised as
//   tau_f = -tau_c clamp(w / w_s, -1, 1)
// (the slope tau_c / w_s enters D while |w| < w_s, implicit in the fixed step; at the cap
// it is explicit). The output damping B_l (N m s/rad at the joint) acts on q; the torsion
// spring K_s, B_s on s. docs/model.md section 6, docs/actuator-format.md.
#include "dmbd/model/actuator.hpp"

#include <Eigen/Core>

namespace dmbd::model::detail {

struct ActuatorTerms {
  Eigen::Matrix2d M = Eigen::Matrix2d::Zero();   // added to the mass matrix over (q, s)
  Eigen::Vector2d f = Eigen::Vector2d::Zero();   // generalized force on (q, s), velocity products included
  // The parts of -df/d(q', s') and -df/d(q, s) that enter the fixed step's implicit solve:
  // the dampers (B' a a^T, B_l r^2, B_s; rotary: also b and the Coulomb slope along a)
  // and the elastomer (K_s on s), symmetric and positive semi-definite. Left out (explicit): the derivative of the velocity-product
  // force, 2 J' r' q' a, and the geometric r'(q) terms of the forces along a.
  Eigen::Matrix2d D = Eigen::Matrix2d::Zero();
  Eigen::Matrix2d K = Eigen::Matrix2d::Zero();
};

// `current_A` is the applied (already clamped) current. For ROTARY pass s = s' = 0.
ActuatorTerms actuator_terms(const ActuatorParams& p, double q, double qd, double s, double sd, double current_A);

// Readings of the actuator's state (ROTARY: s = s' = 0).
double motor_angle(const ActuatorParams& p, double q, double s);               // rad
double motor_velocity(const ActuatorParams& p, double q, double qd, double sd);  // rad/s
double actuator_kinetic_energy(const ActuatorParams& p, double q, double qd, double sd);  // rotor only
double actuator_potential_energy(const ActuatorParams& p, double s);           // spring (0 for ROTARY)

// The rotary kinds' gear friction at output speed w (rad/s): the torque along a (N m) and
// its slope -d tau/dw that enters D (N m s/rad).
struct GearFriction {
  double tau = 0, slope = 0;
};
GearFriction gear_friction(const ActuatorParams& p, double w);

}  // namespace dmbd::model::detail
