#include "contact_elements.hpp"

#include "convex_hull.hpp"
#include "tree_kernel.hpp"

namespace dmbd::model::detail {


namespace {

// Appends the shape's elements (link frame on `body`) to `out`; false if it has none.
bool add_elements(const Shape& sh, int body, ContactElements& out, ContactShape& rec) {
  const Geometry& g = sh.geometry;
  if (!can_collide(g)) return false;
  const Eigen::Isometry3d& X = sh.X_LG;
  auto add_point = [&](const Eigen::Vector3d& p_G) { out.points.push_back({body, X * p_G}); };
  switch (g.kind) {
    case Geometry::Kind::Sphere:
      rec.first = static_cast<int>(out.spheres.size());
      out.spheres.push_back({rec.link, body, Eigen::Vector3d(X.translation()), g.radius_m});
      break;
    case Geometry::Kind::Box:
      rec.first = static_cast<int>(out.points.size());
      for (int k = 0; k < 8; ++k)
        add_point(0.5 * Eigen::Vector3d(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1).cwiseProduct(g.box_size_m));
      break;
    case Geometry::Kind::Mesh: {
      rec.first = static_cast<int>(out.points.size());
      const std::vector<Eigen::Vector3d> hull =
          !g.hull_m.empty() || !g.mesh ? g.hull_m : mesh_contact_points(*g.mesh, kMaxHullPoints);
      for (const Eigen::Vector3d& p : hull) add_point(p);
      if (hull.empty()) return false;
      break;
    }
    case Geometry::Kind::Cylinder: {
      if (!(g.radius_m > 0)) return false;
      rec.first = static_cast<int>(out.rims.size());
      const Eigen::Vector3d axis = X.linear().col(2);  // the cylinder's z
      for (double side : {-0.5, 0.5})
        out.rims.push_back({body, Eigen::Vector3d(X.translation() + side * g.length_m * axis), axis, g.radius_m});
      break;
    }
  }
  return true;
}

}  // namespace

ContactElements contact_elements(const RobotDescription& r, const TreeKernel& kernel) {
  ContactElements out;
  for (std::size_t l = 0; l < r.links.size(); ++l) {
    const int body = kernel.body_of_link(static_cast<int>(l));
    const auto& shapes = r.links[l].collisions;
    for (std::size_t k = 0; k < shapes.size(); ++k) {
      ContactShape rec{static_cast<int>(l), static_cast<int>(k), body, shapes[k].geometry.kind, 0, 0};
      const std::size_t before = out.spheres.size() + out.points.size() + out.rims.size();
      if (!add_elements(shapes[k], body, out, rec)) continue;
      rec.count = static_cast<int>(out.spheres.size() + out.points.size() + out.rims.size() - before);
      out.shapes.push_back(rec);
    }
  }
  return out;
}

}  // namespace dmbd::model::detail
