// The model interface's shared parts: storage sizing and configuration arithmetic.
#include "dmbd/wholebody/robot_model.hpp"

#include <cassert>

namespace dmbd::wholebody {

int Layout::joint_index(const std::string& name) const {
  for (size_t k = 0; k < joints.size(); ++k)
    if (joints[k].name == name) return static_cast<int>(k);
  return -1;
}

ModelData RobotModel::make_data() const {
  const Layout& l = layout();
  ModelData d;
  d.q = Eigen::VectorXd::Zero(l.nq);
  d.v = Eigen::VectorXd::Zero(l.nv);
  d.A = Eigen::MatrixXd::Zero(l.nv, l.nv);
  d.bg = Eigen::VectorXd::Zero(l.nv);
  d.g = Eigen::VectorXd::Zero(l.nv);
  d.frames.resize(static_cast<size_t>(num_frames()));
  for (FrameData& f : d.frames) f.J = Eigen::Matrix<double, 6, Eigen::Dynamic>::Zero(6, l.nv);
  d.J_com = Eigen::Matrix<double, 3, Eigen::Dynamic>::Zero(3, l.nv);
  return d;
}

namespace {

// The base's quaternion (w x y z at q[0..3]) and the rotation of a world-axes rotation
// vector, as quaternions.
Eigen::Quaterniond base_quaternion(const Eigen::Ref<const Eigen::VectorXd>& q) {
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized();
}

Eigen::Quaterniond exp_map(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle < 1e-12) return Eigen::Quaterniond(1.0, 0.5 * w.x(), 0.5 * w.y(), 0.5 * w.z()).normalized();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, w / angle));
}

}  // namespace

void integrate(const Layout& layout, const Eigen::Ref<const Eigen::VectorXd>& q,
               const Eigen::Ref<const Eigen::VectorXd>& v, double dt, Eigen::Ref<Eigen::VectorXd> q_out) {
  assert(q.size() == layout.nq && v.size() == layout.nv && q_out.size() == layout.nq);
  const int nj = layout.nv - layout.base_dofs;
  if (layout.base_dofs == 6) {
    // World-axes angular velocity: R(t + dt) = exp([ω dt]) R(t).
    const Eigen::Quaterniond Q = (exp_map(v.head<3>() * dt) * base_quaternion(q)).normalized();
    q_out[0] = Q.w();
    q_out[1] = Q.x();
    q_out[2] = Q.y();
    q_out[3] = Q.z();
    q_out.segment<3>(4) = q.segment<3>(4) + v.segment<3>(3) * dt;
  }
  q_out.tail(nj) = q.tail(nj) + v.tail(nj) * dt;
}

void difference(const Layout& layout, const Eigen::Ref<const Eigen::VectorXd>& q0,
                const Eigen::Ref<const Eigen::VectorXd>& q1, Eigen::Ref<Eigen::VectorXd> v_out) {
  assert(q0.size() == layout.nq && q1.size() == layout.nq && v_out.size() == layout.nv);
  const int nj = layout.nv - layout.base_dofs;
  if (layout.base_dofs == 6) {
    const Eigen::AngleAxisd aa(base_quaternion(q1) * base_quaternion(q0).conjugate());
    double angle = aa.angle();
    Eigen::Vector3d axis = aa.axis();
    if (angle > M_PI) {  // the shorter way round
      angle = 2.0 * M_PI - angle;
      axis = -axis;
    }
    v_out.head<3>() = axis * angle;
    v_out.segment<3>(3) = q1.segment<3>(4) - q0.segment<3>(4);
  }
  v_out.tail(nj) = q1.tail(nj) - q0.tail(nj);
}

}  // namespace dmbd::wholebody
