// No heap allocation in a step of the operational space controller on the bus
// (control::OscController: the robot model's update over model::RobotDynamics, the point and
// posture tasks, the OSC law, the load-damping feedforward and the torque -> force
// conversion) after construction. The C allocator is interposed in this executable to
// count (as in tests/model/test_alloc_steps.cpp); skipped under AddressSanitizer. Also
// the kinematic CoM estimator's update (issue 15).
#include <gtest/gtest.h>

#include "malloc_counter.hpp"

#include <cmath>
#include <vector>

#include "draco_options.hpp"
#include "robot_files.hpp"
#include "dmbd/model/actuator.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/control/balance_controller.hpp"
#include "dmbd/control/com_estimator.hpp"
#include "dmbd/control/osc_controller.hpp"

using dmbd::test::g_allocations;

namespace dmbd::control {
using namespace dmbd::sim;  // NOLINT: the engine's names in these tests
namespace {

TEST(NoAllocation, OscControllerStep) {
  DMBD_SKIP_UNDER_ASAN();
  const model::RobotDescription robot = model::load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf");
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.translation().z() = 1.3;
  OscSetup setup;
  setup.link = "l_foot";
  setup.trajectory.amplitude_m = Eigen::Vector3d(0.15, 0, 0.05);
  setup.trajectory.frequency_hz = 0.5;
  setup.compensate_load_damping = true;
  const std::vector<std::pair<std::string, double>> q0 = {{"l_knee", 1.2}, {"r_knee", 1.2}};
  OscController osc(robot, X_WB, 9.81, dmbd::test::draco_actuators(), q0, setup, 1000);
  std::vector<double> u(static_cast<size_t>(osc.num_inputs()), 0.0), y(static_cast<size_t>(osc.num_outputs()), 0.0);
  for (int k = 0; k < 10; ++k) u[static_cast<size_t>(2 * k + 1)] = 0.1 * (k + 1);  // joint rates
  osc.step(u.data(), y.data());  // warm-up
  {  // the counter sees an allocation (the test could fail)
    const long probe = g_allocations.load();
    std::vector<double> heap(64, 1.0);
    ASSERT_GT(g_allocations.load(), probe);
    ASSERT_EQ(heap.size(), 64u);
  }
  const long before = g_allocations.load();
  for (int tick = 0; tick < 200; ++tick) osc.step(u.data(), y.data());
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_EQ(osc.tick_times_us().size(), 201u);
}

TEST(NoAllocation, ComEstimatorUpdate) {
  DMBD_SKIP_UNDER_ASAN();
  const model::RobotDescription robot = model::load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf");
  const Eigen::Vector3d sole(0.015, 0.0, -0.044);
  KinematicComEstimator est(robot, {"l_foot", sole}, {"r_foot", sole});
  est.set_stance(wholebody::Side::Right, Eigen::Vector3d(0.0, -0.15, 0.0));
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(10, 0.1), v = Eigen::VectorXd::Constant(10, -0.2);
  const Eigen::Quaterniond R(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()));
  est.update(R, Eigen::Vector3d(0.1, 0.0, 0.2), q, v);  // warm-up
  const long before = g_allocations.load();
  double sink = 0;
  for (int k = 0; k < 100; ++k) sink += est.update(R, Eigen::Vector3d(0.1, 0.0, 0.2), q, v).com_m.z();
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_TRUE(std::isfinite(sink));
}

}  // namespace
}  // namespace dmbd::control

namespace dmbd::control {
using namespace dmbd::sim;  // NOLINT: the engine's names in these tests
namespace {

// The balancing controller fed a still robot in its stance posture (level IMU): its
// ticks go through the joint move, the body lift (and the weight shift with the shipped
// options), double support, lift, the swing's start (TVR, the spline) and mid-swing (the
// replan) with either estimator; none allocates after the first.
void expect_no_allocation_in_balance_steps(BalanceEstimator estimator, bool shipped_options) {
  const model::RobotDescription robot = model::load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf");
  BalanceSetup setup = dmbd::test::draco_balance_names();
  setup.estimator = estimator;
  setup.phases.joint_move_s = 0.05;
  setup.phases.body_lift_s = 0.05;
  setup.phases.body_lift_start_force_N = 300;
  if (shipped_options) {  // balance.yaml's, with a short weight shift
    setup.phases.weight_shift_s = 0.05;
    setup.tvr_point = TvrPoint::Torso;
    setup.ik_base_weight = 1000;
    setup.swing_relative_to_torso = setup.swing_foot_level = setup.actuator_feedforward = true;
    setup.task_gains.torso = setup.task_gains.joints = {200, 28};
    setup.task_gains.swing_foot = {300, 35};
    setup.swing.horizontal_fraction = 0.9;
    setup.qp.w_qdd_base = 10;
  }
  const std::vector<std::pair<std::string, double>> q0 = {
      {"l_hip_pitch", -0.9}, {"l_knee", 1.7}, {"l_ankle", -0.8}, {"r_hip_pitch", -0.9}, {"r_knee", 1.7}, {"r_ankle", -0.8}};
  BalanceController c(robot, 9.81, dmbd::test::draco_actuators(), q0, setup, 2000);
  std::vector<double> u(static_cast<size_t>(c.num_inputs()), 0.0), y(static_cast<size_t>(c.num_outputs()), 0.0);
  for (int k = 0; k < c.num_inputs(); ++k) {
    const std::string n = c.input_name(k);
    for (const auto& [joint, angle] : q0)
      if (n == joint + ".q") u[static_cast<size_t>(k)] = angle;
    if (n == "base.z") u[static_cast<size_t>(k)] = 0.8;
  }
  c.step(u.data(), y.data());  // warm-up
  const long before = g_allocations.load();
  for (int tick = 0; tick < 500; ++tick) c.step(u.data(), y.data());  // to 0.5 s: past the first mid-swing
  EXPECT_EQ(g_allocations.load() - before, 0);
  int phase = -1;
  for (int k = 0; k < c.num_outputs(); ++k)
    if (c.output_name(k) == "balance.step") phase = static_cast<int>(y[static_cast<size_t>(k)]);
  EXPECT_GE(phase, 1);  // stepping had begun
}

TEST(NoAllocation, BalanceControllerStepKinematicEstimator) {
  DMBD_SKIP_UNDER_ASAN();
  expect_no_allocation_in_balance_steps(BalanceEstimator::Kinematic, false);
}

TEST(NoAllocation, BalanceControllerStepMotionCapture) {
  DMBD_SKIP_UNDER_ASAN();
  expect_no_allocation_in_balance_steps(BalanceEstimator::MotionCapture, false);
}

// The same through the weight shift, with the options balance.yaml sets (the torso point,
// the weighted IK, the swing foot relative to the torso, the level sole, the actuator
// feedforward, task gains) and the swing's horizontal fraction.
TEST(NoAllocation, BalanceControllerStepShippedOptions) {
  DMBD_SKIP_UNDER_ASAN();
  expect_no_allocation_in_balance_steps(BalanceEstimator::MotionCapture, true);
}

}  // namespace
}  // namespace dmbd::control
