#include "rim_contact.hpp"

#include <algorithm>
#include <cmath>

namespace dmbd::model::detail {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The half-angle pm of the penetrated arc for A = R s > -h (touching).
double half_angle(double A, double h) { return h <= -A ? kPi : std::acos(std::clamp(h / A, -1.0, 1.0)); }

// Over [p1, p2] of x = A cos phi - h: int x, int x cos, int x sin.
Eigen::Vector3d arc_moments(double A, double h, double p1, double p2) {
  const double s1 = std::sin(p1), s2 = std::sin(p2), c1 = std::cos(p1), c2 = std::cos(p2);
  const double i0 = A * (s2 - s1) - h * (p2 - p1);
  const double ic = 0.5 * A * ((p2 - p1) + (s2 * c2 - s1 * c1)) - h * (s2 - s1);
  const double is = 0.5 * A * (s2 * s2 - s1 * s1) + h * (c2 - c1);
  return {i0, ic, is};
}

// The most downward unit direction in the rim's plane, given m = n - (n . a) a, s = |m|.
Eigen::Vector3d down_direction(const Eigen::Vector3d& m, double s, const Eigen::Vector3d& axis_W) {
  return s > 1e-12 ? Eigen::Vector3d(-m / s) : Eigen::Vector3d(axis_W.unitOrthogonal());
}

}  // namespace

double rim_tilt_sine(const Eigen::Vector3d& axis_W, const Eigen::Vector3d& n) {
  return (n - n.dot(axis_W) * axis_W).norm();
}

Eigen::Vector3d rim_lowest_point(const Eigen::Vector3d& center_W, const Eigen::Vector3d& axis_W, double radius_m,
                                 const Eigen::Vector3d& n) {
  const Eigen::Vector3d m = n - n.dot(axis_W) * axis_W;
  return center_W + radius_m * down_direction(m, m.norm(), axis_W);
}

double rim_load(double radius_m, double s, double height_m) {
  const double A = radius_m * s, h = height_m;
  if (!(h < A)) return 0.0;
  const double pm = half_angle(A, h);
  return 2 * A * std::sin(pm) - 2 * h * pm;
}

RimPenetration rim_penetration(const Eigen::Vector3d& center_W, const Eigen::Vector3d& axis_W, double radius_m,
                               const Eigen::Vector3d& n, double height_m) {
  RimPenetration r;
  const Eigen::Vector3d m = n - n.dot(axis_W) * axis_W;
  const double s = m.norm(), R = radius_m, A = R * s, h = height_m;
  if (!(h < A)) return r;  // the lowest rim point is above the ground
  r.touching = true;
  r.deepest_m = A - h;
  const Eigen::Vector3d u = down_direction(m, s, axis_W);
  const Eigen::Vector3d w = axis_W.cross(u);
  const double pm = half_angle(A, h), width = 2 * pm / kRimArcs;
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (int i = 0; i < kRimArcs; ++i) {
    const double p1 = -pm + i * width, p2 = i + 1 == kRimArcs ? pm : p1 + width;
    const Eigen::Vector3d mo = arc_moments(A, h, p1, p2);
    RimArc& arc = r.arcs[static_cast<std::size_t>(i)];
    arc.width_rad = p2 - p1;
    arc.load_m = std::max(mo[0], 0.0);
    const double mid = 0.5 * (p1 + p2);
    arc.p_W = mo[0] > 0 ? Eigen::Vector3d(center_W + R * (u * mo[1] + w * mo[2]) / mo[0])
                        : Eigen::Vector3d(center_W + R * (u * std::cos(mid) + w * std::sin(mid)));
    total += mo;
  }
  r.load_m = std::max(total[0], 0.0);
  r.cop_W = total[0] > 0 ? Eigen::Vector3d(center_W + R * (u * total[1] + w * total[2]) / total[0])
                         : Eigen::Vector3d(center_W + R * u);
  const double sp = std::sin(pm), cp = std::cos(pm);
  r.energy_m2 = 0.5 * (A * A * (pm + sp * cp) - 4 * A * h * sp + 2 * h * h * pm);
  return r;
}

}  // namespace dmbd::model::detail
