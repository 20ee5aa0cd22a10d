// Where the frames draw each logged contact force (contact_sites.hpp states the rules).
#include "contact_sites.hpp"

#include <cmath>
#include <limits>

namespace dmbd::report::detail {

namespace {

using Kind = model::Geometry::Kind;

// The shape's points in the link frame (X_LG applied).
std::vector<Eigen::Vector3d> shape_points(const model::Shape& sh) {
  const model::Geometry& g = sh.geometry;
  const Eigen::Isometry3d& X = sh.X_LG;
  std::vector<Eigen::Vector3d> p;
  switch (g.kind) {
    case Kind::Box:
      for (int k = 0; k < 8; ++k)
        p.push_back(X * (0.5 * Eigen::Vector3d(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1).cwiseProduct(g.box_size_m)));
      break;
    case Kind::Mesh:
      if (!g.hull_m.empty())
        for (const Eigen::Vector3d& v : g.hull_m) p.push_back(X * v);
      else
        for (const Eigen::Vector3f& v : g.mesh->vertices) p.push_back(X * v.cast<double>());
      break;
    case Kind::Cylinder:  // the rims at z = -L/2 and +L/2 of the geometry frame
      for (double side : {-0.5, 0.5})
        for (int k = 0; k < kRimSamples; ++k) {
          const double a = 2 * M_PI * k / kRimSamples;
          p.push_back(X * Eigen::Vector3d(g.radius_m * std::cos(a), g.radius_m * std::sin(a), side * g.length_m));
        }
      break;
    case Kind::Sphere:
      break;
  }
  return p;
}

}  // namespace

std::vector<ContactSite> contact_sites(const model::RobotDescription& robot) {
  std::vector<ContactSite> sites;
  for (std::size_t l = 0; l < robot.links.size(); ++l) {
    const auto& shapes = robot.links[l].collisions;
    for (std::size_t k = 0; k < shapes.size(); ++k) {
      const model::Geometry& g = shapes[k].geometry;
      if (!model::can_collide(g)) continue;
      ContactSite s;
      s.link = static_cast<int>(l);
      s.shape = static_cast<int>(k);
      s.kind = g.kind;
      s.center_L = shapes[k].X_LG.translation();
      s.radius_m = g.radius_m;
      if (g.kind != Kind::Sphere) s.points_L = shape_points(shapes[k]);
      sites.push_back(std::move(s));
    }
  }
  return sites;
}

Eigen::Vector3d contact_point(const ContactSite& site, const Eigen::Isometry3d& X_WL) {
  if (site.kind == Kind::Sphere) return X_WL * site.center_L - site.radius_m * Eigen::Vector3d::UnitZ();
  Eigen::Vector3d moment = Eigen::Vector3d::Zero(), lowest = Eigen::Vector3d::Zero();
  double depth = 0, lowest_z = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& p_L : site.points_L) {
    const Eigen::Vector3d p = X_WL * p_L;
    if (p.z() < 0) {
      moment -= p.z() * p;
      depth -= p.z();
    }
    if (p.z() < lowest_z) {
      lowest_z = p.z();
      lowest = p;
    }
  }
  return depth > 0 ? Eigen::Vector3d(moment / depth) : lowest;
}

}  // namespace dmbd::report::detail
