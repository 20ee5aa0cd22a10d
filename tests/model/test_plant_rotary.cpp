// The geared rotary actuators in the plant against closed forms: ROTARY's reflected
// inertia, stall torque, torque and current limits, Coulomb and viscous friction;
// ROTARY_SEA's two spring resonances; energy conservation of both undamped; the two
// integrators against each other; readings; the table checked against the robot.
#include "dmbd/model/plant.hpp"

#include "dmbd/model/error.hpp"
#include "plant_fixtures.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace dmbd::model {
namespace {

constexpr double kPi = 3.14159265358979323846;

// One link on a fixed base, about y: 2 kg at 0.3 m plus 0.01 kg m^2, I = 0.19 kg m^2.
constexpr double kLinkInertia = 0.01 + 2.0 * 0.3 * 0.3;

RobotDescription one_link() {
  RobotDescription r;
  r.name = "one_link";
  r.links.push_back(testing::point_link("base", 1.0, {0, 0, 0}, 0.01));
  r.links.push_back(testing::point_link("arm", 2.0, {0, 0, -0.3}, 0.01));
  r.joints.push_back(testing::revolute("shoulder", "base", "arm", {0, 0, 0}, {0, 1, 0}));
  return r;
}

// The same with a second link on an elbow.
RobotDescription two_links() {
  RobotDescription r = one_link();
  r.links.push_back(testing::point_link("forearm", 1.2, {0, 0, -0.25}, 0.004));
  r.joints.push_back(testing::revolute("elbow", "arm", "forearm", {0, 0, -0.5}, {0, 1, 0}));
  return r;
}

// A geared motor without friction, damping or load: J' = J_m N^2 = 0.0825 kg m^2,
// eta k_tau N = 5.1 N m/A, torque limit 40 N m (7.84 A), current limit 10 A.
ActuatorParams motor(const std::string& joint, ActuatorKind kind) {
  ActuatorParams p;
  p.joint = joint;
  p.kind = kind;
  p.J_m_kgm2 = 3.3e-5;
  p.B_m_Nms = 0;
  p.N_m_rad_per_m = 50;
  p.k_tau_Nm_per_A = 0.12;
  p.efficiency = 0.85;
  p.current_limit_A = 10;
  p.torque_limit_Nm = 40;
  p.viscous_friction_Nms = 0;
  p.coulomb_friction_Nm = 0;
  p.B_l_Ns_per_m = 0;
  p.M_r_kg = 0;
  p.K_s_N_per_m = kind == ActuatorKind::ROTARY_SEA ? 350 : 0;
  p.B_s_Ns_per_m = 0;
  return p;
}

PlantOptions options(std::vector<ActuatorParams> acts, Integration mode = Integration::Accurate) {
  PlantOptions o;
  o.base = BaseMode::Fixed;
  o.contact = false;
  o.joint_limits = false;
  o.gravity_m_s2 = 0;  // the closed forms below are about one axis, without gravity
  o.actuators = std::move(acts);
  o.integration = mode;
  o.accuracy = 1e-10;
  o.step_s = 5e-4;
  return o;
}

double reflected(const ActuatorParams& p) { return p.J_m_kgm2 * p.N_m_rad_per_m * p.N_m_rad_per_m; }
double torque_per_amp(const ActuatorParams& p) { return p.efficiency * p.k_tau_Nm_per_A * p.N_m_rad_per_m; }

// The joint's acceleration under the held inputs, from rest, as v(T)/T: the motion is
// uniformly accelerated (one link, no gravity, no velocity-dependent force), which both
// integrators' velocities follow exactly (Dormand-Prince is exact on polynomials, the
// fixed step's v+ = v + h a too).
double acceleration(Plant& p, double T) {
  p.advance_to(T);
  return p.joint_velocities()[0] / T;
}

TEST(PlantRotary, ReflectedInertiaOfTheGearedRotor) {
  for (Integration mode : {Integration::Accurate, Integration::Fixed}) {
    const ActuatorParams m = motor("shoulder", ActuatorKind::ROTARY);
    Plant p(one_link(), options({m}, mode));
    EXPECT_EQ(p.spring_deflections().size(), 1);
    const double i = 3.0;  // 15.3 N m, inside both limits
    p.set_currents(Eigen::VectorXd::Constant(1, i));
    const double a = acceleration(p, 0.1);
    const double expected = torque_per_amp(m) * i / (kLinkInertia + reflected(m));
    EXPECT_NEAR(a / expected, 1.0, 1e-9) << (mode == Integration::Fixed ? "fixed" : "accurate");
    std::printf("ROTARY reflected inertia (%s): %.12g rad/s^2, closed form %.12g (I_link %.4g + J_m N^2 %.4g): %.2g relative\n",
                mode == Integration::Fixed ? "fixed" : "accurate", a, expected, kLinkInertia, reflected(m), a / expected - 1);
  }
}

// Stall torque: an opposing joint torque of exactly eta N k_tau i holds the joint still;
// above the limits the output stalls at the torque limit (7.84 A applied of 20 asked)
// or at the current limit's torque (10 A, 51 N m, when the torque limit is higher).
TEST(PlantRotary, StallTorqueAndTheTwoLimits) {
  struct Case {
    double asked_A, torque_limit_Nm, applied_A, torque_Nm;
  };
  const ActuatorParams base = motor("shoulder", ActuatorKind::ROTARY);
  const double kt = torque_per_amp(base);  // 5.1 N m/A
  for (const Case& c : {Case{3.0, 40, 3.0, 3.0 * kt}, Case{20.0, 40, 40 / kt, 40.0}, Case{-20.0, 40, -40 / kt, -40.0},
                        Case{20.0, 100, 10.0, 10 * kt}}) {
    ActuatorParams m = base;
    m.torque_limit_Nm = c.torque_limit_Nm;
    Plant hold(one_link(), options({m}));
    hold.set_currents(Eigen::VectorXd::Constant(1, c.asked_A));
    EXPECT_NEAR(hold.applied_currents()[0], c.applied_A, 1e-12 * std::abs(c.applied_A));
    EXPECT_NEAR(hold.actuator_forces()[0], c.torque_Nm, 1e-12 * std::abs(c.torque_Nm));  // the drive's estimate
    EXPECT_NEAR(hold.joint_torque_estimates()[0], c.torque_Nm, 1e-12 * std::abs(c.torque_Nm));
    hold.set_joint_torques(Eigen::VectorXd::Constant(1, -c.torque_Nm));
    hold.advance_to(0.5);
    EXPECT_LT(std::abs(hold.joint_positions()[0]), 1e-12) << c.asked_A << " A";
    // One N m less opposition: the link accelerates at 1 / I_total.
    Plant push(one_link(), options({m}));
    push.set_currents(Eigen::VectorXd::Constant(1, c.asked_A));
    push.set_joint_torques(Eigen::VectorXd::Constant(1, -c.torque_Nm + (c.torque_Nm > 0 ? 1.0 : -1.0)));
    const double a = acceleration(push, 0.1);
    EXPECT_NEAR(std::abs(a) * (kLinkInertia + reflected(m)), 1.0, 1e-9) << c.asked_A << " A";
  }
}

// Coulomb friction at the gear output, regularised: below tau_c the joint creeps at
// w_s tau / tau_c (the viscous slope tau_c / w_s of the regularisation; here 0.5 w_s =
// 0.5 mrad/s), above it accelerates at (tau - tau_c) / I_total.
TEST(PlantRotary, CoulombFrictionHoldsBelowAndSlidesAbove) {
  ActuatorParams m = motor("shoulder", ActuatorKind::ROTARY);
  m.coulomb_friction_Nm = 1.5;
  const double ws = m.coulomb_velocity_rad_s, I = kLinkInertia + reflected(m);
  for (Integration mode : {Integration::Accurate, Integration::Fixed}) {
    const char* name = mode == Integration::Fixed ? "fixed" : "accurate";
    Plant hold(one_link(), options({m}, mode));
    hold.set_joint_torques(Eigen::VectorXd::Constant(1, 0.75));
    hold.advance_to(1.0);
    const double creep = 0.5 * ws;
    EXPECT_NEAR(hold.joint_velocities()[0], creep, 1e-9) << name;
    EXPECT_LE(hold.joint_positions()[0], creep * 1.0) << name;  // never faster than the creep
    EXPECT_GT(hold.joint_positions()[0], creep * 0.99) << name;  // and at it after ~1e-3 s
    Plant slide(one_link(), options({m}, mode));
    Eigen::VectorXd v0 = Eigen::VectorXd::Constant(1, 0.1);  // beyond w_s: at the cap
    slide.set_joint_velocities(v0);
    slide.set_joint_torques(Eigen::VectorXd::Constant(1, 3.0));
    slide.advance_to(0.2);
    const double a = (slide.joint_velocities()[0] - 0.1) / 0.2;
    EXPECT_NEAR(a / ((3.0 - 1.5) / I), 1.0, 1e-9) << name;
    std::printf("Coulomb (%s): creep %.6g rad/s at tau = tau_c / 2 (w_s / 2 = %.6g), 1 s: %.6g rad; "
                "above: %.10g rad/s^2 vs (tau - tau_c) / I = %.10g (%.2g relative)\n",
                name, hold.joint_velocities()[0], creep, hold.joint_positions()[0], a, (3.0 - 1.5) / I, a * I / 1.5 - 1);
  }
}

// Viscous terms: gear friction b, rotor damping B_m N^2 and load damping B_l all act on
// the joint's speed: v(t) = v0 exp(-(b + B_m N^2 + B_l) t / I_total).
TEST(PlantRotary, ViscousDecayRate) {
  ActuatorParams m = motor("shoulder", ActuatorKind::ROTARY);
  m.viscous_friction_Nms = 0.3;
  m.B_m_Nms = 1e-5;  // 0.025 N m s/rad at the output
  m.B_l_Ns_per_m = 0.05;
  Plant p(one_link(), options({m}));
  p.set_joint_velocities(Eigen::VectorXd::Constant(1, 2.0));
  p.advance_to(1.0);
  const double rate = std::log(2.0 / p.joint_velocities()[0]) / 1.0;
  const double expected = (0.3 + 1e-5 * 50 * 50 + 0.05) / (kLinkInertia + reflected(m));
  EXPECT_NEAR(rate / expected, 1.0, 1e-7);
  std::printf("viscous decay: %.10g 1/s, closed form %.10g (%.2g relative)\n", rate, expected, rate / expected - 1);
}

TEST(PlantRotary, ReadingsOfARigidGearedMotor) {
  const ActuatorParams m = motor("shoulder", ActuatorKind::ROTARY);
  Plant p(one_link(), options({m}));
  p.set_currents(Eigen::VectorXd::Constant(1, 2.0));
  p.advance_to(0.05);
  const double q = p.joint_positions()[0], v = p.joint_velocities()[0];
  EXPECT_GT(q, 0.01);
  EXPECT_EQ(p.spring_deflections()[0], 0.0);
  EXPECT_EQ(p.motor_angles()[0], 50 * q);
  EXPECT_EQ(p.motor_velocities()[0], 50 * v);
  EXPECT_EQ(p.applied_currents()[0], 2.0);
}

// ---- ROTARY_SEA ------------------------------------------------------------------------

// The frequency (Hz) of x(t) sampled at dt: upward crossings of the middle of its range,
// linearly interpolated, over the whole periods between the first and the last.
double crossing_frequency(const std::vector<double>& x, double dt) {
  const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
  const double mid = 0.5 * (*lo + *hi);
  std::vector<double> t;
  for (std::size_t k = 1; k < x.size(); ++k)
    if (x[k - 1] < mid && x[k] >= mid) t.push_back(dt * ((k - 1) + (mid - x[k - 1]) / (x[k] - x[k - 1])));
  if (t.size() < 2) return 0;
  return (t.size() - 1) / (t.back() - t.front());
}

// The spring deflection sampled over `periods` of `f_hz` at 400 samples a period.
std::vector<double> spring_history(Plant& p, double f_hz, int periods) {
  const int n = 400 * periods;
  const double dt = 1.0 / (400 * f_hz);
  std::vector<double> s;
  for (int k = 1; k <= n; ++k) {
    p.advance_to(k * dt);
    s.push_back(p.spring_deflections()[0]);
  }
  return s;
}

// Link free, rotor (nearly) still: a joint torque starts the link oscillating on the
// spring at sqrt(K / I_link). The rotor is made 1e4 times the link's inertia (J_m
// 0.19 kg m^2 at N = 100); the exact two-mass frequency sqrt(K (1/I + 1/J')) differs by
// 5e-5. Joint locked: a current starts the rotor oscillating at sqrt(K / (J_m N^2)).
TEST(PlantRotarySea, SpringResonancesWithTheMotorOrTheJointHeld) {
  ActuatorParams m = motor("shoulder", ActuatorKind::ROTARY_SEA);
  m.N_m_rad_per_m = 100;
  {
    ActuatorParams big = m;
    big.J_m_kgm2 = 1e4 * kLinkInertia / (100.0 * 100.0);
    Plant p(one_link(), options({big}));
    p.set_joint_torques(Eigen::VectorXd::Constant(1, 2.0));
    const double f = std::sqrt(big.K_s_N_per_m / kLinkInertia) / (2 * kPi);
    const double got = crossing_frequency(spring_history(p, f, 6), 1.0 / (400 * f));
    EXPECT_NEAR(got / f, 1.0, 5e-3);
    std::printf("ROTARY_SEA, rotor held (J' = 1e4 I): %.6f Hz, sqrt(K/I_link) %.6f Hz (%.2g relative)\n", got, f, got / f - 1);
  }
  {
    Plant p(one_link(), options({m}));
    p.lock_joint(0, 0.0);
    p.set_currents(Eigen::VectorXd::Constant(1, 1.0));
    const double f = std::sqrt(m.K_s_N_per_m / reflected(m)) / (2 * kPi);
    const double got = crossing_frequency(spring_history(p, f, 6), 1.0 / (400 * f));
    EXPECT_NEAR(got / f, 1.0, 5e-3);
    EXPECT_EQ(p.joint_positions()[0], 0.0);
    std::printf("ROTARY_SEA, joint locked: %.6f Hz, sqrt(K/(J_m N^2)) %.6f Hz (%.2g relative)\n", got, f, got / f - 1);
  }
}

TEST(PlantRotarySea, Readings) {
  const ActuatorParams m = motor("shoulder", ActuatorKind::ROTARY_SEA);
  Plant p(one_link(), options({m}));
  p.set_currents(Eigen::VectorXd::Constant(1, 2.0));
  p.advance_to(0.03);
  const double q = p.joint_positions()[0], v = p.joint_velocities()[0], s = p.spring_deflections()[0];
  EXPECT_GT(std::abs(s), 1e-4);
  EXPECT_EQ(p.actuator_forces()[0], s * m.K_s_N_per_m);  // the spring's torque, N m
  EXPECT_EQ(p.joint_torque_estimates()[0], s * m.K_s_N_per_m);
  EXPECT_EQ(p.motor_angles()[0], 50 * (q + s));
  // theta_m' = N (q' + s'): against the difference of motor angles over 1 us.
  const double th0 = p.motor_angles()[0];
  const double thd = p.motor_velocities()[0];
  p.advance_to(0.03 + 1e-6);
  EXPECT_NEAR((p.motor_angles()[0] - th0) / 1e-6, thd, 1e-4 * std::abs(thd));
  EXPECT_NE(thd, 50 * v);  // the spring moves: the rotor is not rigid with the joint
}

// ---- both kinds together ---------------------------------------------------------------------

// Shoulder ROTARY, elbow ROTARY_SEA, under gravity, no friction, damping or input: the
// total energy (links, rotors, spring, gravity) is conserved by the accurate integrator.
TEST(PlantRotary, UndampedChainConservesEnergy) {
  PlantOptions o = options({motor("shoulder", ActuatorKind::ROTARY), motor("elbow", ActuatorKind::ROTARY_SEA)});
  o.gravity_m_s2 = 9.81;
  o.accuracy = 1e-9;
  Plant p(two_links(), o);
  p.set_joint_positions(Eigen::Vector2d(0.9, -0.3));
  p.set_joint_velocities(Eigen::Vector2d(0.5, 1.0));
  const double e0 = p.kinetic_energy() + p.potential_energy();
  double worst = 0, s_max = 0;
  for (int k = 1; k <= 50; ++k) {
    p.advance_to(0.1 * k);
    worst = std::max(worst, std::abs(p.kinetic_energy() + p.potential_energy() - e0));
    s_max = std::max(s_max, std::abs(p.spring_deflections()[1]));
  }
  EXPECT_GT(s_max, 1e-3);  // the spring takes part
  EXPECT_LT(worst / std::abs(e0), 1e-8) << "e0 = " << e0;
  std::printf("rotary chain, 5 s undamped: max |dE|/E = %.3g (E = %.4f J, spring up to %.3g rad)\n", worst / std::abs(e0),
              e0, s_max);
}

// The same chain with friction, damping and currents at 1-3 Hz, 1 s (a swing of 0.83
// rad): the fixed step at 0.5 and 0.25 ms against the accurate integrator (1e-9). The
// fixed step is first order: measured 2.8 and 0.85 mrad on the joints, 1.1e-4 and
// 6.4e-5 rad on the spring (without Coulomb friction 1.8 and 0.92 mrad: its explicit cap
// adds a little at reversals).
TEST(PlantRotary, FixedStepMatchesAccurate) {
  std::vector<ActuatorParams> acts = {motor("shoulder", ActuatorKind::ROTARY), motor("elbow", ActuatorKind::ROTARY_SEA)};
  for (ActuatorParams& a : acts) {
    a.viscous_friction_Nms = 0.2;
    a.coulomb_friction_Nm = 0.5;
    a.B_s_Ns_per_m = 0.5;
    a.B_l_Ns_per_m = 0.02;
  }
  struct Bound {
    double step_s, joints_rad, spring_rad;
  };
  for (const Bound& b : {Bound{5e-4, 5e-3, 2e-4}, Bound{2.5e-4, 1.5e-3, 1e-4}}) {
    PlantOptions fo = options(acts, Integration::Fixed), ao = options(acts, Integration::Accurate);
    fo.gravity_m_s2 = ao.gravity_m_s2 = 9.81;
    fo.step_s = b.step_s;
    ao.accuracy = 1e-9;
    Plant fixed(two_links(), fo), accurate(two_links(), ao);
    double dq = 0, ds = 0, swing = 0;
    for (int k = 1; k <= 1000; ++k) {
      const double t = (k - 1) * 1e-3;
      const Eigen::Vector2d i(2.0 * std::sin(2 * kPi * t), 1.0 * std::sin(2 * kPi * 3 * t));
      fixed.set_currents(i);
      accurate.set_currents(i);
      fixed.advance_to(k * 1e-3);
      accurate.advance_to(k * 1e-3);
      dq = std::max(dq, (fixed.joint_positions() - accurate.joint_positions()).cwiseAbs().maxCoeff());
      ds = std::max(ds, (fixed.spring_deflections() - accurate.spring_deflections()).cwiseAbs().maxCoeff());
      swing = std::max(swing, accurate.joint_positions().cwiseAbs().maxCoeff());
    }
    std::printf("rotary chain 1 s, fixed %g ms vs accurate: joints %.3g rad (swing %.3g rad), spring %.3g rad\n",
                b.step_s * 1e3, dq, swing, ds);
    EXPECT_GT(swing, 0.5);
    EXPECT_LT(dq, b.joints_rad) << b.step_s;
    EXPECT_LT(ds, b.spring_rad) << b.step_s;
  }
}

// The plant checks its table against the robot, at the entry's place.
TEST(PlantRotary, AnActuatorOnAMissingJointIsLocated) {
  ActuatorParams m = motor("wrist", ActuatorKind::ROTARY);
  m.where = "arm.yaml:7:5";
  try {
    Plant p(one_link(), options({m}));
    ADD_FAILURE() << "no error";
  } catch (const ModelError& e) {
    EXPECT_EQ(std::string(e.what()), "arm.yaml:7:5: actuator 'wrist': the robot 'one_link' has no joint 'wrist'");
  }
}

}  // namespace
}  // namespace dmbd::model
