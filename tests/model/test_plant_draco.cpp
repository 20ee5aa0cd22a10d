// DRACO in Simbody: the model built from robots/draco/draco.urdf and actuators.yaml,
// its gravity torques against an independent computation, energy conservation of the
// free fixed-base robot, and standing on the ground.
#include "robot_files.hpp"
#include "dmbd/model/dynamics.hpp"
#include "dmbd/model/plant.hpp"

#include "plant_fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace dmbd::model {
namespace {

const RobotDescription& draco() {
  static const RobotDescription r = load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf");
  return r;
}

Eigen::VectorXd posture(int n) {
  // A crouch with some yaw and roll (joint order of the URDF: left leg then right leg).
  Eigen::VectorXd q(n);
  q << 0.2, 0.15, -0.6, 1.1, -0.45, -0.1, -0.05, -0.4, 0.8, -0.3;
  return q;
}

TEST(PlantDraco, BuildsWithTheActuatorsAndKeepsTheMass) {
  PlantOptions o;
  o.actuators = dmbd::test::draco_actuators();
  Plant p(draco(), o);
  EXPECT_EQ(p.num_joints(), 10);
  EXPECT_EQ(p.num_actuators(), 10);
  // The housings' reaction masses are taken from the links: 37 kg (paper) in all.
  EXPECT_NEAR(p.total_mass_kg(), draco().total_mass_kg(), 1e-9);
  EXPECT_NEAR(p.total_mass_kg(), 37.0, 0.5);
  for (int j = 0; j < 10; ++j) EXPECT_GE(p.actuator_of_joint(j), 0) << p.joint_names()[static_cast<std::size_t>(j)];
}

TEST(PlantDraco, GravityTorquesEqualAnIndependentComputation) {
  RobotDynamics d(draco(), {BaseMode::Fixed, Eigen::Isometry3d::Identity(), 9.81});
  ASSERT_EQ(d.nv(), 10);
  const Eigen::VectorXd q = posture(10);
  d.set_state(q, Eigen::VectorXd::Zero(10));
  const Eigen::VectorXd g_sim = d.gravity();
  const Eigen::VectorXd g_ref = testing::gravity_torques(draco(), q, 9.81);
  // Both are exact up to rounding; largest torque ~ 40 N m: 1e-10 N m.
  EXPECT_LT((g_sim - g_ref).cwiseAbs().maxCoeff(), 1e-10) << g_sim.transpose() << "\n" << g_ref.transpose();
  EXPECT_GT(g_ref.cwiseAbs().maxCoeff(), 1.0);  // the posture loads the joints
}

TEST(PlantDraco, FixedBaseSwingingFreelyConservesEnergy) {
  PlantOptions o;
  o.base = BaseMode::Fixed;
  o.X_WB.translation() = Eigen::Vector3d(0, 0, 1.5);
  o.contact = false;
  o.joint_limits = false;
  o.joint_damping = false;
  o.accuracy = 1e-9;
  Plant p(draco(), o);
  p.set_joint_positions(posture(10));
  Eigen::VectorXd v(10);
  v << 1.0, -0.5, 2.0, -1.5, 3.0, -1.0, 0.5, 1.0, 2.0, -2.5;
  p.set_joint_velocities(v);
  p.advance_to(0.0);
  const double e0 = p.kinetic_energy() + p.potential_energy();
  double worst = 0;
  for (int k = 1; k <= 50; ++k) {
    p.advance_to(0.1 * k);
    worst = std::max(worst, std::abs(p.kinetic_energy() + p.potential_energy() - e0));
  }
  // Issue 5: 1e-6 relative over 5 s at a tight integrator tolerance.
  EXPECT_LT(worst / std::abs(e0), 1e-6) << "E0 = " << e0;
  std::printf("DRACO fixed base, 5 s free swing: max |dE|/E = %.3g (E = %.3f J)\n", worst / std::abs(e0), e0);
}

TEST(PlantDraco, FloatingBaseStandsForTenSecondsUnderJointPD) {
  PlantOptions o;  // floating base, contact on, ideal joint torques
  o.integration = Integration::Fixed;
  o.step_s = 5e-4;
  Plant p(draco(), o);
  const Eigen::VectorXd q0 = p.joint_positions();
  const double z0 = p.base_pose().translation().z();
  // PD at 1 kHz, zero-order hold: hips and knees 1500 N m/rad, 20 N m s/rad; the ankles
  // 800 and 2: stiffer than the body's toppling stiffness about them (m g h ~ 330 N m/rad
  // shared by two ankles), yet stable when sampled on an unloaded 0.4 kg foot
  // (kd T / I ~ 1.2). The hip yaws get 5 N m s/rad: with both feet held by friction, the
  // two yaw dampers act on the torso's yaw alone (I ~ 0.02 kg m^2), and a sampled
  // derivative gain is stable only for 2 kd T / I < 2; at 20 the accurate integrator shows
  // the torso's yaw growing from 0.1 s on.
  Eigen::VectorXd kp = Eigen::VectorXd::Constant(10, 1500), kd = Eigen::VectorXd::Constant(10, 20);
  for (int j = 0; j < 10; ++j) {
    const std::string& n = p.joint_names()[static_cast<std::size_t>(j)];
    if (n.find("ankle") != std::string::npos) {
      kp[j] = 800;
      kd[j] = 2;
    }
    if (n.find("yaw") != std::string::npos) kd[j] = 5;
  }
  std::vector<Eigen::Vector3d> feet0;
  for (const ContactReading& c : p.contacts()) feet0.push_back(c.p_W);
  double max_tilt = 0, min_z = 1e9, max_z = -1e9, max_pen = 0, late_speed = 0;
  for (int k = 1; k <= 10000; ++k) {
    const Eigen::VectorXd q = p.joint_positions(), v = p.joint_velocities();
    p.set_joint_torques(kp.cwiseProduct(q0 - q) - kd.cwiseProduct(v));
    p.advance_to(k * 1e-3);
    if (k % 10 == 0) {
      const Eigen::Isometry3d X = p.base_pose();
      max_tilt = std::max(max_tilt, std::acos(std::clamp(X.linear()(2, 2), -1.0, 1.0)));
      min_z = std::min(min_z, X.translation().z());
      max_z = std::max(max_z, X.translation().z());
      for (const ContactReading& c : p.contacts()) max_pen = std::max(max_pen, c.penetration_m);
      if (k > 9000) late_speed = std::max(late_speed, p.base_velocity().norm());
    }
  }
  double creep = 0;
  const std::vector<ContactReading> end = p.contacts();
  for (std::size_t i = 0; i < end.size(); ++i) creep = std::max(creep, (end[i].p_W - feet0[i]).head<2>().norm());
  std::printf("standing 10 s: tilt %.2e rad, torso z %.5f..%.5f m (start %.5f), sinkage %.2f mm, late speed %.2e m/s, "
              "foot drift %.2e m\n", max_tilt, min_z, max_z, z0, 1e3 * max_pen, late_speed, creep);
  EXPECT_LT(max_tilt, 0.05);                 // upright: under 3 degrees
  EXPECT_GT(min_z, z0 - 0.02);               // not sagging
  EXPECT_LT(max_pen, 0.003);                 // feet sink no more than 3 mm
  // No jitter: the torso's speed (angular and linear) stays small in the last second. It
  // rocks slowly in pitch (tilt below 4 mrad, a ~1 s period): the ankles' PD (800, 2)
  // leaves the body's inverted-pendulum mode on them little damped; measured 9e-3.
  EXPECT_LT(late_speed, 2e-2);
  EXPECT_LT(creep, 1e-4);                    // no creep: the spheres stay within 0.1 mm of where they landed
  double total_fz = 0;
  for (const ContactReading& c : end) total_fz += c.force_W.z();
  EXPECT_NEAR(total_fz, p.total_mass_kg() * 9.81, 0.01 * p.total_mass_kg() * 9.81);  // carries the weight
}

}  // namespace
}  // namespace dmbd::model
