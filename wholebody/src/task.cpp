// Tasks: Jacobian, J̇v, errors and the commanded task acceleration (task.hpp).
#include "dmbd/wholebody/task.hpp"

#include <cassert>

#include "dmbd/base/error.hpp"

namespace dmbd::wholebody {

Task::Task(int dim, int nv)
    : J_(Eigen::MatrixXd::Zero(dim, nv)),
      Jdot_v_(Eigen::VectorXd::Zero(dim)),
      e_(Eigen::VectorXd::Zero(dim)),
      edot_(Eigen::VectorXd::Zero(dim)),
      xdd_cmd_(Eigen::VectorXd::Zero(dim)),
      kp_(Eigen::VectorXd::Zero(dim)),
      kd_(Eigen::VectorXd::Zero(dim)) {}

void Task::set_gains(const Eigen::Ref<const Eigen::VectorXd>& kp, const Eigen::Ref<const Eigen::VectorXd>& kd) {
  if (kp.size() != dim() || kd.size() != dim())
    throw InputError("task gains: expected " + std::to_string(dim()) + " values each");
  kp_ = kp;
  kd_ = kd;
}

void Task::set_gains(double kp, double kd) {
  kp_.setConstant(kp);
  kd_.setConstant(kd);
}

void Task::finish(const Eigen::Ref<const Eigen::VectorXd>& xdd_d) {
  xdd_cmd_ = xdd_d + kp_.cwiseProduct(e_) + kd_.cwiseProduct(edot_);
}

// --- PointTask ---------------------------------------------------------------------

PointTask::PointTask(int frame, int nv, int relative_to_frame) : Task(3, nv), frame_(frame), relative_to_(relative_to_frame) {}

void PointTask::set_reference(const Eigen::Vector3d& p, const Eigen::Vector3d& v, const Eigen::Vector3d& a) {
  p_d_ = p;
  v_d_ = v;
  a_d_ = a;
}

void PointTask::update(const ModelData& data) {
  const FrameData& f = data.frames[static_cast<size_t>(frame_)];
  J_ = f.J.bottomRows<3>();
  Jdot_v_ = f.Jdot_v.tail<3>();
  p_ = f.X_WF.translation();
  if (relative_to_ >= 0) {
    const FrameData& b = data.frames[static_cast<size_t>(relative_to_)];
    J_ -= b.J.bottomRows<3>();
    Jdot_v_ -= b.Jdot_v.tail<3>();
    p_ -= b.X_WF.translation();
  }
  e_ = p_d_ - p_;
  edot_.noalias() = -J_ * data.v;
  edot_ += v_d_;
  finish(a_d_);
}

// --- OrientationTask ---------------------------------------------------------------

OrientationTask::OrientationTask(int frame, int nv) : Task(3, nv), frame_(frame) {}

void OrientationTask::set_reference(const Eigen::Matrix3d& R_d, const Eigen::Vector3d& w_d,
                                    const Eigen::Vector3d& dw_d) {
  R_d_ = R_d;
  w_d_ = w_d;
  dw_d_ = dw_d;
}

void OrientationTask::update(const ModelData& data) {
  const FrameData& f = data.frames[static_cast<size_t>(frame_)];
  J_ = f.J.topRows<3>();
  Jdot_v_ = f.Jdot_v.head<3>();
  // The rotation from the frame to the target, in world axes: R_d = exp([e]) R.
  const Eigen::AngleAxisd aa(Eigen::Matrix3d(R_d_ * f.X_WF.rotation().transpose()));
  e_ = aa.axis() * aa.angle();
  edot_.noalias() = -J_ * data.v;
  edot_ += w_d_;
  finish(dw_d_);
}

// --- ComTask -----------------------------------------------------------------------

ComTask::ComTask(int nv) : Task(3, nv) {}

void ComTask::set_reference(const Eigen::Vector3d& p, const Eigen::Vector3d& v, const Eigen::Vector3d& a) {
  p_d_ = p;
  v_d_ = v;
  a_d_ = a;
}

void ComTask::update(const ModelData& data) {
  J_ = data.J_com;
  Jdot_v_ = data.com_Jdot_v;
  e_ = p_d_ - data.com;
  edot_.noalias() = -J_ * data.v;
  edot_ += v_d_;
  finish(a_d_);
}

// --- PostureTask -------------------------------------------------------------------

PostureTask::PostureTask(const Layout& layout, std::vector<int> joints)
    : Task(static_cast<int>(joints.size()), layout.nv),
      q_d_(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(joints.size()))),
      qd_d_(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(joints.size()))),
      qdd_d_(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(joints.size()))) {
  for (size_t r = 0; r < joints.size(); ++r) {
    const int j = joints[r];
    if (j < 0 || j >= static_cast<int>(layout.joints.size()))
      throw InputError("posture task: joint index " + std::to_string(j) + " is not a joint of the model");
    q_index_.push_back(layout.joints[static_cast<size_t>(j)].q_index);
    v_index_.push_back(layout.joints[static_cast<size_t>(j)].v_index);
    J_(static_cast<Eigen::Index>(r), v_index_.back()) = 1.0;  // a selection: J̇ = 0
  }
}

void PostureTask::set_reference(const Eigen::Ref<const Eigen::VectorXd>& q_d,
                                const Eigen::Ref<const Eigen::VectorXd>& qd_d,
                                const Eigen::Ref<const Eigen::VectorXd>& qdd_d) {
  assert(q_d.size() == dim() && qd_d.size() == dim() && qdd_d.size() == dim());
  q_d_ = q_d;
  qd_d_ = qd_d;
  qdd_d_ = qdd_d;
}

void PostureTask::update(const ModelData& data) {
  for (size_t r = 0; r < q_index_.size(); ++r) {
    const auto i = static_cast<Eigen::Index>(r);
    e_[i] = q_d_[i] - data.q[q_index_[r]];
    edot_[i] = qd_d_[i] - data.v[v_index_[r]];
  }
  finish(qdd_d_);
}

}  // namespace dmbd::wholebody
