// The series-elastic actuators in the plant: locked-output frequency response
// against the paper's P^inf_{i->F}, statics through the linkage, energy conservation
// of the coupled (undamped) system.
#include "dmbd/model/plant.hpp"

#include "plant_fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

namespace dmbd::model {
namespace {

constexpr double kPi = 3.14159265358979323846;

// One link below a fixed base, rotating about y, driven by one actuator.
RobotDescription one_joint_robot() {
  RobotDescription r;
  r.name = "one_joint";
  r.links.push_back(testing::point_link("thigh", 6.0, {0, 0, -0.24}, 0.05));
  r.links.push_back(testing::point_link("shank", 3.5, {0, 0, -0.25}, 0.02));
  r.joints.push_back(testing::revolute("knee", "thigh", "shank", {0, 0, -0.48}, {0, 1, 0}));
  return r;
}

ActuatorParams knee_table_one() {
  ActuatorParams p;  // the header's defaults are Table I's knee
  p.joint = "knee";
  p.kind = ActuatorKind::RFSEA;
  p.J_m_kgm2 = 1.6e-5;
  p.B_m_Nms = 2.0e-4;
  p.N_m_rad_per_m = 6632;
  p.K_s_N_per_m = 9.5e6;
  p.B_s_Ns_per_m = 1.6e4;
  p.M_r_kg = 1.3;
  p.B_l_Ns_per_m = 2.0e4;
  p.k_tau_Nm_per_A = 0.0448;
  p.efficiency = 1.0;  // the paper's plant has an ideal screw; DRACO's table has 0.9
  p.current_limit_A = 22;
  p.linkage = {0.05, 0.30, 0.5, 1.0};
  return p;
}

// P^inf_{i->F}(jw) = k_tau N_m K_r / ((M_r + J_m N_m^2) s^2 + (B_r + B_m N_m^2) s + K_r)
// (docs/paper-actuators.md, F/i with M_l -> infinity).
std::complex<double> p_inf(const ActuatorParams& p, double w) {
  const std::complex<double> s(0, w);
  return p.force_per_amp_N_per_A() * p.K_s_N_per_m /
         ((p.M_r_kg + p.reflected_mass_kg()) * s * s + (p.B_s_Ns_per_m + p.reflected_damping_Ns_per_m()) * s + p.K_s_N_per_m);
}

TEST(PlantActuator, LockedOutputFrequencyResponseMatchesPaperPlant) {
  PlantOptions o;
  o.base = BaseMode::Fixed;
  o.contact = false;
  o.actuators = {knee_table_one()};
  o.accuracy = 1e-6;
  Plant plant(one_joint_robot(), o);
  ASSERT_EQ(plant.num_actuators(), 1);
  double worst_db = 0, worst_deg = 0;
  for (double f : {0.1, 0.3, 1.0, 3.0, 10.0, 20.0, 30.0, 60.0, 100.0, 200.0}) {
    plant.reset();
    plant.lock_joint(0, 0.6);
    // 200 zero-order-hold samples a period (800 below 1 Hz), the current sampled at each
    // hold's centre so the hold adds no phase. The staircase's harmonics near N f alias
    // back onto f when F is sampled at the hold rate; below 1 Hz, 200 a period puts them
    // at the actuator's 18.5 Hz resonance (1.4 deg seen at 0.1 Hz), hence 800 there. The
    // transient (decay rate
    // (B_r + B')/(2 (M_r + J')) = 17.6 1/s) is left to die for 0.4 s (e^-7) first.
    const int per = f < 1 ? 800 : 200;
    const double w = 2 * kPi * f, dt = 1.0 / (f * per);
    const int settle = static_cast<int>(std::ceil(0.4 * f)) + 1, measure = f < 1 ? 1 : 3;
    std::complex<double> num = 0, den = 0;
    const double amp = 2.0;  // A
    for (int k = 0; k < (settle + measure) * per; ++k) {
      const double t = k * dt;
      const double i = amp * std::sin(w * (t + 0.5 * dt));  // sample at the hold's centre
      plant.set_currents(Eigen::VectorXd::Constant(1, i));
      plant.advance_to(t + dt);
      if (k >= settle * per) {
        const double tm = t + dt;
        const std::complex<double> e = std::exp(std::complex<double>(0, -w * tm));
        num += plant.actuator_forces()[0] * e;
        den += amp * std::sin(w * tm) * e;
      }
    }
    const std::complex<double> ratio = (num / den) / p_inf(o.actuators[0], w);
    const double db = 20 * std::log10(std::abs(ratio)), deg = std::arg(ratio) * 180 / kPi;
    std::printf("%6.1f Hz: %+.4f dB %+.3f deg\n", f, db, deg);
    worst_db = std::max(worst_db, std::abs(db));
    worst_deg = std::max(worst_deg, std::abs(deg));
    // Issue 12 (issue 5 asked 1 dB and 5 degrees): within 0.1 dB and 1 degree from 0.1
    // to 200 Hz, with the rotor as reflected inertia in the mass matrix (no constraint).
    EXPECT_LT(std::abs(db), 0.1) << f << " Hz";
    EXPECT_LT(std::abs(deg), 1.0) << f << " Hz";
  }
  RecordProperty("worst_gain_error_db", std::to_string(worst_db));
  RecordProperty("worst_phase_error_deg", std::to_string(worst_deg));
  std::printf("locked-output response vs P_inf: worst %.4f dB, %.3f deg\n", worst_db, worst_deg);
}

TEST(PlantActuator, ConstantCurrentHoldsTheGravityTorqueThroughTheLinkage) {
  PlantOptions o;
  o.base = BaseMode::Fixed;
  o.contact = false;
  o.actuators = {knee_table_one()};
  Plant plant(one_joint_robot(), o);
  const double q0 = 0.6;
  // Gravity torque of the shank at q0 (the joint is 0.48 m below a fixed base link).
  const double tau = 3.5 * 9.81 * 0.25 * std::sin(q0);
  const double r = o.actuators[0].linkage.moment_arm_m(q0);
  const double force = tau / r;
  const double current = force / o.actuators[0].force_per_amp_N_per_A();
  plant.set_joint_positions(Eigen::VectorXd::Constant(1, q0));
  plant.set_currents(Eigen::VectorXd::Constant(1, current));
  plant.advance_to(3.0);
  // Static equilibrium: the joint rests at q0 (the small residual comes from the reaction
  // mass's weight along its slider, M_r g / K_s ~ 1e-6 m of spring, ~1e-5 rad) and the
  // sensed force is tau / r.
  EXPECT_NEAR(plant.joint_positions()[0], q0, 2e-4);
  EXPECT_NEAR(plant.actuator_forces()[0], force, 1e-3 * std::abs(force) + 15.0);
  EXPECT_NEAR(plant.joint_torque_estimates()[0], tau, 1e-3 * std::abs(tau) + 15.0 * r);
  EXPECT_LT(std::abs(plant.joint_velocities()[0]), 1e-4);
}

TEST(PlantActuator, UndampedCoupledSystemConservesEnergy) {
  PlantOptions o;
  o.base = BaseMode::Fixed;
  o.contact = false;
  o.joint_limits = false;
  ActuatorParams p = knee_table_one();
  p.B_m_Nms = 0;
  p.B_s_Ns_per_m = 0;
  p.B_l_Ns_per_m = 0;
  ActuatorParams ankle = p;  // an FSEA on a second joint exercises the elastomer force
  ankle.joint = "ankle";
  ankle.kind = ActuatorKind::FSEA;
  ankle.N_m_rad_per_m = 3142;
  ankle.K_s_N_per_m = 1.96e6;
  ankle.linkage = {0.04, 0.25, 0.8, -1.0};
  o.actuators = {p, ankle};
  o.accuracy = 1e-8;
  RobotDescription r = one_joint_robot();
  r.links.push_back(testing::point_link("foot", 0.7, {0.03, 0, -0.04}, 0.002));
  r.joints.push_back(testing::revolute("ankle", "shank", "foot", {0, 0, -0.48}, {0, 1, 0}));
  Plant plant(r, o);
  plant.set_joint_positions(Eigen::Vector2d(0.9, -0.3));
  plant.set_joint_velocities(Eigen::Vector2d(0.5, 1.0));
  plant.advance_to(0.0);
  const double e0 = plant.kinetic_energy() + plant.potential_energy();
  double worst = 0;
  for (int k = 1; k <= 50; ++k) {
    plant.advance_to(0.1 * k);
    worst = std::max(worst, std::abs(plant.kinetic_energy() + plant.potential_energy() - e0));
  }
  // Issue 5 asks 1e-6 relative at a tight tolerance.
  EXPECT_LT(worst / std::abs(e0), 1e-6) << "e0 = " << e0;
  std::printf("coupled actuators, 5 s undamped: max |dE|/E = %.3g (E = %.4f J)\n", worst / std::abs(e0), e0);
}

}  // namespace
}  // namespace dmbd::model
