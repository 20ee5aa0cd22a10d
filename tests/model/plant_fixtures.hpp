#pragma once
// Robots built in code for the plant tests (independent of the URDF loader), and an
// independent forward-kinematics / gravity computation to cross-check Simbody.
#include "dmbd/model/robot_description.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <vector>

namespace dmbd::model::testing {

inline Link point_link(const std::string& name, double m, const Eigen::Vector3d& com, double I = 0) {
  Link l;
  l.name = name;
  l.mass_kg = m;
  l.com_m = com;
  l.inertia_kgm2 = I * Eigen::Matrix3d::Identity();
  return l;
}

inline Joint revolute(const std::string& name, const std::string& parent, const std::string& child,
                      const Eigen::Vector3d& xyz, const Eigen::Vector3d& axis) {
  Joint j;
  j.name = name;
  j.type = JointType::Revolute;
  j.parent = parent;
  j.child = child;
  j.X_PJ = Eigen::Isometry3d::Identity();
  j.X_PJ.translation() = xyz;
  j.axis = axis.normalized();
  j.has_limits = true;
  j.lower = -10;
  j.upper = 10;
  return j;
}

// Planar double pendulum hanging along -z, rotating about y: links of length l1 (joint
// to joint), centres of mass at lc1, lc2 below their joints, central inertias I1, I2
// about y (isotropic so the y component is I1, I2).
struct DoublePendulum {
  double m1 = 2.0, m2 = 1.5, l1 = 0.5, lc1 = 0.3, lc2 = 0.25, I1 = 0.04, I2 = 0.02;
  RobotDescription robot() const {
    RobotDescription r;
    r.name = "double_pendulum";
    r.links.push_back(point_link("base", 1.0, Eigen::Vector3d::Zero(), 0.01));
    r.links.push_back(point_link("upper", m1, {0, 0, -lc1}, I1));
    r.links.push_back(point_link("lower", m2, {0, 0, -lc2}, I2));
    r.joints.push_back(revolute("shoulder", "base", "upper", {0, 0, 0}, {0, 1, 0}));
    r.joints.push_back(revolute("elbow", "upper", "lower", {0, 0, -l1}, {0, 1, 0}));
    return r;
  }
  // Closed forms with angles about +y (a positive angle swings the pendulum towards -x
  // ... for z down: position of com1 = R_y(q1) (0,0,-lc1) = (-lc1 sin q1, 0, -lc1 cos q1)).
  Eigen::Matrix2d mass_matrix(double q2) const {
    const double c2 = std::cos(q2);
    Eigen::Matrix2d M;
    M(0, 0) = I1 + I2 + m1 * lc1 * lc1 + m2 * (l1 * l1 + lc2 * lc2 + 2 * l1 * lc2 * c2);
    M(0, 1) = M(1, 0) = I2 + m2 * (lc2 * lc2 + l1 * lc2 * c2);
    M(1, 1) = I2 + m2 * lc2 * lc2;
    return M;
  }
  Eigen::Vector2d gravity(double q1, double q2, double g) const {
    // V = -g (m1 lc1 cos q1 + m2 (l1 cos q1 + lc2 cos(q1+q2))) (heights negative), g = dV/dq.
    return {g * (m1 * lc1 * std::sin(q1) + m2 * (l1 * std::sin(q1) + lc2 * std::sin(q1 + q2))),
            g * m2 * lc2 * std::sin(q1 + q2)};
  }
  Eigen::Vector2d coriolis(double q2, double v1, double v2) const {
    const double h = m2 * l1 * lc2 * std::sin(q2);
    return {-h * (2 * v1 * v2 + v2 * v2), h * v1 * v1};
  }
};

// Forward kinematics from the description alone: X_WL per link for the 1-dof joints'
// positions q (in description joint order, fixed joints skipped), root at X_WB.
inline std::vector<Eigen::Isometry3d> fk(const RobotDescription& r, const Eigen::VectorXd& q,
                                         const Eigen::Isometry3d& X_WB = Eigen::Isometry3d::Identity()) {
  std::vector<Eigen::Isometry3d> X(r.links.size(), Eigen::Isometry3d::Identity());
  X[0] = X_WB;
  int k = 0;
  for (const Joint& j : r.joints) {
    Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
    if (j.type == JointType::Revolute || j.type == JointType::Continuous)
      M.linear() = Eigen::AngleAxisd(q[k++], j.axis).toRotationMatrix();
    else if (j.type == JointType::Prismatic)
      M.translation() = q[k++] * j.axis;
    X[static_cast<std::size_t>(r.link_index(j.child))] = X[static_cast<std::size_t>(r.link_index(j.parent))] * j.X_PJ * M;
  }
  return X;
}

// Generalised gravity g(q) of a fixed-base tree of revolute joints (A vdot + b + g = tau):
// g_c = -sum over links below joint c of m_l gvec . (a_c x (com_l - o_c)).
inline Eigen::VectorXd gravity_torques(const RobotDescription& r, const Eigen::VectorXd& q, double g,
                                       const Eigen::Isometry3d& X_WB = Eigen::Isometry3d::Identity()) {
  const auto X = fk(r, q, X_WB);
  const Eigen::Vector3d gvec(0, 0, -g);
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(q.size());
  int k = 0;
  for (const Joint& j : r.joints) {
    if (j.type != JointType::Revolute && j.type != JointType::Continuous) continue;
    const Eigen::Isometry3d X_WJ = X[static_cast<std::size_t>(r.link_index(j.parent))] * j.X_PJ;
    const Eigen::Vector3d a = X_WJ.linear() * j.axis, o = X_WJ.translation();
    // Links below this joint: the child and its descendants.
    std::vector<bool> below(r.links.size(), false);
    below[static_cast<std::size_t>(r.link_index(j.child))] = true;
    for (const Joint& d : r.joints)
      if (below[static_cast<std::size_t>(r.link_index(d.parent))]) below[static_cast<std::size_t>(r.link_index(d.child))] = true;
    for (std::size_t l = 0; l < r.links.size(); ++l)
      if (below[l]) tau[k] -= r.links[l].mass_kg * gvec.dot(a.cross(X[l] * r.links[l].com_m - o));
    ++k;
  }
  return tau;
}

}  // namespace dmbd::model::testing
