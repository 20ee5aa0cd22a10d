// The two integrators of the plant against each other (issue 12): the fixed
// semi-implicit step against the error-controlled Dormand-Prince on the same equations,
// for DRACO standing on its ten actuators and for a fixed-base leg swinging under them;
// and the fixed step's energy behaviour with damping and contact off.
#include "robot_files.hpp"
#include "dmbd/model/plant.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace dmbd::model {
namespace {

const RobotDescription& draco() {
  static const RobotDescription r = load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf", UrdfOptions{{}, false, false});
  return r;
}

PlantOptions actuated(Integration mode) {
  PlantOptions o;
  o.actuators = dmbd::test::draco_actuators();
  o.integration = mode;
  o.step_s = 5e-4;
  return o;
}

// Joint PD turned into currents through the linkage and the motor constant (the
// benchmark's standing controller): tau = 3000 (q0 - q) - 100 qdot.
Eigen::VectorXd pd_currents(const Plant& p, const Eigen::VectorXd& q0) {
  const Eigen::VectorXd q = p.joint_positions(), v = p.joint_velocities();
  Eigen::VectorXd i(p.num_actuators());
  for (int a = 0; a < p.num_actuators(); ++a) {
    const ActuatorParams& ap = p.actuator(a);
    const int j = p.joint_index(ap.joint);
    i[a] = (3000 * (q0[j] - q[j]) - 100 * v[j]) / (ap.linkage.moment_arm_m(q[j]) * ap.force_per_amp_N_per_A());
  }
  return i;
}

TEST(PlantSteppers, FixedStepMatchesAccurateStandingOnTheActuators) {
  Plant fixed(draco(), actuated(Integration::Fixed)), accurate(draco(), actuated(Integration::Accurate));
  const Eigen::VectorXd q0 = fixed.joint_positions();
  double dz = 0, dq = 0;
  for (int k = 1; k <= 2000; ++k) {
    fixed.set_currents(pd_currents(fixed, q0));
    accurate.set_currents(pd_currents(accurate, q0));
    fixed.advance_to(k * 1e-3);
    accurate.advance_to(k * 1e-3);
    dz = std::max(dz, std::abs(fixed.base_pose().translation().z() - accurate.base_pose().translation().z()));
    dq = std::max(dq, (fixed.joint_positions() - accurate.joint_positions()).cwiseAbs().maxCoeff());
  }
  std::printf("standing on the actuators 2 s, fixed 0.5 ms vs accurate: torso height %.2e m, joints %.2e rad; "
              "steps %lld vs %lld\n", dz, dq, fixed.integrator_steps(), accurate.integrator_steps());
  EXPECT_LT(dz, 1e-3);  // issue 12: torso height within 1 mm
  EXPECT_LT(dq, 5e-3);  // and joint angles within 5 mrad
}

TEST(PlantSteppers, FixedStepMatchesAccurateForALegSwingingUnderItsActuators) {
  auto options = [](Integration mode) {
    PlantOptions o = actuated(mode);
    o.base = BaseMode::Fixed;
    o.X_WB.translation() = Eigen::Vector3d(0, 0, 1.5);
    o.contact = false;
    return o;
  };
  Plant fixed(draco(), options(Integration::Fixed)), accurate(draco(), options(Integration::Accurate));
  // The left leg driven by currents of 3 A at 1-3 Hz: a swing of 0.14 rad; the right
  // leg's actuators hold no current.
  const double kPi = 3.14159265358979323846;
  double dq = 0, swing = 0;
  for (int k = 1; k <= 1000; ++k) {
    const double t = (k - 1) * 1e-3;
    Eigen::VectorXd i = Eigen::VectorXd::Zero(fixed.num_actuators());
    for (int a = 0; a < fixed.num_actuators(); ++a)
      if (fixed.actuator(a).joint.rfind("l_", 0) == 0) i[a] = 3.0 * std::sin(2 * kPi * (1.0 + 0.5 * a) * t);
    fixed.set_currents(i);
    accurate.set_currents(i);
    fixed.advance_to(k * 1e-3);
    accurate.advance_to(k * 1e-3);
    dq = std::max(dq, (fixed.joint_positions() - accurate.joint_positions()).cwiseAbs().maxCoeff());
    swing = std::max(swing, accurate.joint_positions().cwiseAbs().maxCoeff());
  }
  std::printf("fixed-base leg swing 1 s, fixed 0.5 ms vs accurate: joints %.2e rad (swing %.3f rad)\n", dq, swing);
  EXPECT_GT(swing, 0.1);  // the leg does move
  EXPECT_LT(dq, 2e-3);    // issue 12: joint angles within 2 mrad at a 0.5 ms step
}

TEST(PlantSteppers, FixedStepKeepsTheEnergyOfTheUndampedRobotOnItsActuators) {
  PlantOptions o = actuated(Integration::Fixed);
  o.base = BaseMode::Fixed;
  o.X_WB.translation() = Eigen::Vector3d(0, 0, 1.5);
  o.contact = false;
  o.joint_limits = false;
  o.joint_damping = false;
  for (ActuatorParams& a : o.actuators) a.B_m_Nms = a.B_s_Ns_per_m = a.B_l_Ns_per_m = 0;
  Plant p(draco(), o);
  Eigen::VectorXd q(10), v(10);
  q << 0.2, 0.15, -0.6, 1.1, -0.45, -0.1, -0.05, -0.4, 0.8, -0.3;
  v << 0.5, -0.3, 1.0, -1.0, 1.5, -0.5, 0.3, 0.6, 1.0, -1.2;
  p.set_joint_positions(q);
  p.set_joint_velocities(v);
  const double e0 = p.kinetic_energy() + p.potential_energy(), k0 = p.kinetic_energy();
  double worst = 0, last = 0;
  for (int k = 1; k <= 5000; ++k) {
    p.advance_to(k * 1e-3);
    last = p.kinetic_energy() + p.potential_energy() - e0;
    worst = std::max(worst, std::abs(last));
    if (k % 500 == 0) std::printf("  t %.1f s: dE %+.4f J, kinetic %.3f J\n", k * 1e-3, last, p.kinetic_energy());
  }
  std::printf("  initial kinetic energy %.3f J\n", k0);
  // Potential energy is measured from z = 0: compare against the energy that can move,
  // the kinetic energy plus the potential above the lowest posture (|E0| is ~470 J).
  std::printf("undamped robot on its actuators, fixed 0.5 ms, 5 s: max |dE| = %.3g J of E0 = %.4g J (%.2g)\n", worst, e0,
              worst / std::abs(e0));
  EXPECT_LT(worst / std::abs(e0), 0.01);  // issue 12: within 1 % over 5 s
}

}  // namespace
}  // namespace dmbd::model
