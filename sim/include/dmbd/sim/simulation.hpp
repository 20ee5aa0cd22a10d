#pragma once
// Multi-rate co-simulation: the continuous plant (dmbd::model::Plant, integrated between
// events with error control or by its fixed step) and discrete controllers
// (sim::Controller: loop programs run by the codegen interpreters, the arithmetic of the
// generated code in double, float or fixed point, or any other) at their own rates,
// joined by a bus of named scalar signals.
//
// At every controller tick t_k = k / rate the controller samples its inputs from the bus
// (sensors are read from the plant at that instant, references evaluated at t_k), runs
// one step, and publishes its outputs at t_k + delay_s (its computation delay); a
// published output holds (zero-order hold) until the next. Signals named
// "<joint>.current" (A) and "<joint>.torque" (N m) drive the plant. Events fall on an
// integer nanosecond grid, so runs are exactly repeatable.
//
// Bus signals (per joint J of the plant; the sensor ones are sampled at controller
// ticks, so that neither a controller's inputs nor the noise sequence depend on the
// log rate, and the log holds the last sample; with no controller they are sampled at
// log ticks):
//   J.q, J.qd                true joint angle (rad) and rate (rad/s); m, m/s for a prismatic joint
//   J.current, J.torque      commands (A for an actuated joint; N m for any joint, N for a
//                            prismatic one, clamped to the URDF effort limit without an actuator)
//   and for a joint with an actuator:
//   J.q_enc                  joint angle from the motor and spring encoders through
//                            the transmission (the firmware's lookup): x(q) = x(0) + theta/N_m - x_s
//   J.q_pot                  joint angle from the potentiometer (noise, ADC, 1st-order filter),
//                            when the actuator has one
//   J.force                  sensed actuator force K_s x_s (spring encoder), N (N m for a rotary
//                            kind; a rigid geared motor's: its current-based torque estimate)
//   J.motor_angle, J.spring_deflection   encoder readings (rad; m, or rad for a rotary SEA;
//                            no spring signal for a rigid geared motor)
// and for a floating base (true values, after every plant advance):
//   base.x, base.y, base.z   torso origin in world (m)
//   base.roll, base.pitch, base.yaw   R = Rz(yaw) Ry(pitch) Rx(roll) (rad)
//   base.tilt                angle of the torso's z axis from the vertical (rad)
//   base.wx, base.wy, base.wz   torso angular velocity, world axes (rad/s; an ideal gyro)
//   base.vx, base.vy, base.vz   torso origin velocity, world (m/s)
// plus every reference (its name) and every controller output (its bus name). Logged
// only, per actuator: J.force_true (N), J.current_applied (A, after the drive's limit),
// J.i2t (A^2 s, the integral of the applied current squared since t = 0: exact, the
// current is held between events), and the thermal nodes J.T_winding, J.T_housing
// (degC; _cooled and _uncooled with cooling Both); and with contact, the force on the
// robot at each colliding collision shape, contact.K.fx/fy/fz (N, world; K counts the
// shapes that can collide, links in order and each link's in URDF order). A
// reference may also drive a command directly ("l_knee.current": a current chirp for
// system identification): it is then held from log tick to log tick.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "dmbd/base/error.hpp"
#include "dmbd/model/plant.hpp"
#include "dmbd/model/thermal.hpp"
#include "dmbd/sim/controller.hpp"
#include "dmbd/sim/log.hpp"
#include "dmbd/sim/run_result.hpp"
#include "dmbd/sim/signals.hpp"

namespace dmbd::sim {

// A controller on the bus: its ports bound to bus signals (in its port order; an empty
// output name publishes "<name>.<port>"), and its computation delay: an output computed
// from the inputs sampled at t_k is applied at t_k + delay_s (0 <= delay <= one period).
struct ControllerSpec {
  std::string name;                   // in messages, and the prefix of its unbound outputs
  std::shared_ptr<Controller> controller;  // required (InputError when null); its rate is the tick rate
  double delay_s = 0;                 // computation delay, s, rounded to whole nanoseconds
  std::vector<std::string> inputs;    // bus signal per controller input
  std::vector<std::string> outputs;   // bus signal per controller output
  // Where the controller and each input binding were written ("file:line:col"; empty, or
  // input_where shorter than inputs, when unknown): errors about them start with it.
  std::string where;
  std::vector<std::string> input_where;  // "file:line:col" per input binding, in inputs' order
};

// A reference (a scenario's `references` entry): a new bus signal (no unit) that
// controllers read, or, named J.current or J.torque of the plant, a command it drives
// directly. Evaluated at controller ticks and log ticks, held in between.
struct ReferenceSpec {
  std::string name;  // bus signal
  Source source;     // its value against time (s)
  std::string where = {};  // "file:line:col" it was written at, or empty: starts errors about it
};

// A force on a link: f_W = direction * source(t) at point p_L of the link.
// (A scenario's `forces` entry; evaluated at every event, held in between.)
struct ForceSpec {
  std::string link;                                        // a link of the plant's robot (InputError otherwise)
  Eigen::Vector3d point_L = Eigen::Vector3d::Zero();       // p_L, link frame, m (`point`)
  Eigen::Vector3d direction_W = Eigen::Vector3d::UnitX();  // world frame, not normalised: its length scales f
  Source source;                                           // the magnitude against time, N
  std::string where = {};  // as ReferenceSpec::where
  // A force started by an event on the bus (`trigger`; none: the source runs on the
  // simulation's clock): the bus signal's occurrence-th change (a controller's counter,
  // e.g. balance.touch_downs), seen at the event it is published at, starts the source
  // after_s later, at T; the force is 0 before T and source(t - T) from T on (held between
  // events, as every force). T is logged as "forces.K.start_s" (K: the force's index;
  // NaN until it is known). A signal that is not on the bus is an InputError.
  struct Trigger {
    std::string signal;  // the bus signal whose changes are counted
    int occurrence = 1;  // >= 1
    double after_s = 0;  // >= 0
  };
  std::optional<Trigger> trigger = {};  // none: the source runs on the simulation's clock
};

// A start-up support for a floating base (the authors' balancing simulation held the
// base until it was released): two points of the base link, its origin and height_m
// above it on its z axis, each pulled back horizontally to where it was at t = 0 by a
// spring and damper, until release_s. Horizontal only: the legs carry the weight; the
// support keeps the torso from tipping or drifting. Updated at every event.
// (The scenario's robot.support.)
struct SupportSpec {
  double release_s = 0.0;             // s: the support acts while t < release_s
  double stiffness_N_per_m = 5000.0;  // k of each point's horizontal spring, N/m
  double damping_N_s_per_m = 500.0;   // c of each point's horizontal damper, N s/m
  double height_m = 0.3;              // the upper point's height above the base origin, m
};

// Ends a floating-base run early, without error, once the robot is down: the torso's
// origin below torso_below_m or its tilt beyond tilt_above_rad (checked after every
// plant advance; the log then ends with that instant's row). Simulating a robot lying on
// the ground (only its feet collide) is meaningless and may diverge.
// (The scenario's end_on_fall.)
struct EndOnFall {
  double torso_below_m = 0.5;   // the base origin's height (base.z), m
  double tilt_above_rad = 1.0;  // base.tilt, rad
};

// Which of each actuator's two thermal models (liquid cooling on and off, both always
// run) are logged (the scenario's thermal.cooling): On or Off as J.T_winding and
// J.T_housing, Both as J.T_winding_cooled, J.T_housing_cooled, J.T_winding_uncooled and
// J.T_housing_uncooled (degC).
enum class Cooling { On, Off, Both };

// Everything a Simulation runs besides the plant (a scenario's variant, built by
// run_variant; docs/scenario-format.md names each field's key).
struct SimulationSpec {
  // Stepped in this order at an instant where several tick (a later one reads an earlier
  // one's undelayed outputs in the same tick).
  std::vector<ControllerSpec> controllers;
  std::vector<ReferenceSpec> references;  // `references`
  std::vector<ForceSpec> forces;          // `forces`
  std::optional<SupportSpec> support;  // floating base only
  std::optional<EndOnFall> end_on_fall;  // floating base only
  double duration_s = 1;              // simulated time, s (0 < duration < 1e9, rounded to whole ns)
  double log_rate_hz = 1000;          // log rows per second; a whole number of ns per period
  // A pattern of signal names the log keeps: shell-style, as POSIX fnmatch reads it
  // ("balance.*", "l_?nee.q").
  struct LogPattern {
    std::string pattern;  // e.g. "base.*"
    std::string where;    // "file:line:col" of the pattern (as ReferenceSpec::where)
  };
  // The signals the log keeps (a scenario's log_only), time always; empty: every signal.
  // A pattern that matches no signal is an InputError at its where.
  std::vector<LogPattern> log_only;
  bool sensor_noise = false;          // off: exact readings (no quantisation, no noise)
  uint64_t seed = 1;                  // of the noise (std::mt19937_64); potentiometer k uses seed * 1000003 + k
  double force_noise_N = 0;           // white noise added to J.force when sensor_noise
  Cooling cooling = Cooling::On;      // thermal models run per actuator; Both logs two
  // Runaway detection: a non-finite joint angle, or a joint faster than this (rad/s),
  // after a plant advance means the run diverged (DivergenceError).
  double max_joint_rate_rad_s = 200;
};

// Thrown when the run diverges (NaN, integrator failure, runaway); the message names
// the time and the state ("simulation diverged at t = 0.731 s: ... (l_knee q = ...)").
class DivergenceError : public InputError {
 public:
  // DivergenceError(message), InputError's constructor: what() is the message as given.
  using InputError::InputError;
};

// The co-simulation of one plant with a SimulationSpec (above): the bus is built at
// construction, run() integrates and logs (meant to be called once per object).
class Simulation {
 public:
  // The plant must outlive the simulation. Throws InputError (dmbd/base/error.hpp)
  // naming a bus signal that nothing provides, a program input/output count mismatch,
  // a rate that is not a whole number of nanoseconds, or an unknown link; also for a
  // delay outside 0 to one period, a reference named as an existing signal other than
  // a command, a signal both a controller and a reference drive, a null controller,
  // and a support on a base that is not floating.
  Simulation(model::Plant& plant, SimulationSpec spec);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // Runs from the plant's current state for spec.duration_s;
  // `on_progress` with the fraction done, about every 1 % of the run.
  // The log's times count from 0 at the start; it ends early (without error) when
  // end_on_fall sees the robot down. Throws InputError, before running, for a duration
  // outside (0, 1e9) s, a log rate that is not a whole number of nanoseconds per period
  // or a log that would exceed 2 GB; DivergenceError on a runaway; and the plant's
  // model::ModelError (a failed integrator step) with the joints' state appended.
  Log run(const std::function<void(double)>& on_progress = {});

  // Bus signal names (the log's columns follow them).
  std::vector<std::string> signal_names() const;
  // Controller steps taken and saturations engaged, per controller.
  std::vector<long long> controller_steps() const;
  // Controller::clamp_events() of each controller, in spec order (0 for one that does
  // not count them: see counts_clamp_events()).
  std::vector<unsigned long long> controller_clamp_events() const;
  // Per joint name: the joints whose rate went beyond their URDF velocity limit during
  // run() (checked after every plant advance; joints without a limit are not watched).
  std::map<std::string, VelocityExcess> velocity_limit_exceeded() const;
  // One line per triggered force whose trigger never fired during run() (the signal
  // changed fewer times than its occurrence): that force was never applied.
  std::vector<std::string> unfired_triggers() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dmbd::sim
