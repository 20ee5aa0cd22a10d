#pragma once
// The paper's balancing controller (Sec. IV-B, Fig. 7, Fig. 8) as a controller on the bus:
// unsupported stepping in place by whole-body control and the TVR footstep planner.
// Every control tick (1 kHz, with its computation delay):
//   1. state: joint angles and rates, the torso IMU (orientation, angular velocity), and
//      the base's position and velocity either from the stance foot's kinematics
//      (KinematicComEstimator) or from "motion capture" (the true values plus noise);
//   2. phase: wholebody::PhaseMachine (start-up joint move and body lift, an optional
//      weight shift, then double support → lift → swing → landing per side, touch-down on
//      the swing ankle's velocity);
//   3. footsteps: the TVR planner at the swing's start and once more at mid-swing, the
//      swing foot on a B-spline (wholebody::SwingTrajectory); the heading hold's hip yaw
//      offsets for the swing (BalanceSetup::heading_gain);
//   4. prioritised IK from the contact null space (hip yaws → swing ankle → torso roll,
//      pitch, height → swing foot; in the weight shift hip yaws → torso → CoM x, y),
//      giving q_des = q + Δq, q̇_des, q̈_des (the tasks' accelerations with the task gains,
//      none by default);
//   5. joint feedback q̈_cmd = q̈_des + Kp (q_des − q) + Kd (q̇_des − q̇) on the joints;
//   6. the whole-body QP (wholebody::WbcQp): reaction forces in the friction pyramid,
//      F_max blended through lift and landing, torque limits → feedforward torques τ_ff.
//      A QP that fails keeps the last command (counted: balance.qp_failures).
//   7. a fall (the torso tilted beyond fall_tilt_rad by the IMU) ends the control for good:
//      every joint is then held where it is with no feedforward (balance.fallen = 1).
// Its outputs are each joint's targets for that joint's own loop: J.q_des, J.qd_des,
// J.tau_ff, and for an actuated joint the feedforward actuator force J.force_ff =
// τ_ff N_l(q) (for joint_impedance_controller.yaml's F_ff; with actuator_feedforward
// plus the actuator's own rotor inertia and damping at the commanded motion).
//
// Ports (per joint J of the model, in the model's joint order):
//   inputs   J.<q_signal>, J.<qd_signal>
//            base.roll, base.pitch, base.yaw, base.wx, base.wy, base.wz   (the IMU)
//            base.x, base.y, base.z, base.vx, base.vy, base.vz            (motion capture only)
//   outputs  J.q_des (rad), J.qd_des (rad/s), J.tau_ff (N m), J.force_ff (N, actuated)
//            balance.phase (0 joint move, 1 body lift, 2 double support, 3 lift, 4 swing,
//            5 landing, 6 weight shift), balance.swing_side (0 left, 1 right), balance.step,
//            balance.touch_downs, balance.qp_failures, balance.fallen,
//            balance.com_x/y/z, balance.com_vx/vy (m, m/s: the estimate the controller uses),
//            balance.foothold_x/y (the current swing's planned foothold),
//            balance.swing_x/y/z_d (the swing foot's target), balance.swing_x/y/z (the
//            swing side's contact point), balance.stance_x/y (the stance foot's),
//            balance.landings, balance.landed_x/y, balance.planned_x/y (the last
//            landing: where the foot that came down stands, latched at the next lift's
//            start once it has settled, and where it was planned to at its touch-down;
//            balance.landings counts them),
//            balance.fz_l, balance.fz_r (N, the QP's normal forces).
// Allocation-free step; the wall time of each evaluation is recorded (tick_times_us).
#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "dmbd/model/actuator.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/control/bus_controller.hpp"
#include "dmbd/wholebody/phase_machine.hpp"
#include "dmbd/wholebody/swing.hpp"
#include "dmbd/wholebody/tvr.hpp"
#include "dmbd/wholebody/wbc_qp.hpp"

namespace dmbd::control {

// Where the controller's base position and velocity come from (`estimator`): Kinematic,
// the stance foot's kinematics from the IMU and the joints (KinematicComEstimator);
// MotionCapture, the true base.x .. base.vz plus white noise (six more inputs).
enum class BalanceEstimator { Kinematic, MotionCapture };

// Joint-level feedback in the WBC's accelerations (1/s², 1/s) for one joint.
struct JointFeedback {
  // The proportional gain, 1/s² (on the joint's or the task's position error).
  double kp = 0.0, kd = 0.0;  // the derivative gain, 1/s (on the rate error)
};

// Feedback in the IK tasks' accelerations, ẍ_cmd = ẍ_d + Kp e + Kd ė (1/s², 1/s). The
// authors' tasks had none (their errors only become Δq and the joint feedback); with a
// point contact the IK's smallest Δq for a torso error is partly a rotation of the whole
// robot about the contact point, which no joint target corrects, so the scenario may add
// them (docs/experiments.md, "balance").
struct BalanceTaskGains {
  JointFeedback torso;        // roll, pitch and height
  JointFeedback swing_foot;   // the swing foot's position
  JointFeedback joints;       // the hip yaws and the swing ankle
  JointFeedback com{20.0, 9.0};  // the CoM in the weight shift
};

// The weight shift before the first step (phases.weight_shift_s > 0): the CoM moves on a
// quintic from where it is to the point midway between the feet, shifted by offset_m,
// arriving with the lateral speed of the stepping orbit toward the first stance foot:
// v = (w/2) ω tanh(ω T/2), w the feet's lateral distance, T one step (double support +
// lift + swing + landing), ω the TVR's — the linear inverted pendulum's symmetric orbit,
// so the first step starts where the steady stepping passes. That is the plan; on DRACO's
// point feet the CoM task does not follow it (balance.yaml, 0.3 s: −0.050 of −0.20 m/s at
// the end; the path asks up to 2.6 m/s² sideways near the middle, where feet 0.19 m apart
// give about 1.1 m/s²), and the first step is still the smaller for it.
struct BalanceWeightShift {
  Eigen::Vector2d offset_m = Eigen::Vector2d::Zero();  // added to the feet's midpoint, world x and y, m
  double speed_scale = 1.0;  // on the orbit's speed
};

// The point the TVR planner treats as the pendulum's mass: the CoM (tvr.com_height_m
// should then be the CoM's height), or the authors' torso origin + an offset (in the
// torso's heading frame) with the torso's velocity (at the torso's height), or the CoM
// with the angular momentum about the stance foot's contact point (`angular_momentum`:
// the pendulum's velocity is (L_y, −L_x)/(m h), h = tvr.com_height_m; Gong and Grizzle's
// ALIP state). Over a point foot L obeys L̇ = m g (x_CoM − p) exactly, whatever the legs
// and torso do inside, so its prediction over a step holds where the CoM velocity's,
// which the swing leg's motion moves, does not.
enum class TvrPoint { Com, Torso, AngularMomentum };

// The options of a `bus_controllers` entry of type balance (docs/scenario-format.md,
// "bus_controllers"; over the robot folder's controllers.balance, key by key): the
// balancing controller's set-up. Each field's key is its name unless said otherwise.
struct BalanceSetup : BusControllerOptions {
  BalanceSetup() { type = name = "balance"; }
  // The posture the start-up's joint move goes to (rad; a joint not listed keeps its
  // initial angle) and the torso height the body lift reaches and stepping keeps (m).
  std::vector<std::pair<std::string, double>> stance_posture;
  double torso_height_m = 1.0;     // the torso origin's height target, world z, m
  double swing_ankle_rad = -0.17;  // the swing ankle's flexion target (the paper's 80°)
  wholebody::PhaseMachineParams phases;  // phase durations, body-lift forces, first swing side
  wholebody::TvrParams tvr;              // the TVR planner's t_prime_s, kappa, com_height_m
  wholebody::SwingParams swing;          // the swing foot's spline: mid height, landing speed
  wholebody::WbcQpParams qp;             // the QP's friction, weights and torque limit
  TvrPoint tvr_point = TvrPoint::Com;    // the planner's pendulum point (`tvr_point`: com or a map)
  // TvrPoint::Torso's offset from the torso origin in its heading frame (x forward, y
  // left), m (`tvr_point.torso_offset_m`).
  Eigen::Vector2d tvr_torso_offset_m{0.06, 0.0};
  // `tvr.integral_gain` [x, y] (per step, 0: none): integral action on the pull to the
  // start. At each swing's start the planner's target moves by gain × (x_des − x_s), the
  // start less where the CoM will be at the switch, up to ±integral_limit_m; a constant
  // bias the pendulum does not model (a line foot's centre of pressure off its centre)
  // then leaves no steady offset.
  Eigen::Vector2d tvr_integral_gain = Eigen::Vector2d::Zero();
  double tvr_integral_limit_m = 0.2;    // `tvr.integral_limit_m`: the largest move of the target, m, per axis
  // The heading held while stepping (`heading`: {gain, step_max_rad}; gain 0: none, the
  // torso's yaw then follows its stance foot's, which turns on its contact points). At
  // each swing's start, dpsi = gain x (the heading at the first lift - the torso's yaw),
  // within +-step_max_rad: during the swing the stance hip yaw turns the torso by dpsi
  // about the planted foot and the swing hip yaw returns to its stance angle in the air.
  double heading_gain = 0.0;          // `heading.gain`: the fraction of the error turned per step, 0 to 1
  double heading_step_max_rad = 0.05;  // `heading.step_max_rad`: the largest turn per step, rad
  BalanceTaskGains task_gains;           // feedback in the IK tasks (none by default but com's)
  // The IK's weight on the floating base's six coordinates (the joints': 1): 1 is the
  // authors' least-norm step; larger keeps the IK from "moving" the robot about its point
  // contacts, which no joint target can do (wholebody::PrioritizedIk::set_weights).
  double ik_base_weight = 1.0;
  // The swing foot's task relative to the torso (its world target less the torso's
  // measured position and velocity) instead of in the world (the authors'): the joints
  // then carry the foot to its foothold while the base falls as the pendulum will.
  bool swing_relative_to_torso = false;
  // J.force_ff also carries what each actuator's rotor inertia and damping (rotor and
  // output side) take at the commanded motion, over the drive efficiency (none: τ_ff N_l
  // alone).
  bool actuator_feedforward = false;
  // The swing foot's sole kept level (its pitch about the world's y axis as it stood at
  // the lift) instead of the swing ankle's joint angle going to swing_ankle_rad.
  bool swing_foot_level = false;
  BalanceWeightShift weight_shift;       // the weight shift's path (when phases.weight_shift_s > 0)
  // Per joint name (`joint_feedback`: {JOINT: [kp, kd]}); a joint not listed has none
  // (DRACO's folder gives the authors' [80, 170, 170, 170, 5] and [3, 8, 8, 3, 0] per leg).
  std::vector<std::pair<std::string, JointFeedback>> joint_feedback;
  // The robot's names the tasks use; no defaults (robots/NAME/robot.yaml gives them):
  // the torso (`torso_link`),
  std::string torso_link;
  // the feet's links, [left, right] (`foot_links`): each one's contact point is the
  // centre of its collision shapes (a point foot),
  std::array<std::string, 2> foot_link;
  // the hip yaw joints, [left, right] (`hip_yaw_joints`: held by the hip-yaw task),
  std::array<std::string, 2> hip_yaw;
  // the ankle joints, [left, right] (`ankle_joints`): the swing ankle's task, touch-down
  // on its velocity.
  std::array<std::string, 2> ankle;
  double fall_tilt_rad = 0.5;   // the torso's tilt from the vertical that counts as a fall
  // The angle signal it reads per joint J: J.<q_signal> (`sensors.q`).
  std::string q_signal = "q",
      // The rate signal it reads per joint J: J.<qd_signal> (`sensors.qd`).
      qd_signal = "qd";
  BalanceEstimator estimator = BalanceEstimator::Kinematic;  // kinematic or motion_capture
  double mocap_position_noise_m = 0.001;     // standard deviations of the motion capture: position, m
  double mocap_velocity_noise_m_s = 0.005;   // ... velocity, m/s (both: `motion_capture_noise`)
  unsigned long long seed = 1;               // of the motion-capture noise (std::mt19937_64)
};

// The controller above on the bus (ports: above), built by the registry's balance type
// (registry.hpp) for a floating-base variant with contact.
class BalanceController : public BusController {
 public:
  // robot: the robot as simulated (floating base); q0: the joint angles at t = 0 by
  // name; actuators: those of the plant (their transmissions). max_ticks: tick times
  // kept. Throws InputError (at setup.where) for an unknown link or joint, or a name
  // that is not set.
  BalanceController(const model::RobotDescription& robot, double gravity_m_s2,
                    const std::vector<model::ActuatorParams>& actuators,
                    const std::vector<std::pair<std::string, double>>& q0, const BalanceSetup& setup,
                    long long max_ticks);
  ~BalanceController() override;

  // "wbc": its timing figures are wbc_tick_us_median and wbc_tick_us_max.
  std::string timing_name() const override { return "wbc"; }
  // Per joint its targets J.q_des (a joint's loop must read one of J.q_des, J.qd_des,
  // J.tau_ff, J.force_ff).
  std::vector<JointCommand> joint_commands() const override;
  // The plant's total mass as truth "total_mass_kg" (the balance experiment's push
  // analysis), and the TVR planner's pendulum: "planner_gravity_m_s2" (the scenario's
  // robot.gravity) and "planner_omega_per_s" (sqrt(g / tvr.com_height_m)).
  void record(const model::Plant& plant, std::map<std::string, double>& truth) const override;
  long long qp_failures() const;  // ticks whose QP failed (the last command kept), as balance.qp_failures

 protected:
  // One tick: steps 1 to 7 above.
  void tick(const double* u, double* y) override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dmbd::control
