#pragma once
// Rigid-body dynamics of a robot for controllers (operational-space and whole-body
// control): mass matrix, Coriolis + gravity, Jacobians and their bias terms, centre of
// mass. Eigen types only; Simbody realises the kinematics behind the interface and the
// terms are assembled in model/src/tree_kernel.cpp (allocation-free).
// The model is the bare multibody tree of the URDF: no actuators, contact or limits.
//
// Coordinates (Simbody's, documented so callers can rely on them):
//   floating base: q = [quaternion w x y z of torso in world (4), torso origin in world (3), joints],
//                  v = [torso angular velocity in world (3), torso origin velocity in world (3), joint rates];
//   fixed base:    q = [joints], v = [joint rates].
// Joints are the URDF's 1-dof joints (revolute, continuous, prismatic) in the order of
// RobotDescription::joints; fixed joints have no coordinate. A 1-dof joint that moves
// only massless links is welded (listed in welded_joints()).

#include "dmbd/model/robot_description.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <memory>
#include <string>
#include <vector>

namespace dmbd::model {

enum class BaseMode { Fixed, Floating };

struct DynamicsOptions {
  BaseMode base = BaseMode::Floating;
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();  // root pose when fixed
  double gravity_m_s2 = 9.81;                              // along -z of the world
};

class RobotDynamics {
 public:
  RobotDynamics(const RobotDescription& robot, const DynamicsOptions& options = {});
  ~RobotDynamics();
  RobotDynamics(const RobotDynamics&) = delete;
  RobotDynamics& operator=(const RobotDynamics&) = delete;

  int nq() const;
  int nv() const;
  int base_dofs() const;                                  // 6 floating, 0 fixed
  const std::vector<std::string>& joint_names() const;     // one per joint coordinate
  const std::vector<std::string>& welded_joints() const;
  int joint_index(const std::string& name) const;          // into joint_names(), or -1
  int joint_q_index(int joint) const;                      // its entry in q
  int joint_v_index(int joint) const;                      // its entry in v
  int link_index(const std::string& name) const;           // RobotDescription link index, or -1
  double total_mass_kg() const;

  // The default configuration: base at identity (floating) and every joint at 0.
  Eigen::VectorXd neutral_configuration() const;

  // Sets the configuration and velocity every query below uses (quaternions are
  // normalised). Nothing is allocated here or in the out-parameter queries below: a
  // controller calls them every tick (tests/model/test_alloc_steps.cpp).
  void set_state(const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& v);

  // Out-parameter forms (sizes as stated; the caller preallocates).
  void mass_matrix(Eigen::Ref<Eigen::MatrixXd> A) const;                  // nv x nv
  void coriolis_and_gravity(Eigen::Ref<Eigen::VectorXd> bg) const;        // nv
  void gravity(Eigen::Ref<Eigen::VectorXd> g) const;                      // nv
  void coriolis(Eigen::Ref<Eigen::VectorXd> b) const;                     // nv
  void point_jacobian(int link, const Eigen::Vector3d& p_L, Eigen::Ref<Eigen::MatrixXd> J) const;  // 3 x nv
  void frame_jacobian(int link, const Eigen::Vector3d& p_L, Eigen::Ref<Eigen::MatrixXd> J) const;  // 6 x nv
  void com_jacobian(Eigen::Ref<Eigen::MatrixXd> J) const;                 // 3 x nv

  // Value forms (allocate the result).
  Eigen::MatrixXd mass_matrix() const;                     // A(q), nv x nv
  Eigen::VectorXd coriolis_and_gravity() const;            // b + g: A vdot + b + g = tau
  Eigen::VectorXd gravity() const;                         // g(q)
  Eigen::VectorXd coriolis() const;                        // b(q, v)

  Eigen::Isometry3d link_pose(int link) const;             // X_WL
  // Point p_L fixed in link L: world position, Jacobian (3 x nv), and J̇v (3).
  Eigen::Vector3d point_position(int link, const Eigen::Vector3d& p_L) const;
  Eigen::MatrixXd point_jacobian(int link, const Eigen::Vector3d& p_L) const;
  Eigen::Vector3d point_jacobian_dot_v(int link, const Eigen::Vector3d& p_L) const;
  // Frame at p_L in link L: 6 x nv Jacobian [angular; linear] in world axes, and J̇v.
  Eigen::MatrixXd frame_jacobian(int link, const Eigen::Vector3d& p_L) const;
  Eigen::Matrix<double, 6, 1> frame_jacobian_dot_v(int link, const Eigen::Vector3d& p_L) const;

  Eigen::Vector3d com_position() const;                    // world
  Eigen::MatrixXd com_jacobian() const;                    // 3 x nv
  Eigen::Vector3d com_jacobian_dot_v() const;

  double kinetic_energy() const;
  double potential_energy() const;                         // gravity, zero at z = 0

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dmbd::model
