#pragma once
// The robot model behind dmbd.RobotModel (docs/python.md, "The robot model"): a URDF's
// bare rigid-body tree as Pinocchio users query it. Plain C++ (no pybind11): the values
// model::RobotDynamics computes (the tree kernel) or, with Engine::Simbody, Simbody's own
// operators (model::SimbodyReference), in the Python API's conventions:
//   - coordinates are RobotDynamics' (floating base: q = [quaternion w x y z, origin, joints],
//     v = [angular velocity in world, origin velocity in world, joint rates]);
//   - frames are the links (and the joints: a URDF joint's frame is its child link's);
//   - frame Jacobians are 6 x nv with the rows [linear; angular] (Pinocchio's order) in the
//     reference frame asked for: LOCAL, WORLD or LOCAL_WORLD_ALIGNED, as Pinocchio means them.
// Every argument is checked: a wrong size, a non-finite entry, a zero quaternion or an
// unknown frame is an InputError with a one-line message.
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "dmbd/model/dynamics.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/model/simbody_reference.hpp"
#include "dmbd/wholebody/robot_model.hpp"

namespace dmbd::python {

enum class ReferenceFrame { Local, World, LocalWorldAligned };
enum class Engine { Kernel, Simbody };

// "kernel" or "simbody"; InputError otherwise.
Engine engine_named(const std::string& name);

class RobotModel {
 public:
  // A robot folder's NAME (robots/NAME, the robot search path) or a URDF file; base
  // "fixed" (the root link welded at the world origin) or "floating"; gravity along -z.
  static std::unique_ptr<RobotModel> load(const std::string& name_or_urdf, const std::string& base, double gravity_m_s2);
  RobotModel(model::RobotDescription robot, model::BaseMode base, double gravity_m_s2);
  RobotModel(const RobotModel&) = delete;
  RobotModel& operator=(const RobotModel&) = delete;

  const model::RobotDescription& description() const { return *robot_; }
  const model::RobotDynamics& dynamics() const { return *dynamics_; }
  const wholebody::Layout& layout() const { return layout_; }
  bool floating() const { return layout_.base_dofs == 6; }
  double gravity_m_s2() const { return gravity_; }
  std::vector<std::string> link_names() const;
  std::vector<std::string> frame_names() const;  // the links, then the joints
  // Description joint index -> its index into q / v, or -1 (fixed or welded).
  int joint_q_index(int description_joint) const;
  int joint_v_index(int description_joint) const;
  // Limits per coordinate (±inf on the base and where the URDF gives none).
  Eigen::VectorXd lower_position_limit() const;
  Eigen::VectorXd upper_position_limit() const;
  Eigen::VectorXd velocity_limit() const;
  Eigen::VectorXd effort_limit() const;

  Eigen::VectorXd neutral() const;
  Eigen::VectorXd integrate(const Eigen::VectorXd& q, const Eigen::VectorXd& v) const;
  Eigen::VectorXd difference(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const;

  Eigen::MatrixXd mass_matrix(const Eigen::VectorXd& q, Engine e);
  Eigen::VectorXd bias_forces(const Eigen::VectorXd& q, const Eigen::VectorXd& v, Engine e);
  Eigen::VectorXd gravity_forces(const Eigen::VectorXd& q, Engine e);
  Eigen::VectorXd forward_dynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& tau, Engine e);
  Eigen::VectorXd inverse_dynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& vdot, Engine e);
  Eigen::Isometry3d frame_placement(const Eigen::VectorXd& q, const std::string& frame, Engine e);
  Eigen::MatrixXd frame_jacobian(const Eigen::VectorXd& q, const std::string& frame, ReferenceFrame rf, Engine e);
  Eigen::Vector3d com(const Eigen::VectorXd& q, Engine e);
  Eigen::MatrixXd com_jacobian(const Eigen::VectorXd& q, Engine e);

 private:
  void check_configuration(const Eigen::VectorXd& q, const char* what) const;
  void check_vector(const Eigen::VectorXd& x, int n, const char* what, const char* size_name) const;
  // Sets (q, v) on the engine asked for (v = 0 when not given).
  void set_state(const Eigen::VectorXd& q, const Eigen::VectorXd* v, Engine e);
  model::SimbodyReference& reference();
  int frame_link(const std::string& frame) const;

  std::unique_ptr<model::RobotDescription> robot_;  // RobotDynamics keeps a reference
  model::DynamicsOptions options_;
  double gravity_;
  std::unique_ptr<model::RobotDynamics> dynamics_;
  std::unique_ptr<model::SimbodyReference> reference_;  // made when first asked for
  wholebody::Layout layout_;
  std::vector<int> joint_q_, joint_v_;  // per description joint
};

}  // namespace dmbd::python
