// sim::DynamicsModel: wholebody's robot model over model::RobotDynamics.
#include "dmbd/control/dynamics_model.hpp"

#include <cassert>
#include <limits>

#include "dmbd/base/error.hpp"

namespace dmbd::control {

namespace {

double or_infinite(double v) { return v > 0 ? v : std::numeric_limits<double>::infinity(); }

}  // namespace

wholebody::Layout layout_of(const model::RobotDescription& robot, const model::RobotDynamics& dyn) {
  wholebody::Layout l;
  l.nq = dyn.nq();
  l.nv = dyn.nv();
  l.base_dofs = dyn.base_dofs();
  const auto& names = dyn.joint_names();
  for (int j = 0; j < static_cast<int>(names.size()); ++j) {
    const model::Joint& urdf = robot.joints[static_cast<size_t>(robot.joint_index(names[static_cast<size_t>(j)]))];
    wholebody::Joint joint;
    joint.name = names[static_cast<size_t>(j)];
    joint.q_index = dyn.joint_q_index(j);
    joint.v_index = dyn.joint_v_index(j);
    if (urdf.has_limits && urdf.upper > urdf.lower && urdf.type != model::JointType::Continuous) {
      joint.limits.lower_rad = urdf.lower;
      joint.limits.upper_rad = urdf.upper;
    }
    joint.limits.effort_Nm = or_infinite(urdf.effort);
    joint.limits.velocity_rad_s = or_infinite(urdf.velocity);
    l.joints.push_back(joint);
  }
  return l;
}

DynamicsModel::DynamicsModel(const model::RobotDescription& robot, const model::DynamicsOptions& options)
    : robot_(std::make_unique<model::RobotDescription>(robot)),
      dynamics_(std::make_unique<model::RobotDynamics>(*robot_, options)),
      layout_(layout_of(*robot_, *dynamics_)) {
  for (const wholebody::Joint& j : layout_.joints) {
    const double armature = robot_->joints[static_cast<size_t>(robot_->joint_index(j.name))].armature;
    if (armature > 0) armature_.emplace_back(j.v_index, armature);
  }
}

int DynamicsModel::add_frame(const wholebody::FrameSpec& frame) {
  const int link = dynamics_->link_index(frame.link);
  if (link < 0) throw InputError("frame: robot '" + robot_->name + "' has no link '" + frame.link + "'");
  frames_.push_back({link, frame.p_L});
  return static_cast<int>(frames_.size()) - 1;
}

void DynamicsModel::update(const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& v,
                           wholebody::ModelData& data) {
  assert(data.frames.size() == frames_.size() && data.A.rows() == layout_.nv);
  data.q = q;
  data.v = v;
  dynamics_->set_state(q, v);
  dynamics_->mass_matrix(data.A);
  for (const auto& [index, armature] : armature_) data.A(index, index) += armature;
  dynamics_->coriolis_and_gravity(data.bg);
  dynamics_->gravity(data.g);
  for (size_t k = 0; k < frames_.size(); ++k) {
    const Frame& f = frames_[k];
    wholebody::FrameData& out = data.frames[k];
    out.X_WF = dynamics_->link_pose(f.link);
    out.X_WF.translation() = dynamics_->point_position(f.link, f.p_L);
    dynamics_->frame_jacobian(f.link, f.p_L, out.J);
    out.Jdot_v = dynamics_->frame_jacobian_dot_v(f.link, f.p_L);
  }
  data.com = dynamics_->com_position();
  dynamics_->com_jacobian(data.J_com);
  data.com_Jdot_v = dynamics_->com_jacobian_dot_v();
}

}  // namespace dmbd::control
