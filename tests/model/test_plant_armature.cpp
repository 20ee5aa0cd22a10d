// A joint's armature (model::Joint::armature, a geared rotor reflected onto the joint):
// a pendulum of mass m with its centre of mass lc below the pivot and central inertia Ic
// swings with the inertia I = Ic + m lc² + I_a. Closed forms: the kinetic energy ½ I v²
// (to 1e-12 relative) and the small-oscillation period 2π √(I / (m g lc)) (from 0.01 rad,
// the amplitude's correction is 6e-6 of it; measured between zero crossings to 0.05 %),
// on both integrators, and the energy conserved without damping (1e-6 of the swing's, at
// an integrator accuracy of 1e-9).
#include "plant_fixtures.hpp"
#include "dmbd/model/plant.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace dmbd::model {
namespace {

using testing::point_link;
using testing::revolute;

constexpr double kM = 2.0, kLc = 0.3, kIc = 0.04, kG = 9.81;

RobotDescription pendulum(double armature) {
  RobotDescription r;
  r.name = "pendulum";
  r.links.push_back(point_link("base", 1.0, Eigen::Vector3d::Zero(), 0.01));
  r.links.push_back(point_link("bob", kM, {0, 0, -kLc}, kIc));
  r.joints.push_back(revolute("pivot", "base", "bob", {0, 0, 0}, {0, 1, 0}));
  r.joints.back().armature = armature;
  return r;
}

PlantOptions fixed_base(Integration mode) {
  PlantOptions o;
  o.base = BaseMode::Fixed;
  o.integration = mode;
  o.step_s = 2e-4;
  return o;
}

// The mean time between the upward zero crossings of q over 4 s, s.
double measured_period(Integration mode, double armature) {
  Plant p(pendulum(armature), fixed_base(mode));
  p.set_joint_positions(Eigen::VectorXd::Constant(1, 0.01));
  std::vector<double> up;
  double prev = 0.01;
  for (int k = 1; k <= 20000; ++k) {
    const double t = k * 2e-4;
    p.advance_to(t);
    const double q = p.joint_positions()[0];
    if (prev < 0 && q >= 0) up.push_back(t - 2e-4 * q / (q - prev));  // linear between the samples
    prev = q;
  }
  return up.size() < 2 ? NAN : (up.back() - up.front()) / static_cast<double>(up.size() - 1);
}

TEST(PlantArmature, AddsToTheJointsInertiaInTheKineticEnergy) {
  for (double a : {0.0, 0.5}) {
    Plant p(pendulum(a), fixed_base(Integration::Accurate));
    p.set_joint_velocities(Eigen::VectorXd::Constant(1, 1.7));
    const double I = kIc + kM * kLc * kLc + a;
    EXPECT_NEAR(p.kinetic_energy(), 0.5 * I * 1.7 * 1.7, 1e-12 * I) << "armature " << a;
  }
}

TEST(PlantArmature, SlowsThePendulumAsTheClosedFormSays) {
  for (const Integration mode : {Integration::Accurate, Integration::Fixed})
    for (double a : {0.0, 0.3}) {
      const double expected = 2 * M_PI * std::sqrt((kIc + kM * kLc * kLc + a) / (kM * kG * kLc));
      EXPECT_NEAR(measured_period(mode, a), expected, 5e-4 * expected) << "armature " << a << (mode == Integration::Fixed ? ", fixed" : ", accurate");
    }
}

TEST(PlantArmature, TheEnergyIsConservedWithItUndamped) {
  PlantOptions o = fixed_base(Integration::Accurate);
  o.accuracy = 1e-9;
  Plant p(pendulum(0.3), o);
  p.set_joint_positions(Eigen::VectorXd::Constant(1, 1.0));
  const double e0 = p.kinetic_energy() + p.potential_energy();
  p.advance_to(3.0);
  const double drop = kM * kG * kLc * (1 - std::cos(1.0));  // the swing's energy scale
  EXPECT_NEAR(p.kinetic_energy() + p.potential_energy(), e0, 1e-6 * drop);  // Dormand–Prince at 1e-9
}

}  // namespace
}  // namespace dmbd::model
