// Collision meshes at load: their contact points are the convex hull's vertices (qhull),
// and a missing one's warning says the collision is skipped (docs/model.md, "Contact").
#include "dmbd/model/robot_description.hpp"

#include "test_urdf_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

namespace dmbd::model {
namespace {

using test::line_of;
using test::slurp;
using test::urdf_data;

TEST(UrdfCollision, MeshContactPointsAreTheWedgesSixCorners) {
  const RobotDescription r = load_urdf(urdf_data("mixed/mixed.urdf"));
  const Link& puck = r.links[static_cast<std::size_t>(r.link_index("puck"))];
  ASSERT_EQ(puck.collisions.size(), 1u);
  const Geometry& g = puck.collisions[0].geometry;
  ASSERT_TRUE(g.mesh);
  // wedge.obj: triangle (0 0 0), (0.2 0 0), (0 0 0.1) extruded along y to 0.3, written here.
  const Eigen::Vector3d corners[] = {{0, 0, 0}, {0.2, 0, 0}, {0, 0, 0.1}, {0, 0.3, 0}, {0.2, 0.3, 0}, {0, 0.3, 0.1}};
  ASSERT_EQ(g.hull_m.size(), 6u);
  for (const Eigen::Vector3d& c : corners)
    EXPECT_TRUE(std::any_of(g.hull_m.begin(), g.hull_m.end(), [&](const Eigen::Vector3d& p) { return (p - c).norm() < 1e-7; }))
        << c.transpose();  // the file's numbers as floats
  // A visual mesh gets no contact points.
  for (const Link& l : r.links)
    for (const Shape& s : l.visuals) EXPECT_TRUE(s.geometry.hull_m.empty()) << l.name;
}

TEST(UrdfCollision, MissingCollisionMeshIsNamedSkippedInTheMeshsOneWarning) {
  const std::string path = urdf_data("partial/missing_meshes.urdf");
  const std::string text = slurp(path);
  const RobotDescription r = load_urdf(path);
  ASSERT_EQ(r.warnings.size(), 3u);  // as before: one per missing mesh, then the massless link
  // ghost.stl is first a visual (the warning's line), then the collision.
  const int visual = line_of(text, "ghost.stl");
  const auto second = text.find("ghost.stl", text.find("ghost.stl") + 1);
  const int collision = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(second), '\n'));
  const std::string tail = "; the collision of link 'base' at line " + std::to_string(collision) + " is skipped (no contact)";
  EXPECT_EQ(r.warnings[0].rfind(path + ":" + std::to_string(visual) + ": link 'base': ", 0), 0u) << r.warnings[0];
  ASSERT_GE(r.warnings[0].size(), tail.size());
  EXPECT_EQ(r.warnings[0].substr(r.warnings[0].size() - tail.size()), tail) << r.warnings[0];
  EXPECT_TRUE(r.links[0].collisions[0].geometry.hull_m.empty());
}

}  // namespace
}  // namespace dmbd::model
