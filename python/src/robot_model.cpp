// The Python robot model's computations (robot_model.hpp): arguments checked, the state set
// on the engine asked for, and Jacobians turned into Pinocchio's row order and reference
// frames. Configuration arithmetic is wholebody's (the controllers' own integrate and
// difference, same coordinates).
#include "robot_model.hpp"

#include <cmath>
#include <filesystem>
#include <limits>

#include "dmbd/base/error.hpp"
#include "dmbd/base/strings.hpp"
#include "dmbd/control/dynamics_model.hpp"
#include "dmbd/model/equations_of_motion.hpp"
#include "dmbd/model/error.hpp"
#include "dmbd/model/robot_folder.hpp"

namespace dmbd::python {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

bool names_a_file(const std::string& s) {
  std::error_code ec;
  return s.find('/') != std::string::npos || (s.size() > 5 && s.compare(s.size() - 5, 5, ".urdf") == 0) ||
         std::filesystem::is_regular_file(s, ec);
}

// Refuses what the model's coordinates do not cover: a second floating body or a planar
// joint inside the tree would put quaternions or 3-dof joints among the joint coordinates.
void check_joint_kinds(const model::RobotDescription& robot) {
  for (const model::Joint& j : robot.joints)
    if (j.type == model::JointType::Floating || j.type == model::JointType::Planar)
      throw model::ModelError(robot.source + ": joint '" + j.name + "' is " + model::joint_type_name(j.type) +
                              ": the robot model takes revolute, continuous, prismatic and fixed joints (choose a "
                              "floating root with base='floating')");
}

Eigen::Matrix3d skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d S;
  S << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return S;
}

}  // namespace

Engine engine_named(const std::string& name) {
  if (name == "kernel") return Engine::Kernel;
  if (name == "simbody") return Engine::Simbody;
  throw InputError("engine '" + name + "': expected 'kernel' (the tree kernel) or 'simbody' (Simbody's own operators)");
}

std::unique_ptr<RobotModel> RobotModel::load(const std::string& name_or_urdf, const std::string& base, double gravity_m_s2) {
  if (base != "fixed" && base != "floating") throw InputError("base '" + base + "': expected 'fixed' or 'floating'");
  if (!std::isfinite(gravity_m_s2) || gravity_m_s2 < 0)
    throw InputError("gravity " + std::to_string(gravity_m_s2) + ": expected a finite number >= 0 (m/s², along -z)");
  if (name_or_urdf.empty()) throw InputError("load_robot: expected a robot's name (robots/NAME) or a URDF file, got ''");
  const std::string urdf = names_a_file(name_or_urdf) ? name_or_urdf : model::find_robot(name_or_urdf).urdf;
  model::UrdfOptions options;
  options.load_meshes = false;  // the dynamics need no mesh
  return std::make_unique<RobotModel>(model::load_urdf(urdf, options),
                                      base == "floating" ? model::BaseMode::Floating : model::BaseMode::Fixed, gravity_m_s2);
}

RobotModel::RobotModel(model::RobotDescription robot, model::BaseMode base, double gravity_m_s2)
    : robot_(std::make_unique<model::RobotDescription>(std::move(robot))), gravity_(gravity_m_s2) {
  check_joint_kinds(*robot_);
  options_.base = base;
  options_.gravity_m_s2 = gravity_m_s2;
  dynamics_ = std::make_unique<model::RobotDynamics>(*robot_, options_);
  layout_ = control::layout_of(*robot_, *dynamics_);
  joint_q_.assign(robot_->joints.size(), -1);
  joint_v_.assign(robot_->joints.size(), -1);
  for (const wholebody::Joint& j : layout_.joints) {
    const auto d = static_cast<std::size_t>(robot_->joint_index(j.name));
    joint_q_[d] = j.q_index;
    joint_v_[d] = j.v_index;
  }
}

std::vector<std::string> RobotModel::link_names() const {
  std::vector<std::string> n;
  for (const model::Link& l : robot_->links) n.push_back(l.name);
  return n;
}

std::vector<std::string> RobotModel::frame_names() const {
  std::vector<std::string> n = link_names();
  for (const model::Joint& j : robot_->joints) n.push_back(j.name);
  return n;
}

int RobotModel::joint_q_index(int j) const { return joint_q_.at(static_cast<std::size_t>(j)); }
int RobotModel::joint_v_index(int j) const { return joint_v_.at(static_cast<std::size_t>(j)); }

Eigen::VectorXd RobotModel::lower_position_limit() const {
  Eigen::VectorXd x = Eigen::VectorXd::Constant(layout_.nq, -kInf);
  for (const wholebody::Joint& j : layout_.joints) x[j.q_index] = j.limits.lower_rad;
  return x;
}
Eigen::VectorXd RobotModel::upper_position_limit() const {
  Eigen::VectorXd x = Eigen::VectorXd::Constant(layout_.nq, kInf);
  for (const wholebody::Joint& j : layout_.joints) x[j.q_index] = j.limits.upper_rad;
  return x;
}
Eigen::VectorXd RobotModel::velocity_limit() const {
  Eigen::VectorXd x = Eigen::VectorXd::Constant(layout_.nv, kInf);
  for (const wholebody::Joint& j : layout_.joints) x[j.v_index] = j.limits.velocity_rad_s;
  return x;
}
Eigen::VectorXd RobotModel::effort_limit() const {
  Eigen::VectorXd x = Eigen::VectorXd::Constant(layout_.nv, kInf);
  for (const wholebody::Joint& j : layout_.joints) x[j.v_index] = j.limits.effort_Nm;
  return x;
}

void RobotModel::check_vector(const Eigen::VectorXd& x, int n, const char* what, const char* size_name) const {
  if (x.size() != n)
    throw InputError(std::string(what) + " has " + std::to_string(x.size()) + " entries, expected " + size_name + " = " +
                     std::to_string(n));
  for (Eigen::Index i = 0; i < x.size(); ++i)
    if (!std::isfinite(x[i])) throw InputError(std::string(what) + "[" + std::to_string(i) + "] is not finite");
}

void RobotModel::check_configuration(const Eigen::VectorXd& q, const char* what) const {
  check_vector(q, layout_.nq, what, "nq");
  if (floating() && q.head<4>().norm() < 1e-12)
    throw InputError(std::string(what) + "[0:4], the base's quaternion (w x y z), is zero");
}

void RobotModel::set_state(const Eigen::VectorXd& q, const Eigen::VectorXd* v, Engine e) {
  check_configuration(q, "q");
  if (v) check_vector(*v, layout_.nv, "v", "nv");
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(layout_.nv);
  if (e == Engine::Kernel)
    dynamics_->set_state(q, v ? *v : zero);
  else
    reference().set_state(q, v ? *v : zero);
}

model::SimbodyReference& RobotModel::reference() {
  if (!reference_) reference_ = std::make_unique<model::SimbodyReference>(*robot_, options_);
  return *reference_;
}

int RobotModel::frame_link(const std::string& frame) const {
  const int link = robot_->link_index(frame);
  if (link >= 0) return link;
  const int joint = robot_->joint_index(frame);
  if (joint >= 0) return robot_->link_index(robot_->joints[static_cast<std::size_t>(joint)].child);
  throw InputError("robot '" + robot_->name + "' has no frame '" + frame + "' (frames are its links and joints; closest: '" +
                   closest_name(frame, frame_names()) + "')");
}

Eigen::VectorXd RobotModel::neutral() const { return dynamics_->neutral_configuration(); }

Eigen::VectorXd RobotModel::integrate(const Eigen::VectorXd& q, const Eigen::VectorXd& v) const {
  check_configuration(q, "q");
  check_vector(v, layout_.nv, "v", "nv");
  Eigen::VectorXd out(layout_.nq);
  wholebody::integrate(layout_, q, v, 1.0, out);
  return out;
}

Eigen::VectorXd RobotModel::difference(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const {
  check_configuration(q0, "q0");
  check_configuration(q1, "q1");
  Eigen::VectorXd out(layout_.nv);
  wholebody::difference(layout_, q0, q1, out);
  return out;
}

Eigen::MatrixXd RobotModel::mass_matrix(const Eigen::VectorXd& q, Engine e) {
  set_state(q, nullptr, e);
  return e == Engine::Kernel ? dynamics_->mass_matrix() : reference().mass_matrix();
}

Eigen::VectorXd RobotModel::bias_forces(const Eigen::VectorXd& q, const Eigen::VectorXd& v, Engine e) {
  set_state(q, &v, e);
  return e == Engine::Kernel ? dynamics_->coriolis_and_gravity() : reference().coriolis_and_gravity();
}

Eigen::VectorXd RobotModel::gravity_forces(const Eigen::VectorXd& q, Engine e) {
  set_state(q, nullptr, e);
  return e == Engine::Kernel ? dynamics_->gravity() : reference().gravity();
}

Eigen::VectorXd RobotModel::forward_dynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& tau,
                                             Engine e) {
  check_vector(tau, layout_.nv, "tau", "nv");
  set_state(q, &v, e);
  return e == Engine::Kernel ? model::forward_dynamics(*dynamics_, tau) : reference().forward_dynamics(tau);
}

Eigen::VectorXd RobotModel::inverse_dynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& vdot,
                                             Engine e) {
  check_vector(vdot, layout_.nv, "a", "nv");
  set_state(q, &v, e);
  return e == Engine::Kernel ? model::inverse_dynamics(*dynamics_, vdot) : reference().inverse_dynamics(vdot);
}

Eigen::Isometry3d RobotModel::frame_placement(const Eigen::VectorXd& q, const std::string& frame, Engine e) {
  const int link = frame_link(frame);
  set_state(q, nullptr, e);
  return e == Engine::Kernel ? dynamics_->link_pose(link) : reference().link_pose(link);
}

Eigen::MatrixXd RobotModel::frame_jacobian(const Eigen::VectorXd& q, const std::string& frame, ReferenceFrame rf, Engine e) {
  const Eigen::Isometry3d X = frame_placement(q, frame, e);
  const int link = frame_link(frame);
  const Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  // W = [angular; linear] in world axes, the linear rows the frame origin's velocity.
  const Eigen::MatrixXd W = e == Engine::Kernel ? dynamics_->frame_jacobian(link, origin) : reference().frame_jacobian(link, origin);
  const auto w = W.topRows<3>(), v = W.bottomRows<3>();
  Eigen::MatrixXd J(6, layout_.nv);
  switch (rf) {
    case ReferenceFrame::LocalWorldAligned:
      J << v, w;
      break;
    case ReferenceFrame::Local:
      J << X.linear().transpose() * v, X.linear().transpose() * w;
      break;
    case ReferenceFrame::World:  // the velocity of the body's point at the world origin: v - w x p
      J << v + skew(X.translation()) * w, w;
      break;
  }
  return J;
}

Eigen::Vector3d RobotModel::com(const Eigen::VectorXd& q, Engine e) {
  set_state(q, nullptr, e);
  return e == Engine::Kernel ? dynamics_->com_position() : reference().com_position();
}

Eigen::MatrixXd RobotModel::com_jacobian(const Eigen::VectorXd& q, Engine e) {
  set_state(q, nullptr, e);
  return e == Engine::Kernel ? dynamics_->com_jacobian() : reference().com_jacobian();
}

}  // namespace dmbd::python
