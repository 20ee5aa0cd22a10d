// The table under a fixed base (moved here from frames.cpp: the replay draws it too).
#include "table.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "dmbd/viz/primitives.hpp"

namespace dmbd::report::detail {

namespace {

// The table a fixed base is clamped to (the paper's table tests), one scene body in the
// world at X_WT: T at the base origin, z up, x along the base's heading (its x axis
// seen from above). The top (kTableDepth_m along x, kTableWidth_m across, kTableTop_m
// thick) has its upper face at the bottom of the root link's geometry (at the base
// origin for a root without geometry). Its front edge is kTableClear_m behind every
// other link's mesh that reaches into the top's height (DRACO's hips), so the legs hang
// free in front of the table and the three-quarter front view sees them; the torso's
// rear rests on it. A top centred under the torso would hide the thighs from that view
// and have the legs pass through it. It is centred under the root's geometry instead
// when nothing reaches into it, or when the edge would leave the root's geometry
// wholly in front of it. Four legs go down to the ground (z = 0) when the top's
// underside is at least kTableMinLegs_m above it. Placed once, from the first frame.
constexpr double kTableDepth_m = 0.5, kTableWidth_m = 0.6, kTableTop_m = 0.04, kTableLeg_m = 0.04,
                 kTableClear_m = 0.02, kTableMinLegs_m = 0.1;
const Eigen::Vector4f kTableTopRgba{0.78f, 0.64f, 0.42f, 1.0f}, kTableLegRgba{0.62f, 0.50f, 0.33f, 1.0f};

}  // namespace

Table table_under(const viz::Scene& robot_scene, const std::vector<Eigen::Isometry3d>& X, const Eigen::Isometry3d& X_WB) {
  Table t;
  t.body.name = "table";
  const Eigen::Vector3d x_B = X_WB.linear().col(0);
  t.X_WT.translation() = X_WB.translation();
  t.X_WT.linear() = Eigen::AngleAxisd(std::atan2(x_B.y(), x_B.x()), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Isometry3d X_TW = t.X_WT.inverse();
  // Bounds in T of each mesh at the first frame.
  const auto mesh_box = [&](std::size_t body, const viz::SceneMesh& m) {
    Eigen::AlignedBox3d b;
    const Eigen::Isometry3d X_TL = X_TW * X[body];
    for (const auto& v : m.vertices) b.extend(X_TL * v.cast<double>());
    return b;
  };
  Eigen::AlignedBox3d root;
  for (const auto& m : robot_scene.bodies.front().meshes) root.extend(mesh_box(0, m));
  const double z_top = root.isEmpty() ? 0.0 : root.min().z();
  const double x_mid = root.isEmpty() ? 0.0 : root.center().x(), y_mid = root.isEmpty() ? 0.0 : root.center().y();
  double x_behind = std::numeric_limits<double>::infinity();  // the rearmost point reaching into the top
  for (std::size_t b = 1; b < robot_scene.bodies.size(); ++b)
    for (const auto& m : robot_scene.bodies[b].meshes) {
      const Eigen::AlignedBox3d box = mesh_box(b, m);
      if (!box.isEmpty() && box.min().z() < z_top && box.max().z() > z_top - kTableTop_m - kTableClear_m)
        x_behind = std::min(x_behind, box.min().x());
    }
  double x_front = x_mid + 0.5 * kTableDepth_m;
  if (std::isfinite(x_behind) && (root.isEmpty() || x_behind - kTableClear_m > root.min().x()))
    x_front = x_behind - kTableClear_m;
  const Eigen::Vector3d top_centre(x_front - 0.5 * kTableDepth_m, y_mid, z_top - 0.5 * kTableTop_m);
  viz::SceneMesh top = viz::transformed(viz::box_mesh({kTableDepth_m, kTableWidth_m, kTableTop_m}),
                                        Eigen::Isometry3d(Eigen::Translation3d(top_centre)));
  top.rgba = kTableTopRgba;
  t.body.meshes.push_back(std::move(top));
  const double underside_W = X_WB.translation().z() + z_top - kTableTop_m;  // T is level: z differs by the origin's
  if (underside_W >= kTableMinLegs_m)
    for (const double sx : {-1.0, 1.0})
      for (const double sy : {-1.0, 1.0}) {
        const double inset = 0.03 + 0.5 * kTableLeg_m;
        const Eigen::Vector3d centre(top_centre.x() + sx * (0.5 * kTableDepth_m - inset),
                                     top_centre.y() + sy * (0.5 * kTableWidth_m - inset),
                                     z_top - kTableTop_m - 0.5 * underside_W);
        viz::SceneMesh leg = viz::transformed(viz::box_mesh({kTableLeg_m, kTableLeg_m, underside_W}),
                                              Eigen::Isometry3d(Eigen::Translation3d(centre)));
        leg.rgba = kTableLegRgba;
        t.body.meshes.push_back(std::move(leg));
      }
  return t;
}


}  // namespace dmbd::report::detail
