#pragma once
// Internal to model/: a cylinder's rim circle pressed into the ground, as an elastic
// ring of stiffness kappa per unit length (ContactParams::rim_stiffness_N_per_m2). Eigen
// only; docs/model.md ("Contact", cylinders) states the rule.
//
// The rim: centre c, unit axis a, radius R; the ground: unit normal n, the centre's
// height h = n . c. With m = n - (n . a) a, s = |m| (the sine of the axis' tilt from n)
// and u = -m / s (the rim's most downward direction; any unit vector normal to a when
// s = 0), w = a x u, the rim point at angle phi from u is c + R (u cos phi + w sin phi),
// its penetration x(phi) = R s cos phi - h, penetrated for cos phi > h / (R s): the arc
// |phi| < pm, pm = acos(h / (R s)) (pm = pi, the whole ring, when h <= -R s). Each rim
// element presses along n with kappa x per unit length, so in closed form
//   F   = kappa R int x dphi   = kappa R (2 R s sin pm - 2 h pm),
//   CoP = c + R u [R s (pm + sin pm cos pm) - 2 h sin pm] / [2 R s sin pm - 2 h pm]
// (parallel forces along n: the resultant acts through the CoP exactly), and the
// elastic energy U = kappa R int x^2/2 dphi
//       = kappa R [R^2 s^2 (pm + sin pm cos pm) - 4 R s h sin pm + 2 h^2 pm] / 2.
// The penetrated arc is split into kRimArcs equal sub-arcs, each a force along n at its
// own centre of pressure carrying its own integral: together exactly F and its moment,
// and a stiffness that spans rotations for the fixed stepper's implicit solve (a disc
// standing on its face resists tilting).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>

namespace dmbd::model::detail {

constexpr int kRimArcs = 4;

struct RimArc {
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();  // its centre of pressure
  double load_m = 0;                              // int x dphi over it (m rad): force kappa R load
  double width_rad = 0;                           // its angle: stiffness kappa R width along n
};

struct RimPenetration {
  bool touching = false;
  double deepest_m = 0;                             // R s - h (at phi = 0)
  double load_m = 0;                                // int x dphi (m rad)
  double energy_m2 = 0;                             // int x^2 / 2 dphi (m^2 rad)
  Eigen::Vector3d cop_W = Eigen::Vector3d::Zero();  // centre of pressure
  std::array<RimArc, kRimArcs> arcs;
};

// The rim (centre, unit axis, radius, world) against the ground of unit normal n, the
// centre at height h above it.
RimPenetration rim_penetration(const Eigen::Vector3d& center_W, const Eigen::Vector3d& axis_W, double radius_m,
                               const Eigen::Vector3d& n, double height_m);

// The rim's lowest point along n (any of its points when it lies flat), and the sine s
// of its axis' tilt from n.
Eigen::Vector3d rim_lowest_point(const Eigen::Vector3d& center_W, const Eigen::Vector3d& axis_W, double radius_m,
                                 const Eigen::Vector3d& n);
double rim_tilt_sine(const Eigen::Vector3d& axis_W, const Eigen::Vector3d& n);

// int x dphi alone (m rad) for the tilt sine s and the centre height h: the static load
// is kappa R times it (used to place a robot on the ground).
double rim_load(double radius_m, double s, double height_m);

}  // namespace dmbd::model::detail
