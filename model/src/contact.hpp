#pragma once
// Internal to model/: the point contact laws both steppers use, written in the ground's
// frame (ground_frame.hpp): x, y along the ground, z along its normal. Eigen only.
//
// Sphere. Normal: Hunt-Crossley on the Hertz law of a sphere of radius R pressed into a
//   flat, F_n = c x^{3/2} (1 + 3/2 d xdot),  c = 4/3 k sqrt(R k),  k = E^{2/3} / 2,
// with x the penetration, xdot its rate, E the plane-strain modulus and d the
// dissipation (s/m): the constants of Simbody's SmoothSphereHalfSpaceForce, so the
// sinkage is that of the earlier model. F_n >= 0 (no pull when separating fast).
// Point (a box corner, a mesh's hull vertex). Normal: linear Hunt-Crossley,
//   F_n = k x (1 + d xdot),  F_n >= 0,  k = point_stiffness_N_per_m, d = point_dissipation_s_per_m.
// Friction (both): a tangential spring-damper from the contact point to an anchor on the
// ground, f_t = -k_t (p - a) - d_t v_t, capped by the Coulomb cone |f_t| <= mu F_n,
// with k_t = mu F_n / delta_s and d_t = mu F_n / v_s in proportion to the load: the
// damping is regularised Coulomb friction's slope (v_s = 0.01 m/s, as before), the
// spring removes its creep. While the cone holds (stick) the foot does not creep; the
// spring alone reaches the cone at |p - a| = delta_s, beyond which the anchor is
// dragged along (slip). This is the elastic-plastic ("history") tangential model of
// discrete-element contact (Chrono's SMC) with a load-proportional stiffness.
// The stiff parts of both (dF/dx, dF/dxdot; k_t, d_t while sticking) enter the fixed
// stepper's implicit solve; sliding friction is applied explicitly.
#include "dmbd/model/plant.hpp"

#include <Eigen/Core>

namespace dmbd::model::detail {

struct ContactForce {
  bool touching = false;
  bool sliding = false;
  double penetration_m = 0;
  double normal_force_N = 0;
  Eigen::Vector3d force_W = Eigen::Vector3d::Zero();  // on the robot at the contact point
  // The diagonal parts of -d force / d position and -d force / d velocity that enter the
  // implicit solve (dF_n/dx, k_t; d_n, d_t while sticking). Left out (explicit): the
  // friction's dependence on the penetration through F_n, (f_t / F_n) dF_n/dx.
  Eigen::Matrix3d K = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d D = Eigen::Matrix3d::Zero();
  double potential_J = 0;                             // normal and tangential-spring energy
};
using SphereContact = ContactForce;

// Hertz constant c (N/m^1.5) of a sphere of radius R on a flat of modulus E.
double hertz_constant(double radius_m, double stiffness_Pa);
// Penetration of that sphere under a static load (m).
double hertz_sinkage(double force_N, double radius_m, double stiffness_Pa);

// The force at a contact point of the sphere's body (ground frame), given the
// penetration (> 0 when touching), the point's velocity and its offset from the anchor
// (x, y).
SphereContact sphere_contact(const ContactParams& p, double radius_m, double penetration_m,
                             const Eigen::Vector3d& velocity_W, const Eigen::Vector2d& anchor_offset);
// The same with the sphere's Hertz constant given (the plant computes it once a sphere:
// a power, otherwise taken on every contact at every step).
SphereContact sphere_contact_hertz(const ContactParams& p, double hertz_N_per_m15, double penetration_m,
                                   const Eigen::Vector3d& velocity_W, const Eigen::Vector2d& anchor_offset);

// The same for a point contact (linear normal law), ground frame.
ContactForce point_contact(const ContactParams& p, double penetration_m, const Eigen::Vector3d& velocity_G,
                           const Eigen::Vector2d& anchor_offset);

// The anchor friction of a contact whose normal force c.normal_force_N is set: writes
// the tangential force, its stick K and D, `sliding`, and adds the spring's energy.
void anchor_friction(const ContactParams& p, const Eigen::Vector2d& anchor_offset, const Eigen::Vector2d& velocity_t,
                     ContactForce& c);

// The anchor offset after the return map: unchanged while the spring force stays inside
// the cone, else shortened along itself to k_t |offset| = mu F_n, that is |offset| =
// delta_s whatever F_n (k_t = mu F_n / delta_s): the map needs no force, only where the
// contact touches.
Eigen::Vector2d slide_anchor(const ContactParams& p, const Eigen::Vector2d& anchor_offset);

}  // namespace dmbd::model::detail
