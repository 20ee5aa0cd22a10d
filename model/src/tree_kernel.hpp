#pragma once
// Internal to model/: the bare multibody tree of a RobotDescription (links and joints,
// no force elements) and the rigid-body quantities the plant's steppers and
// RobotDynamics read, written into storage sized once at construction.
//
// Simbody builds the tree; the kinematics (body poses, hinge columns, body velocities,
// bias accelerations and the forces they take) are realised here, one outward pass per
// stage over the mobilizers (mobilizer.hpp), and the dynamics terms assembled from them,
// in world axes about the world origin O:
//   - mass matrix by the composite-rigid-body algorithm, M_ij = S_i^T I^c S_j;
//   - Coriolis + gravity c = sum_b J_b^T (F_centrifugal,b - F_gravity,b);
//   - point, frame and centre-of-mass Jacobians from the hinge columns.
// Why not Simbody's calcM / calcResidualForceIgnoringConstraints / calcStationJacobian:
// on Debian's Simbody 3.7 they allocate (52, 10 and several heap blocks per call), and
// calcM and calcStationJacobian cost 13-20 us and 25-35 us on DRACO; a fixed time step
// and a controller update must not allocate and have a ~50 us budget. Tests check every
// term here against those Simbody operators (tests/model/test_kernel_tree.cpp).
//
// Coordinates are Simbody's, in mobilized-body order: for DRACO, q = [torso quaternion
// w x y z, torso origin (world), joints], v = [torso angular velocity (world), torso
// origin velocity (world), joint rates]. A fixed base has no base coordinates.
#include "dmbd/model/dynamics.hpp"
#include "dmbd/model/robot_description.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <memory>
#include <string>
#include <vector>

namespace dmbd::model::detail {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

class TreeKernel {
 public:
  // `mass_taken[l]` (kg, may be empty) is removed from link l at its centre of mass:
  // actuator housings modelled as separate point masses carry it instead.
  TreeKernel(const RobotDescription& robot, BaseMode base, const Eigen::Isometry3d& X_WB, double gravity_m_s2,
             const std::vector<double>& mass_taken = {});
  ~TreeKernel();
  TreeKernel(const TreeKernel&) = delete;
  TreeKernel& operator=(const TreeKernel&) = delete;

  int nq() const;
  int nv() const;
  int base_dofs() const;                               // 6 floating, 0 fixed
  int num_bodies() const;                              // mobilized bodies, ground (0) included
  int body_of_link(int link) const;                    // description link -> body
  // The 1-dof joints (revolute, continuous, prismatic) in description order.
  const std::vector<std::string>& joint_names() const;
  const std::vector<int>& joint_description_index() const;
  const std::vector<std::string>& welded_joints() const;
  int joint_q(int joint) const;                        // its index into q
  int joint_v(int joint) const;                        // its index into v
  int joint_body(int joint) const;                     // the body it moves
  int parent_body(int body) const;                     // -1 for ground
  double total_mass_kg() const;
  double body_mass_kg(int body) const;
  double gravity_m_s2() const;

  // State. set_q/set_v invalidate what depends on them; queries realise lazily.
  void set_q(const Eigen::Ref<const Eigen::VectorXd>& q);
  void set_v(const Eigen::Ref<const Eigen::VectorXd>& v);
  const Eigen::VectorXd& q() const;
  const Eigen::VectorXd& v() const;
  // A default configuration: identity quaternions, zero elsewhere (the base at X_WB).
  Eigen::VectorXd neutral_q() const;
  // Sets the floating base's coordinates so its frame is X_WB (no-op for a fixed base).
  void set_base_pose(Eigen::Ref<Eigen::VectorXd> q, const Eigen::Isometry3d& X_WB) const;

  // Kinematics at q (and v).
  Eigen::Isometry3d pose(int body) const;              // X_WB
  const Eigen::Matrix3d& rotation(int body) const;     // R_WB
  const Eigen::Vector3d& origin(int body) const;       // p_WBo
  Eigen::Vector3d angular_velocity(int body) const;    // omega_WB, world
  Eigen::Vector3d point_velocity(int body, const Eigen::Vector3d& p_W) const;
  // Jacobians of a point fixed on `body`, now at p_W: linear 3 x nv, or [angular; linear]
  // 6 x nv. Columns of mobilities that do not move the body are zero.
  void point_jacobian(int body, const Eigen::Vector3d& p_W, Eigen::Ref<Eigen::MatrixXd> J) const;
  void frame_jacobian(int body, const Eigen::Vector3d& p_W, Eigen::Ref<Eigen::MatrixXd> J) const;
  // The mobilities that move `body` (ascending): its Jacobians are zero elsewhere.
  const std::vector<int>& body_mobilities(int body) const;
  // The same Jacobians restricted to those columns (3 x m or 6 x m, m = their number).
  void point_jacobian_columns(int body, const Eigen::Vector3d& p_W, Eigen::Ref<Eigen::Matrix3Xd> J) const;
  void frame_jacobian_columns(int body, const Eigen::Vector3d& p_W,
                              Eigen::Ref<Eigen::Matrix<double, 6, Eigen::Dynamic>> J) const;
  // J-dot v of the point (the acceleration it has when vdot = 0), world.
  Eigen::Vector3d point_bias_acceleration(int body, const Eigen::Vector3d& p_W) const;
  Vector6d frame_bias_acceleration(int body, const Eigen::Vector3d& p_W) const;  // [angular; linear]

  // Dynamics at (q, v): M vdot + c = tau with c = Coriolis + gravity.
  void mass_matrix(Eigen::Ref<Eigen::MatrixXd> M) const;
  void coriolis_and_gravity(Eigen::Ref<Eigen::VectorXd> c) const;
  void gravity(Eigen::Ref<Eigen::VectorXd> g) const;
  void coriolis(Eigen::Ref<Eigen::VectorXd> c) const;

  Eigen::Vector3d com() const;
  void com_jacobian(Eigen::Ref<Eigen::MatrixXd> J) const;   // 3 x nv
  Eigen::Vector3d com_bias_acceleration() const;
  double kinetic_energy() const;
  double gravity_potential() const;                         // zero at z = 0

  // Simbody's own operators at the same state, for cross-checks in tests only (they
  // realise Simbody's State and allocate): calcM, calcResidualForceIgnoringConstraints
  // with gravity, station Jacobian and its bias, body pose and velocity, N(q).
  void reference_mass_matrix(Eigen::Ref<Eigen::MatrixXd> M) const;
  void reference_coriolis_and_gravity(Eigen::Ref<Eigen::VectorXd> c) const;
  void reference_point_jacobian(int body, const Eigen::Vector3d& p_W, Eigen::Ref<Eigen::MatrixXd> J) const;
  Eigen::Vector3d reference_point_bias_acceleration(int body, const Eigen::Vector3d& p_W) const;
  Eigen::Isometry3d reference_pose(int body) const;
  Vector6d reference_velocity(int body) const;         // [angular; velocity of the body's origin]
  void reference_qdot(const Eigen::Ref<const Eigen::VectorXd>& v, Eigen::Ref<Eigen::VectorXd> qd) const;

  // qdot = N(q) v at the current q.
  void qdot(const Eigen::Ref<const Eigen::VectorXd>& v, Eigen::Ref<Eigen::VectorXd> qd) const;
  // q <- q + h N(q) v with quaternions renormalised (N at the current q: set_q(q) first).
  void integrate(Eigen::Ref<Eigen::VectorXd> q, const Eigen::Ref<const Eigen::VectorXd>& v, double h) const;
  // Normalises the quaternions in q.
  void normalize(Eigen::Ref<Eigen::VectorXd> q) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dmbd::model::detail
