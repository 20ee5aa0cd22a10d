#include "contact.hpp"

#include <algorithm>
#include <cmath>

namespace dmbd::model::detail {

double hertz_constant(double radius_m, double stiffness_Pa) {
  const double k = 0.5 * std::pow(stiffness_Pa, 2.0 / 3.0);
  return 4.0 / 3.0 * k * std::sqrt(radius_m * k);
}

double hertz_sinkage(double force_N, double radius_m, double stiffness_Pa) {
  return std::pow(std::max(force_N, 0.0) / hertz_constant(radius_m, stiffness_Pa), 2.0 / 3.0);
}

SphereContact sphere_contact(const ContactParams& p, double radius_m, double penetration_m,
                             const Eigen::Vector3d& velocity_W, const Eigen::Vector2d& anchor_offset) {
  return sphere_contact_hertz(p, hertz_constant(radius_m, p.stiffness_Pa), penetration_m, velocity_W, anchor_offset);
}

SphereContact sphere_contact_hertz(const ContactParams& p, double hz, double penetration_m,
                                   const Eigen::Vector3d& velocity_W, const Eigen::Vector2d& anchor_offset) {
  SphereContact c;
  if (!(penetration_m > 0)) return c;
  c.touching = true;
  c.penetration_m = penetration_m;
  const double x = penetration_m, xdot = -velocity_W.z();
  const double elastic = hz * x * std::sqrt(x);
  const double damping = 1.0 + 1.5 * p.dissipation_s_per_m * xdot;
  c.potential_J = 0.4 * elastic * x;  // integral of c x^1.5 dx
  if (damping <= 0) return c;         // separating faster than the material recovers: no force
  c.normal_force_N = elastic * damping;
  c.K(2, 2) = 1.5 * hz * std::sqrt(x) * damping;
  c.D(2, 2) = 1.5 * p.dissipation_s_per_m * elastic;
  c.force_W.z() = c.normal_force_N;
  anchor_friction(p, anchor_offset, velocity_W.head<2>(), c);
  return c;
}

ContactForce point_contact(const ContactParams& p, double penetration_m, const Eigen::Vector3d& velocity_G,
                           const Eigen::Vector2d& anchor_offset) {
  ContactForce c;
  if (!(penetration_m > 0)) return c;
  c.touching = true;
  c.penetration_m = penetration_m;
  const double x = penetration_m, xdot = -velocity_G.z(), k = p.point_stiffness_N_per_m;
  const double elastic = k * x;
  const double damping = 1.0 + p.point_dissipation_s_per_m * xdot;
  c.potential_J = 0.5 * elastic * x;  // integral of k x dx
  if (damping <= 0) return c;         // no pull
  c.normal_force_N = elastic * damping;
  c.K(2, 2) = k * damping;
  c.D(2, 2) = p.point_dissipation_s_per_m * elastic;
  c.force_W.z() = c.normal_force_N;
  anchor_friction(p, anchor_offset, velocity_G.head<2>(), c);
  return c;
}

void anchor_friction(const ContactParams& p, const Eigen::Vector2d& anchor_offset, const Eigen::Vector2d& velocity_t,
                     ContactForce& c) {
  const double cap = p.friction * c.normal_force_N;
  const double kt = cap / p.stiction_displacement_m, dt = cap / p.stiction_velocity_m_s;
  Eigen::Vector2d ft = -kt * anchor_offset - dt * velocity_t;
  const double norm = ft.norm();
  c.potential_J += 0.5 * kt * anchor_offset.squaredNorm();
  if (norm > cap) {
    ft *= cap / norm;
    c.sliding = true;
  } else {
    c.K(0, 0) = c.K(1, 1) = kt;
    c.D(0, 0) = c.D(1, 1) = dt;
  }
  c.force_W.head<2>() = ft;
}

Eigen::Vector2d slide_anchor(const ContactParams& p, const Eigen::Vector2d& anchor_offset) {
  // The spring k_t |offset| = mu F_n |offset| / delta_s reaches the cone at |offset| = delta_s.
  const double d = anchor_offset.norm();
  return d > p.stiction_displacement_m ? Eigen::Vector2d(anchor_offset * (p.stiction_displacement_m / d)) : anchor_offset;
}

}  // namespace dmbd::model::detail
