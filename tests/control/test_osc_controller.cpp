// control::OscController on the bus: the path's derivatives, the law's value at rest (pure
// gravity compensation), the torque -> actuator force conversion through the linkage
// (F = τ N_l(q)) and back (τ_s = F / N_l(q)), and the ports.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "draco_options.hpp"
#include "robot_files.hpp"
#include "dmbd/model/actuator.hpp"
#include "dmbd/model/dynamics.hpp"
#include "dmbd/base/error.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/control/osc_controller.hpp"

namespace dmbd::control {
using namespace dmbd::sim;  // NOLINT: the engine's names in these tests
namespace {

const model::RobotDescription& draco() {
  static const model::RobotDescription r = model::load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf");
  return r;
}

const std::vector<std::pair<std::string, double>> kBentKnees = {
    {"l_hip_pitch", -0.6}, {"l_knee", 1.2}, {"l_ankle", -0.6}, {"r_hip_pitch", -0.6}, {"r_knee", 1.2}, {"r_ankle", -0.6}};

// Central differences of p and v (h = 1e-5 s): truncation ~h² |d³p/dt³| ≈ 1e-10 · 3e3;
// tolerance 1e-5 (m/s, m/s²) at 0.3 m and 1.4 Hz, inside and after the ramp.
TEST(OscTrajectory, VelocityAndAccelerationAreTheDerivativesOfThePath) {
  OscTrajectory tr;
  tr.amplitude_m = Eigen::Vector3d(0.3, 0.0, 0.05);
  tr.frequency_hz = 1.4;
  tr.ramp_s = 1.0;
  const double h = 1e-5;
  for (double t : {0.1, 0.37, 0.5, 0.93, 1.2, 2.71}) {
    Eigen::Vector3d p, v, a, pp, vp, ap, pm, vm, am;
    tr.evaluate(t, p, v, a);
    tr.evaluate(t + h, pp, vp, ap);
    tr.evaluate(t - h, pm, vm, am);
    EXPECT_LT(((pp - pm) / (2 * h) - v).norm(), 1e-5) << "t = " << t;
    EXPECT_LT(((vp - vm) / (2 * h) - a).norm(), 1e-5) << "t = " << t;
  }
  Eigen::Vector3d p, v, a;
  tr.evaluate(0.0, p, v, a);  // a smooth start: at rest at the path's centre
  EXPECT_EQ(p.norm() + v.norm() + a.norm(), 0.0);
  tr.evaluate(3.25 / 1.4, p, v, a);  // after the ramp: the plain sinusoid at its crest (3¼ periods)
  EXPECT_NEAR(p.x(), 0.3, 1e-12);
  EXPECT_NEAR(a.x(), -0.3 * std::pow(2 * M_PI * 1.4, 2), 1e-9);
}

struct Bus {
  std::vector<double> u, y;
};

TEST(OscController, AtRestOnItsPathItCommandsGravityAndTheLinkageForce) {
  const auto actuators = dmbd::test::draco_actuators();
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.translation().z() = 1.3;
  OscSetup setup;
  setup.link = "l_foot";
  setup.trajectory.amplitude_m = Eigen::Vector3d(0.3, 0, 0);
  setup.trajectory.frequency_hz = 1.4;
  setup.compensate_load_damping = true;  // zero at rest
  OscController osc(draco(), X_WB, 9.81, actuators, kBentKnees, setup, 10);
  ASSERT_EQ(osc.joints().size(), 10u);
  // Inputs: q, qd per joint, then each actuated joint's force.
  ASSERT_EQ(osc.num_inputs(), 30);
  ASSERT_EQ(osc.num_outputs(), 10 + 20 + 6);
  EXPECT_EQ(osc.input_name(0), osc.joints()[0] + ".q");
  EXPECT_EQ(osc.input_name(20), osc.joints()[0] + ".force");
  EXPECT_EQ(osc.output_name(10), osc.joints()[0] + ".force_d");
  EXPECT_EQ(osc.output_unit(10), "N");

  model::DynamicsOptions o;
  o.base = model::BaseMode::Fixed;
  o.X_WB = X_WB;
  model::RobotDynamics ref(draco(), o);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(10);
  for (const auto& [n, a] : kBentKnees) q[ref.joint_q_index(ref.joint_index(n))] = a;
  ref.set_state(q, Eigen::VectorXd::Zero(10));
  const Eigen::VectorXd g = ref.gravity();

  Bus bus{std::vector<double>(30, 0.0), std::vector<double>(36, 0.0)};
  for (int k = 0; k < 10; ++k) {
    bus.u[static_cast<size_t>(2 * k)] = q[ref.joint_q_index(ref.joint_index(osc.joints()[static_cast<size_t>(k)]))];
    bus.u[static_cast<size_t>(20 + k)] = 100.0 * (k + 1);  // sensed forces
  }
  osc.step(bus.u.data(), bus.y.data());
  for (int k = 0; k < 10; ++k) {
    const std::string& j = osc.joints()[static_cast<size_t>(k)];
    const int r = ref.joint_v_index(ref.joint_index(j));
    // The target sits where the ankle is and nothing moves: τ = g(q) (1e-9 N m: the
    // posture and task terms are exactly zero, only the rounding of b + g remains).
    EXPECT_NEAR(bus.y[static_cast<size_t>(k)], g[r], 1e-9) << j;
    const auto act = std::find_if(actuators.begin(), actuators.end(), [&](const auto& a) { return a.joint == j; });
    ASSERT_NE(act, actuators.end());
    const double n_l = act->linkage.N_l(q[r]);
    EXPECT_NEAR(bus.y[static_cast<size_t>(10 + 2 * k)], g[r] * n_l, 1e-9 * std::abs(n_l)) << j;
    EXPECT_NEAR(bus.y[static_cast<size_t>(11 + 2 * k)], 100.0 * (k + 1) / n_l, 1e-12) << j;
  }
  // The point: target and position are the ankle's, 1.3 m up less the leg.
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(bus.y[static_cast<size_t>(30 + i)], bus.y[static_cast<size_t>(33 + i)], 1e-15);
  EXPECT_EQ(osc.tick_times_us().size(), 1u);
}

TEST(OscController, AnUnknownLinkIsNamedWhereTheScenarioGaveIt) {
  OscSetup setup;
  setup.link = "l_foot";
  setup.link = "l_flipper";
  setup.where = "osc.yaml:12:3";
  try {
    OscController osc(draco(), Eigen::Isometry3d::Identity(), 9.81, {}, {}, setup, 1);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("osc.yaml:12:3: osc.link: "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("l_flipper"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dmbd::control
