#pragma once
// Simbody's own answers for what RobotDynamics computes, for cross-checks (the Python
// robot model's engine="simbody", docs/python.md; tests). Its own Simbody system, built
// from the description by the same routine as the tree kernel (so the coordinates are
// RobotDynamics'), with Simbody's uniform gravity (Force::Gravity along -z of the world).
// Each query realises Simbody's State and calls one of its operators:
//   mass matrix            SimbodyMatterSubsystem::calcM
//   b + g, inverse dyn.    calcResidualForceIgnoringConstraints (O(n) recursive Newton-Euler)
//                          with Force::Gravity's body forces
//   forward dynamics       calcAccelerationIgnoringConstraints (O(n) articulated body)
//   link pose              MobilizedBody::getBodyTransform
//   frame Jacobian         calcFrameJacobian
//   centre of mass         calcSystemMassCenterLocationInGround; its Jacobian one column
//                          per mobility, calcSystemMassCenterVelocityInGround at a unit u
// Slow and allocating (a State realised per call): never in a control loop.
#include "dmbd/model/dynamics.hpp"
#include "dmbd/model/robot_description.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <memory>

namespace dmbd::model {

class SimbodyReference {
 public:
  // The description must outlive the reference.
  SimbodyReference(const RobotDescription& robot, const DynamicsOptions& options = {});
  ~SimbodyReference();
  SimbodyReference(const SimbodyReference&) = delete;
  SimbodyReference& operator=(const SimbodyReference&) = delete;

  int nq() const;
  int nv() const;

  // The state every query below uses (quaternions normalised). Throws ModelError for a
  // wrong size, as RobotDynamics::set_state.
  void set_state(const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& v);

  Eigen::MatrixXd mass_matrix() const;                              // A(q), nv x nv
  Eigen::VectorXd coriolis_and_gravity() const;                     // b + g at (q, v)
  Eigen::VectorXd gravity() const;                                  // g(q)
  Eigen::VectorXd inverse_dynamics(const Eigen::Ref<const Eigen::VectorXd>& vdot) const;  // A vdot + b + g
  Eigen::VectorXd forward_dynamics(const Eigen::Ref<const Eigen::VectorXd>& tau) const;   // vdot

  Eigen::Isometry3d link_pose(int link) const;                      // X_WL
  // 6 x nv, [angular; linear] in world axes, the linear part the velocity of the point
  // p_L fixed in the link (as RobotDynamics::frame_jacobian).
  Eigen::MatrixXd frame_jacobian(int link, const Eigen::Vector3d& p_L) const;
  Eigen::Vector3d com_position() const;                             // world
  Eigen::MatrixXd com_jacobian() const;                             // 3 x nv

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dmbd::model
