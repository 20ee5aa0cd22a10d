#pragma once
// Internal to model/: the contact elements of a robot's collision shapes, fixed on their
// bodies (every shape of every link; docs/model.md, "Contact"):
//   sphere    one Hertz contact at its centre and radius;
//   box       its 8 corners, point contacts;
//   mesh      the vertices of its convex hull (Geometry::hull_m, at most 64), point contacts;
//   cylinder  its two rim circles (centre, axis, radius), elastic rings.
// A mesh without hull points (its file did not load) has no element and no shape entry.
#include "convex_hull.hpp"
#include "dmbd/model/robot_description.hpp"

#include <Eigen/Core>

#include <vector>

namespace dmbd::model::detail {

class TreeKernel;

struct ContactSphere {
  int link = -1, body = -1;
  Eigen::Vector3d center_B;
  double radius_m = 0;
};

struct ContactPoint {
  int body = -1;
  Eigen::Vector3d p_B;
};

struct ContactRim {
  int body = -1;
  Eigen::Vector3d center_B, axis_B;  // axis unit
  double radius_m = 0;
};

// A colliding shape: its elements are [first, first + count) of the list of its kind
// (spheres; points for boxes and meshes; rims for cylinders).
struct ContactShape {
  int link = -1, shape = -1, body = -1;
  Geometry::Kind kind = Geometry::Kind::Sphere;
  int first = 0, count = 0;
};

struct ContactElements {
  std::vector<ContactShape> shapes;   // links in order, shapes in URDF order
  std::vector<ContactSphere> spheres;
  std::vector<ContactPoint> points;
  std::vector<ContactRim> rims;
};

ContactElements contact_elements(const RobotDescription& robot, const TreeKernel& kernel);

}  // namespace dmbd::model::detail
