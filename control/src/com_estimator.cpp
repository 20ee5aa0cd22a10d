// KinematicComEstimator (com_estimator.hpp): two passes of the model's kinematics, the
// first with the base at the origin and no linear velocity to find where the stance foot
// would be, the second at the base position and velocity that put it back.
#include "dmbd/control/com_estimator.hpp"

#include <cassert>

namespace dmbd::control {

namespace {

model::DynamicsOptions floating() {
  model::DynamicsOptions o;
  o.base = model::BaseMode::Floating;
  return o;
}

}  // namespace

KinematicComEstimator::KinematicComEstimator(const model::RobotDescription& robot, const wholebody::FrameSpec& left_foot,
                                             const wholebody::FrameSpec& right_foot)
    : model_(robot, floating()) {
  foot_frame_[0] = model_.add_frame(left_foot);
  foot_frame_[1] = model_.add_frame(right_foot);
  data_ = model_.make_data();
  q_ = Eigen::VectorXd::Zero(model_.layout().nq);
  v_ = Eigen::VectorXd::Zero(model_.layout().nv);
}

void KinematicComEstimator::set_stance(wholebody::Side side, const Eigen::Vector3d& foot_W) {
  stance_ = side;
  stance_foot_W_ = foot_W;
}

const ComEstimate& KinematicComEstimator::update(const Eigen::Quaterniond& R_WB, const Eigen::Vector3d& omega_W,
                                                 const Eigen::Ref<const Eigen::VectorXd>& joint_q,
                                                 const Eigen::Ref<const Eigen::VectorXd>& joint_v) {
  const wholebody::Layout& l = model_.layout();
  assert(joint_q.size() == static_cast<Eigen::Index>(l.joints.size()) && joint_v.size() == joint_q.size());
  const Eigen::Quaterniond Q = R_WB.normalized();
  q_.head<4>() << Q.w(), Q.x(), Q.y(), Q.z();
  q_.segment<3>(4).setZero();
  v_.head<3>() = omega_W;
  v_.segment<3>(3).setZero();
  for (size_t j = 0; j < l.joints.size(); ++j) {
    q_[l.joints[j].q_index] = joint_q[static_cast<Eigen::Index>(j)];
    v_[l.joints[j].v_index] = joint_v[static_cast<Eigen::Index>(j)];
  }
  const auto& foot = data_.frames[static_cast<size_t>(foot_frame_[static_cast<int>(stance_)])];
  model_.update(q_, v_, data_);
  // Translating the base by p moves the foot by p; a base velocity u moves it at u.
  estimate_.base_position_m = stance_foot_W_ - foot.X_WF.translation();
  estimate_.base_velocity_m_s = -(foot.J.bottomRows<3>() * v_);
  q_.segment<3>(4) = estimate_.base_position_m;
  v_.segment<3>(3) = estimate_.base_velocity_m_s;
  model_.update(q_, v_, data_);
  estimate_.com_m = data_.com;
  estimate_.com_velocity_m_s.noalias() = data_.J_com * v_;
  return estimate_;
}

}  // namespace dmbd::control
