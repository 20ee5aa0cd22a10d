// BalanceController: the state estimate (balance_controller.hpp, step 1). The joints
// from their sensors; the torso's orientation and angular velocity from the IMU; its
// position and velocity from the stance foot's kinematics (KinematicComEstimator, the
// stance foot's contact point latched where it was when the other foot lifted) or from
// motion capture (the true values plus white noise, the paper's CoM velocity source).
#include <algorithm>
#include <cmath>

#include "balance_impl.hpp"

namespace dmbd::control {

namespace {

// R = Rz(yaw) Ry(pitch) Rx(roll), as the bus gives the torso's orientation.
Eigen::Quaterniond from_rpy(double roll, double pitch, double yaw) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
}

}  // namespace

void BalanceController::Impl::read_state(const double* u) {
  const wholebody::Layout& l = model.layout();
  for (int j = 0; j < nj; ++j) {
    joint_q[j] = u[2 * j];
    joint_v[j] = u[2 * j + 1];
  }
  const double* imu = u + 2 * nj;
  const Eigen::Quaterniond R = from_rpy(imu[0], imu[1], imu[2]);
  const Eigen::Vector3d omega(imu[3], imu[4], imu[5]);
  tilt = std::acos(std::clamp(R.toRotationMatrix()(2, 2), -1.0, 1.0));
  if (tick == 0 && setup.estimator == BalanceEstimator::Kinematic) {
    // The world's origin under the base at the start, the left foot's sphere centres at
    // its height above the ground on the first tick (0.03 m for DRACO's feet).
    estimator.set_stance(Side::Left, Eigen::Vector3d::Zero());
    const ComEstimate& e0 = estimator.update(R, omega, joint_q, joint_v);
    const double sphere_radius = 0.03;
    estimator.set_stance(Side::Left, Eigen::Vector3d(-e0.base_position_m.x(), -e0.base_position_m.y(), sphere_radius));
  }
  q.head<4>() << R.w(), R.x(), R.y(), R.z();
  v.head<3>() = omega;
  if (setup.estimator == BalanceEstimator::Kinematic) {
    const ComEstimate& e = estimator.update(R, omega, joint_q, joint_v);
    q.segment<3>(4) = e.base_position_m;
    v.segment<3>(3) = e.base_velocity_m_s;
  } else {
    const double* mocap = imu + 6;
    for (int i = 0; i < 3; ++i) {
      q[4 + i] = mocap[i] + setup.mocap_position_noise_m * normal(rng);
      v[3 + i] = mocap[3 + i] + setup.mocap_velocity_noise_m_s * normal(rng);
    }
  }
  for (int j = 0; j < nj; ++j) {
    q[l.joints[static_cast<size_t>(j)].q_index] = joint_q[j];
    v[l.joints[static_cast<size_t>(j)].v_index] = joint_v[j];
  }
  model.update(q, v, data);
}

Eigen::Vector3d BalanceController::Impl::foot_point(Side s) const {
  return data.frames[static_cast<size_t>(foot_frame[static_cast<size_t>(s)])].X_WF.translation();
}

}  // namespace dmbd::control
