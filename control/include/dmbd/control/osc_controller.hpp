#pragma once
// Operational space control of a fixed-base robot as a controller on the bus (paper
// Sec. IV-A): one point of the robot (a frame's origin, e.g. the left ankle) follows a
// sinusoidal path about where it starts, every joint held near its starting angle by a
// posture task in the null space; τ = A J̄ (ẍ_cmd − J̇ v) + b + g + Nᵀ τ₀
// (wholebody::OperationalSpaceControl), optionally plus the actuators' identified
// output-side damping at the joint (OscSetup::compensate_load_damping). Each joint's torque command goes to its
// actuator the way the robot does it: F_d = τ_d N_l(q) (the linkage, model/actuator.hpp)
// on "<joint>.force_d", for that joint's force controller (a loop program on the bus).
//
// Ports, per joint J of the model (in the model's joint order):
//   inputs   J.<q_signal>, J.<qd_signal>   joint angle and rate (configurable sensors)
//            J.force                       sensed actuator force (actuated joints)
//   outputs  J.tau_d (N m)                 the OSC torque
//            J.torque (N m)                the same, driving the plant directly (joints
//                                          without an actuator: ideal torque joints)
//            J.force_d (N)                 the actuator force command (actuated joints)
//            J.tau_s (N m)                 the sensed force through the linkage, F / N_l(q)
//            osc.x_d, osc.y_d, osc.z_d, osc.x, osc.y, osc.z (m)   target and measured point
// Allocation-free step; the wall time of each evaluation is recorded (tick_times_us).
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "dmbd/model/actuator.hpp"
#include "dmbd/model/dynamics.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/control/bus_controller.hpp"

namespace dmbd::control {

// The point's target: p_d(t) = p_0 + s(t) (a ∘ sin(2π f t)), each axis its own
// amplitude, with a smooth start s(t) = minimum-jerk ramp 0 → 1 over ramp_s (so that the
// target's velocity and acceleration start at 0 and are continuous).
struct OscTrajectory {
  Eigen::Vector3d amplitude_m = Eigen::Vector3d::Zero();  // a, per world axis, m (`amplitude_m`)
  double frequency_hz = 1.0;                              // f, Hz (`frequency_hz`)
  double ramp_s = 1.0;                                    // s, the ramp's length (`ramp_s`; 0: none, s = 1)
  // Target position, velocity and acceleration at t (relative to p_0).
  void evaluate(double t, Eigen::Vector3d& p, Eigen::Vector3d& v, Eigen::Vector3d& a) const;
};

// The options of a `bus_controllers` entry of type osc (docs/scenario-format.md,
// "bus_controllers"): the controller's point, path, gains and sensors; rate, delay and
// name are every bus controller's (BusControllerOptions).
struct OscSetup : BusControllerOptions {
  OscSetup() { type = name = "osc"; }
  // The point's link (`link`; required: the robot folder's controllers.osc.link or the
  // scenario's).
  std::string link;
  Eigen::Vector3d point_L = Eigen::Vector3d::Zero(); // its place in the link (`point`), link frame, m
  OscTrajectory trajectory;                          // `trajectory`: the point's path about p_0
  Eigen::Vector3d kp = Eigen::Vector3d::Constant(400.0);   // task gains, 1/s² (per world axis; `kp`)
  Eigen::Vector3d kd = Eigen::Vector3d::Constant(40.0);    // 1/s (`kd`)
  // The posture task's gains (every joint toward its starting angle): kp, 1/s² (`posture.kp`),
  double posture_kp = 100.0, posture_kd = 20.0;            // and kd, 1/s (`posture.kd`)
  // The angle signal it reads per joint J: J.<q_signal> (`sensors.q`; e.g. q_enc).
  std::string q_signal = "q",
      // The rate signal it reads per joint J: J.<qd_signal> (`sensors.qd`).
      qd_signal = "qd";
  // Add each actuator's output-side damping at the joint, B_l r(q)² q̇_ref (Table I's
  // B_l, which the rigid-body model lacks), to the OSC torque: a feedforward at the
  // least-dissipation joint rates for the reference's rate (osc_controller.cpp).
  bool compensate_load_damping = false;
};

// The controller above on the bus (ports: above), built by the registry's osc type
// (registry.hpp) for a fixed-base variant.
class OscController : public BusController {
 public:
  // robot: the robot as simulated (welded joints applied); base fixed at X_WB; q0: the
  // joint angles at t = 0 by joint name, 0 for a joint not listed (the posture target and
  // the path's centre); actuators: those of the plant (their transmissions). max_ticks:
  // how many tick times to keep (storage allocated here). Throws InputError (at
  // setup.where) for an unknown link or no link given.
  OscController(const model::RobotDescription& robot, const Eigen::Isometry3d& X_WB, double gravity_m_s2,
                const std::vector<model::ActuatorParams>& actuators,
                const std::vector<std::pair<std::string, double>>& q0, const OscSetup& setup, long long max_ticks);
  ~OscController() override;

  // "osc": its timing figures are osc_tick_us_median and osc_tick_us_max.
  std::string timing_name() const override { return "osc"; }
  // Per actuated joint its force command J.force_d (the joint's force loop must read it).
  std::vector<JointCommand> joint_commands() const override;
  // Each actuator's current limit as truth "J.current_limit_A" (the osc_table experiment's
  // saturation figure).
  void record(const model::Plant& plant, std::map<std::string, double>& truth) const override;

  // The joints, in the model's order.
  const std::vector<std::string>& joints() const;

 protected:
  // One tick: the target at t = (ticks so far) / rate_hz, the OSC torque, the outputs.
  void tick(const double* u, double* y) override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dmbd::control
