// The kinematic CoM estimator (sim/com_estimator.hpp) against the true state: a robot
// whose stance foot is still (its base velocity chosen so) gives back its base position
// and velocity, CoM and CoM velocity exactly (1e-12 m, 1e-12 m/s: the same kinematics,
// two ways round); a foot that slipped by d gives a CoM off by exactly −d.
#include <gtest/gtest.h>

#include <random>

#include "dmbd/model/dynamics.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/control/com_estimator.hpp"

namespace dmbd::control {

namespace {

const Eigen::Vector3d kSole(0.015, 0.0, -0.044);

struct Truth {
  Eigen::VectorXd q, v, joint_q, joint_v;
  Eigen::Vector3d foot_W, com, com_velocity;
};

// A random state whose left foot point is still: the base's linear velocity cancels the
// point's velocity from the rotation and the joints.
Truth random_truth(const model::RobotDescription& robot, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  model::RobotDynamics dyn(robot, model::DynamicsOptions{});
  Truth t;
  t.q = dyn.neutral_configuration();
  t.v = Eigen::VectorXd::Zero(dyn.nv());
  const Eigen::Quaterniond Q = Eigen::Quaterniond(1.0, 0.1 * u(rng), 0.1 * u(rng), 0.3 * u(rng)).normalized();
  t.q.head<4>() << Q.w(), Q.x(), Q.y(), Q.z();
  t.q.segment<3>(4) = Eigen::Vector3d(u(rng), u(rng), 1.0 + 0.1 * u(rng));
  t.v.head<3>() = Eigen::Vector3d(0.5 * u(rng), 0.5 * u(rng), 0.5 * u(rng));
  const int nj = static_cast<int>(dyn.joint_names().size());
  t.joint_q.resize(nj);
  t.joint_v.resize(nj);
  for (int j = 0; j < nj; ++j) {
    t.joint_q[j] = 0.3 * u(rng);
    t.joint_v[j] = u(rng);
    t.q[dyn.joint_q_index(j)] = t.joint_q[j];
    t.v[dyn.joint_v_index(j)] = t.joint_v[j];
  }
  const int foot = dyn.link_index("l_foot");
  dyn.set_state(t.q, t.v);
  t.v.segment<3>(3) = -dyn.point_jacobian(foot, kSole) * t.v;  // the foot point still
  dyn.set_state(t.q, t.v);
  t.foot_W = dyn.point_position(foot, kSole);
  t.com = dyn.com_position();
  t.com_velocity = dyn.com_jacobian() * t.v;
  EXPECT_LT((dyn.point_jacobian(foot, kSole) * t.v).norm(), 1e-12);
  return t;
}

Eigen::Quaterniond orientation(const Truth& t) { return Eigen::Quaterniond(t.q[0], t.q[1], t.q[2], t.q[3]); }

TEST(KinematicComEstimator, AStillStanceFootGivesTheTrueCom) {
  const model::RobotDescription robot = model::load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf");
  KinematicComEstimator est(robot, {"l_foot", kSole}, {"r_foot", kSole});
  std::mt19937 rng(21);
  for (int trial = 0; trial < 10; ++trial) {
    const Truth t = random_truth(robot, rng);
    est.set_stance(wholebody::Side::Left, t.foot_W);
    const ComEstimate& e = est.update(orientation(t), t.v.head<3>(), t.joint_q, t.joint_v);
    EXPECT_LT((e.base_position_m - t.q.segment<3>(4)).norm(), 1e-12) << trial;
    EXPECT_LT((e.base_velocity_m_s - t.v.segment<3>(3)).norm(), 1e-12) << trial;
    EXPECT_LT((e.com_m - t.com).norm(), 1e-12) << trial;
    EXPECT_LT((e.com_velocity_m_s - t.com_velocity).norm(), 1e-12) << trial;
  }
}

TEST(KinematicComEstimator, ASlippedFootShiftsTheEstimateByTheSlip) {
  const model::RobotDescription robot = model::load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf");
  KinematicComEstimator est(robot, {"l_foot", kSole}, {"r_foot", kSole});
  std::mt19937 rng(22);
  const Truth t = random_truth(robot, rng);
  const Eigen::Vector3d slip(0.02, -0.01, 0.0);
  est.set_stance(wholebody::Side::Left, t.foot_W - slip);  // latched before the foot slid by slip
  const ComEstimate& e = est.update(orientation(t), t.v.head<3>(), t.joint_q, t.joint_v);
  EXPECT_LT((e.com_m - (t.com - slip)).norm(), 1e-12);
  EXPECT_LT((e.com_velocity_m_s - t.com_velocity).norm(), 1e-12);
}

}  // namespace
}  // namespace dmbd::control
