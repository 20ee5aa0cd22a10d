#include "dmbd/model/robot_description.hpp"

namespace dmbd::model {

int RobotDescription::link_index(const std::string& name) const {
  for (std::size_t i = 0; i < links.size(); ++i)
    if (links[i].name == name) return static_cast<int>(i);
  return -1;
}

int RobotDescription::joint_index(const std::string& name) const {
  for (std::size_t i = 0; i < joints.size(); ++i)
    if (joints[i].name == name) return static_cast<int>(i);
  return -1;
}

int RobotDescription::parent_joint_of_link(int link) const {
  if (link < 0 || link >= static_cast<int>(links.size())) return -1;
  for (std::size_t i = 0; i < joints.size(); ++i)
    if (joints[i].child == links[link].name) return static_cast<int>(i);
  return -1;
}

double RobotDescription::total_mass_kg() const {
  double m = 0;
  for (const Link& l : links) m += l.mass_kg;
  return m;
}

const char* joint_type_name(JointType t) {
  switch (t) {
    case JointType::Fixed: return "fixed";
    case JointType::Revolute: return "revolute";
    case JointType::Continuous: return "continuous";
    case JointType::Prismatic: return "prismatic";
    case JointType::Floating: return "floating";
    case JointType::Planar: return "planar";
  }
  return "?";
}

bool can_collide(const Geometry& g) {
  switch (g.kind) {
    case Geometry::Kind::Sphere:
    case Geometry::Kind::Box: return true;
    case Geometry::Kind::Cylinder: return g.radius_m > 0;
    case Geometry::Kind::Mesh: return !g.hull_m.empty() || (g.mesh && !g.mesh->vertices.empty());
  }
  return false;
}

}  // namespace dmbd::model
