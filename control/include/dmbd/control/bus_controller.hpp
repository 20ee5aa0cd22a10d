#pragma once
// A robot-level controller on the simulation's bus (operational space control, balancing,
// one a user registers): what every such controller shares. Its ports are named after
// the bus signals they read and drive (the scenario binds each port to its own name); it
// times each of its ticks; it says which of its outputs are commands for a joint's loop
// or the plant (so that a scenario whose commands reach nothing is refused), what it
// records of the plant for the experiments.
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "dmbd/model/actuator.hpp"
#include "dmbd/model/dynamics.hpp"
#include "dmbd/model/plant.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/sim/controller.hpp"

namespace dmbd::control {

// A bus controller's options as read from a scenario's `bus_controllers` entry (over the
// robot folder's defaults for its type): each type derives its own struct.
struct BusControllerOptions {
  virtual ~BusControllerOptions() = default;
  std::string type;       // the registry's name of the type (`type`)
  std::string name;       // on the bus and in messages (`name`; default: the type)
  double rate_hz = 1000;  // `rate_hz`: ticks per second
  double delay_s = 0.0;   // `delay_s`: computation delay, s, 0 to one period
  std::string where;      // "file:line:col" of the entry, for messages
  // `assumed_load_set`: the actuator file's load set whose terms (B_l) the controller
  // computes with, while the plant keeps its own (empty: the plant's values). A
  // controller tuned on one load (a test stand) running on another (the robot).
  std::string assumed_load_set;
  std::string assumed_load_set_where;  // "file:line:col" of that option
};

// What a bus controller is built for: one variant's robot and plant.
struct BusControllerContext {
  const model::RobotDescription& robot;                  // as simulated (welded joints applied)
  model::BaseMode base = model::BaseMode::Fixed;         // the plant's base
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();  // its pose (fixed) or start (floating)
  double gravity_m_s2 = 9.81;                            // along -z of the world
  bool contact = false;                                  // the ground is there
  std::vector<model::ActuatorParams> actuators;          // the plant's actuators
  std::vector<std::pair<std::string, double>> q0;        // each moving joint's angle at t = 0
  double duration_s = 1;                                 // the run's length (storage for its ticks)
};

// A joint's command from a bus controller that must reach the plant: at least one of
// `signals` must be read by another controller (the joint's loop) or be a plant input
// (J.torque, J.current).
struct JointCommand {
  std::string joint;                 // the joint's name
  std::vector<std::string> signals;  // the bus signals any one of which must reach it
};

// The base of every bus controller: ports, timing, commands, what it records.
class BusController : public sim::Controller {
 public:
  // Ticks at options.rate_hz; keeps the wall time of up to max_ticks ticks.
  BusController(const BusControllerOptions& options, long long max_ticks);

  double rate_hz() const override { return rate_hz_; }
  int num_inputs() const override { return static_cast<int>(inputs_.size()); }
  int num_outputs() const override { return static_cast<int>(outputs_.size()); }
  // The bus signal port k reads (its name is the signal's).
  std::string input_name(int k) const override { return inputs_[static_cast<std::size_t>(k)]; }
  // The bus signal port k drives.
  std::string output_name(int k) const override { return outputs_[static_cast<std::size_t>(k)]; }
  std::string output_unit(int k) const override { return units_[static_cast<std::size_t>(k)]; }
  // One tick (tick() below), timed.
  void step(const double* u, double* y) final;

  // The wall time of each tick so far (up to max_ticks), µs.
  const std::vector<double>& tick_times_us() const { return tick_us_; }
  // The prefix of its timing figures in metrics.json (timing_us: PREFIX_tick_us_median, _max).
  virtual std::string timing_name() const = 0;
  // The commands that must reach the plant (none by default).
  virtual std::vector<JointCommand> joint_commands() const { return {}; }
  // The simulator's values the experiments read of this controller's plant, into truth
  // (metrics.json runs.RUN.truth), before the run. None by default.
  virtual void record(const model::Plant& plant, std::map<std::string, double>& truth) const;

 protected:
  // The ports, in order (each a bus signal's name), and the units of the outputs.
  void add_input(const std::string& signal) { inputs_.push_back(signal); }
  // Adds an output port driving `signal` (its unit, for the log).
  void add_output(const std::string& signal, const std::string& unit);
  // One tick at t = ticks() / rate_hz(): reads u[0 .. num_inputs), writes y. No allocation.
  virtual void tick(const double* u, double* y) = 0;
  // Ticks completed before this one (tick() of the k-th tick sees k).
  long long ticks() const { return ticks_; }

 private:
  double rate_hz_;
  std::vector<std::string> inputs_, outputs_, units_;
  std::vector<double> tick_us_;
  long long ticks_ = 0;
};

// How many ticks a controller at rate_hz takes over duration_s (its timing storage).
long long ticks_over(double duration_s, double rate_hz);

}  // namespace dmbd::control
