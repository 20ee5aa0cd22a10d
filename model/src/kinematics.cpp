// Description-level kinematics and mass properties: forward kinematics, centre of mass,
// a joint's subtree inertia about its axis, payloads. Plain Eigen, no Simbody.
#include <map>
#include <string>

#include "dmbd/model/error.hpp"
#include "dmbd/model/robot_description.hpp"

namespace dmbd::model {

std::vector<Eigen::Isometry3d> link_frames(const RobotDescription& robot, const std::vector<double>& q,
                                           const Eigen::Isometry3d& X_W_root) {
  if (q.size() != robot.joints.size())
    throw ModelError("link_frames: " + std::to_string(q.size()) + " joint positions for " + std::to_string(robot.joints.size()) +
                     " joints of '" + robot.name + "'");
  std::vector<Eigen::Isometry3d> X_WL(robot.links.size(), X_W_root);
  std::map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < robot.links.size(); ++i) index[robot.links[i].name] = i;
  // Joints are parent-before-child: one pass.
  for (std::size_t j = 0; j < robot.joints.size(); ++j) {
    const Joint& joint = robot.joints[j];
    const auto p = index.find(joint.parent), c = index.find(joint.child);
    if (p == index.end() || c == index.end()) continue;
    Eigen::Isometry3d X_JC = Eigen::Isometry3d::Identity();
    const Eigen::Vector3d axis = joint.axis.norm() > 0 ? joint.axis.normalized() : Eigen::Vector3d::UnitX();
    if (joint.type == JointType::Revolute || joint.type == JointType::Continuous)
      X_JC.linear() = Eigen::AngleAxisd(q[j], axis).toRotationMatrix();
    else if (joint.type == JointType::Prismatic)
      X_JC.translation() = q[j] * axis;
    X_WL[c->second] = X_WL[p->second] * joint.X_PJ * X_JC;
  }
  return X_WL;
}

std::vector<Eigen::Isometry3d> default_pose_link_frames(const RobotDescription& robot) {
  return link_frames(robot, std::vector<double>(robot.joints.size(), 0.0));
}

Eigen::Vector3d center_of_mass(const RobotDescription& robot, const std::vector<Eigen::Isometry3d>& X_WL) {
  Eigen::Vector3d h = Eigen::Vector3d::Zero();
  double m = 0;
  for (std::size_t l = 0; l < robot.links.size() && l < X_WL.size(); ++l) {
    h += robot.links[l].mass_kg * (X_WL[l] * robot.links[l].com_m);
    m += robot.links[l].mass_kg;
  }
  return m > 0 ? Eigen::Vector3d(h / m) : Eigen::Vector3d::Zero();
}

// Joints are parent before child: children accumulate into parents in reverse order.
std::vector<double> subtree_masses(const RobotDescription& r) {
  std::vector<double> m(r.links.size());
  for (std::size_t l = 0; l < r.links.size(); ++l) m[l] = r.links[l].mass_kg;
  for (auto it = r.joints.rbegin(); it != r.joints.rend(); ++it) {
    const int p = r.link_index(it->parent), c = r.link_index(it->child);
    if (p >= 0 && c >= 0) m[static_cast<std::size_t>(p)] += m[static_cast<std::size_t>(c)];
  }
  return m;
}

double subtree_axis_inertia(const RobotDescription& robot, int joint) {
  const auto X = default_pose_link_frames(robot);
  const Joint& J = robot.joints.at(static_cast<std::size_t>(joint));
  const int child = robot.link_index(J.child);
  const Eigen::Isometry3d& X_WC = X[static_cast<std::size_t>(child)];
  const Eigen::Vector3d a = (X_WC.linear() * J.axis).normalized(), o = X_WC.translation();
  std::vector<int> sub{child};
  for (std::size_t k = 0; k < sub.size(); ++k)
    for (const auto& j : robot.joints)
      if (j.parent == robot.links[static_cast<std::size_t>(sub[k])].name) sub.push_back(robot.link_index(j.child));
  double I = 0;
  for (int l : sub) {
    const Link& L = robot.links[static_cast<std::size_t>(l)];
    const Eigen::Matrix3d R = X[static_cast<std::size_t>(l)].linear();
    const Eigen::Vector3d c = X[static_cast<std::size_t>(l)] * L.com_m - o;
    const Eigen::Vector3d d = c - a * a.dot(c);
    I += a.dot(R * L.inertia_kgm2 * R.transpose() * a) + L.mass_kg * d.squaredNorm();
  }
  return I;
}

void add_payload(RobotDescription& robot, const std::string& link, double mass_kg, const Eigen::Vector3d& com_L,
                 const Eigen::Vector3d& inertia_kgm2) {
  const int l = robot.link_index(link);
  if (l < 0) throw ModelError("payload: robot '" + robot.name + "' has no link '" + link + "'");
  if (!(mass_kg > 0)) throw ModelError("payload on '" + link + "': mass " + std::to_string(mass_kg) + " kg is not positive");
  Link& L = robot.links[static_cast<std::size_t>(l)];
  const double m = L.mass_kg + mass_kg;
  const Eigen::Vector3d c = (L.mass_kg * L.com_m + mass_kg * com_L) / m;
  auto shift = [](double mass, const Eigen::Vector3d& d) { return mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose()); };
  L.inertia_kgm2 = L.inertia_kgm2 + shift(L.mass_kg, L.com_m - c) + Eigen::Matrix3d(inertia_kgm2.asDiagonal()) + shift(mass_kg, com_L - c);
  L.com_m = c;
  L.mass_kg = m;
}

}  // namespace dmbd::model
