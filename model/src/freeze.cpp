// freeze_joints: weld 1-dof joints of a description at given positions.
#include <cmath>
#include <string>

#include "dmbd/model/error.hpp"
#include "dmbd/model/robot_description.hpp"

namespace dmbd::model {

RobotDescription freeze_joints(const RobotDescription& robot,
                               const std::vector<std::pair<std::string, double>>& positions) {
  RobotDescription out = robot;
  for (const auto& [name, q] : positions) {
    const int j = out.joint_index(name);
    if (j < 0) throw ModelError("freeze_joints: robot '" + robot.name + "' has no joint '" + name + "'");
    Joint& joint = out.joints[static_cast<std::size_t>(j)];
    if (!std::isfinite(q)) throw ModelError("freeze_joints: joint '" + name + "': position is not finite");
    if (joint.has_limits && (q < joint.lower - 1e-12 || q > joint.upper + 1e-12))
      throw ModelError("freeze_joints: joint '" + name + "': " + std::to_string(q) + " is outside its limits [" +
                       std::to_string(joint.lower) + ", " + std::to_string(joint.upper) + "]");
    switch (joint.type) {
      case JointType::Revolute:
      case JointType::Continuous:
        joint.X_PJ = joint.X_PJ * Eigen::AngleAxisd(q, joint.axis);
        break;
      case JointType::Prismatic:
        joint.X_PJ = joint.X_PJ * Eigen::Translation3d(q * joint.axis);
        break;
      default:
        throw ModelError("freeze_joints: joint '" + name + "' is not a 1-dof joint");
    }
    joint.type = JointType::Fixed;
    joint.has_limits = false;
  }
  return out;
}

}  // namespace dmbd::model
