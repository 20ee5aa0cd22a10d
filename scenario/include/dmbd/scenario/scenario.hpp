#pragma once
// Scenarios: what `dmbd simulate` runs (docs/scenario-format.md). A scenario file names
// the robot and how it is mounted, which joints its actuators drive and which are
// welded or locked, the controllers (diagram files lowered to loop programs) and how
// their ports bind to bus signals, references, disturbances, duration and outputs, and
// optionally `variants` or a `matrix` of variants (each overriding fields of the base)
// and an `experiment` that turns the variants' logs into metrics and figures.
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "dmbd/control/bus_controller.hpp"
#include "dmbd/experiments/experiment.hpp"
#include "dmbd/model/dynamics.hpp"
#include "dmbd/model/plant.hpp"
#include "dmbd/model/robot_folder.hpp"
#include "dmbd/sim/controller.hpp"
#include "dmbd/sim/run_result.hpp"
#include "dmbd/sim/simulation.hpp"

namespace dmbd::scenario {

// A rigid mass bolted to a link: mass at com_L (link frame), principal moments about
// axes parallel to the link frame's.
// (An entry of robot.payloads; merged into the link after welding.)
struct Payload {
  std::string link;                                        // `link`: the link it is bolted to
  double mass_kg = 0;                                      // `mass_kg`, kg (> 0)
  Eigen::Vector3d com_L = Eigen::Vector3d::Zero();         // `com`: its centre of mass, link frame, m
  Eigen::Vector3d inertia_kgm2 = Eigen::Vector3d::Zero();  // `inertia_kgm2`: Ixx, Iyy, Izz about com_L, kg m^2
};

// An inertia disc on a joint's axis, sized so that the load the joint's actuator sees,
// reflected through the linkage at the joint's initial angle, is reflected_mass_kg:
// (I_subtree + I_disc) N_l(q0)^2 = M_l. Its centre is on the axis: no gravity torque.
// (An entry of robot.loads; the disc is 10 kg, on the child link at the joint's origin.)
struct ReflectedLoad {
  std::string joint;              // `joint`: a moving joint with an actuator
  double reflected_mass_kg = 0;   // `reflected_mass_kg`: M_l, kg (> 0), at the joint's initial angle
};

// The scenario's `robot` (docs/scenario-format.md, "robot"): the plant's robot, how it is
// mounted, which joints move and which actuators drive them.
struct RobotSetup {
  // `name`: the robot folder (model::find_robot, the scenario's folder searched first),
  // or null when the scenario gives `urdf` alone.
  std::shared_ptr<const model::RobotFolder> folder;
  // The URDF: the folder's, or `urdf` (written relative to the scenario's folder;
  // load_scenario keeps it resolved, having checked that it exists).
  std::string urdf;
  // The actuator file (`actuators.file`, else the folder's; "" none: docs/actuator-format.md).
  std::string actuator_file;
  // `base`: Fixed (the root link welded to the world at X_WB) or Floating (a free 6-dof
  // base starting at X_WB, re-seated on the ground with contact).
  model::BaseMode base = model::BaseMode::Fixed;
  // `base_pose`: the root link's pose in the world (xyz m, R = Rz(yaw) Ry(pitch) Rx(roll)).
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  bool all_actuators = false;                  // `actuators: all`: every actuator whose joint moves
  std::vector<std::string> actuators;          // joints driven through their actuators (the file's entries)
  std::string actuator_load_set;               // `actuators.load`: a named load set of the file ("": each entry's `load:`)
  std::vector<std::pair<std::string, double>> actuator_scales;  // `actuators.scale`: {symbol: factor}, in file order
  bool freeze_all_others = false;              // weld every 1-dof joint not in `moving`
  std::vector<std::string> moving;             // `moving` (given: freeze_all_others is set)
  std::vector<std::pair<std::string, double>> freeze;   // welded at these angles (others at 0 clamped into limits)
  std::vector<std::pair<std::string, double>> initial;  // joint angles at t = 0
  std::vector<std::pair<std::string, double>> lock;     // locked outputs
  std::vector<Payload> payloads;               // `payloads`, in file order
  // `armature`: {joint: kg m² (kg)}, a geared rotor's inertia reflected onto a joint that
  // has no actuator model (model::Joint::armature), in file order.
  std::vector<std::pair<std::string, double>> armature;
  std::vector<ReflectedLoad> loads;            // `loads`, in file order
  bool contact = false;                        // `contact`: every collision shape against the ground
  double gravity_m_s2 = 9.81;                  // `gravity`, m/s^2 along -z of the world (0: none)
  // `ground_normal`: the ground plane's normal through the origin (normalised; a tilted
  // one makes a slope, gravity stays along -z), world frame.
  Eigen::Vector3d ground_normal = Eigen::Vector3d::UnitZ();
  std::optional<sim::SupportSpec> support;          // a floating base held horizontally until released
  // Where each named entry was written ("file:line:col"), keyed "moving:NAME",
  // "actuators:NAME", "actuators.load", "actuators.scale:SYMBOL", "armature:NAME", "freeze:NAME", "initial:NAME", "lock:NAME", "loads:NAME",
  // "payloads:LINK", and "support": mistakes found only when the robot is built are
  // reported there.
  std::map<std::string, std::string> where;
};

// What runs a scenario controller's loop program: codegen's interpreter, or its
// generated code compiled by the system compiler and loaded (software in the loop).
enum class Implementation { Interpreter, Generated };

// An entry of the scenario's `controllers` (docs/scenario-format.md, "controllers"): a
// diagram lowered to a loop program at rate_hz, its ports bound to bus signals.
struct ControllerSetup {
  std::string name;                            // `name`: in messages; unbound outputs are NAME.PORT
  std::string diagram;                         // resolved path
  std::vector<std::pair<std::string, double>> parameters;  // `parameters`: diagram parameter overrides
  double rate_hz = 1000;                       // `rate_hz`: ticks per second, the lowering rate too
  double delay_s = 0;                          // `delay_s`: computation delay, s, 0 to one period
  sim::Scalar scalar = sim::Scalar::Double;              // `scalar`: double, float or fixed
  int word_bits = 32;                          // `word_bits`: 16 or 32, the fixed-point word
  Implementation implementation = Implementation::Interpreter;  // interpreter or generated code
  std::vector<std::pair<std::string, std::string>> inputs;   // program input -> bus signal
  std::vector<std::pair<std::string, std::string>> outputs;  // program output -> bus signal
  std::string where;                                         // "file:line:col" of the controller
  // "file:line:col" of each input binding, in the order of inputs.
  std::vector<std::string> input_where, output_where;        // ... of each output binding
};

// The scenario's `frames` (docs/scenario-format.md, "frames"): report/ renders the frames
// and the video from a run's log; sim only reads and keeps it.
struct FrameSetup {
  bool enabled = true;                         // `enabled` (`frames: false`: off, as --no-frames)
  double fps = 30;                             // `fps`: the video's frame rate, the highest sampling rate
  // `width`, pixels.
  int width_px = 1280, height_px = 720;        // `height`, pixels
  int max_frames = 240;                        // longer runs render at a lower rate (time-lapse)
  // `camera.position`, world frame, m (none: a three-quarter view from the front left).
  std::optional<Eigen::Vector3d> camera_position, camera_look_at;  // `camera.look_at`, world, m
  std::string variant;                         // which variant is rendered (default: the first)
  // Unused: no scenario key sets it and nothing reads it (always empty).
  std::string phase_signal;
};

// An entry of the scenario's `plots`: logged signals against time, in plots/FILE (PNG).
struct PlotSetup {
  std::string title,  // `title` (may be empty)
      y_label,        // `y_label` (may be empty)
      file;           // `file`: the PNG's name in plots/
  std::vector<std::string> signals;            // "signal" or "variant:signal"
};

// A figure of merit against a swept parameter (`sweep_plots`, docs/scenario-format.md):
// one numeric matrix axis on x, one metrics.json value per run on y, and the
// condition it must meet, so that the figure shows the interval of the parameter where
// an observation holds (and metrics.json `sweeps` gives it).
struct SweepCurve {
  std::string metric;                 // `metric`: a JSON pointer into metrics.json, {run} standing for the run's name
  std::string label;                  // `label`: the curve's name (its axes' title)
  double scale = 1;                   // `scale`: plotted and compared as metric x scale (e.g. 1000: m to mm)
  std::optional<double> at_most;      // `at_most`: the condition's upper bound, in scaled units
  std::optional<double> at_least;     // `at_least`: its lower bound
};
// One entry of `sweep_plots`.
struct SweepPlotSetup {
  std::string file;                   // `file`: the PNG's name in plots/ (its stem keys metrics.json `sweeps`)
  std::string axis;                   // `axis`: a matrix axis whose every value gives `value`
  std::string title;                  // `title` (may be empty)
  std::string x_label;                // `x_label` (default: the axis)
  std::string y_label;                // `y_label` (may be empty)
  bool log_x = false;                 // `log_x`: a logarithmic x axis
  std::vector<SweepCurve> curves;     // `curves`: one axes each, stacked, sharing x
  std::string where;                  // "file:line:col" of the entry
};

// A variant's `push` (docs/scenario-format.md, "push"): one horizontal push, its keys
// merged key by key over the base and the matrix axes (so that one axis gives the
// direction, another the force, another the moment), turned into one more entry of the
// variant's forces when the scenario has been read. force_N 0: no push (a reference run).
struct PushSetup {
  std::optional<std::string> link;                   // `link`: the link pushed
  std::optional<Eigen::Vector3d> point;              // `point`: in the link's frame, m (default 0)
  std::optional<double> direction_deg;               // `direction_deg`: 0 forward (+x), 90 left (+y)
  std::optional<double> force_N;                     // `force_N`: >= 0
  std::optional<double> duration_s;                  // `duration_s`: > 0
  std::optional<double> start_s;                     // `start_s`: at this time ...
  std::optional<sim::ForceSpec::Trigger> trigger;    // `trigger`: ... or at a bus event (forces[].trigger)
  std::string where;                                 // "file:line:col" of the last `push` map read
};

// How the plant is integrated (model::PlantOptions): error-controlled (accurate, for
// identification and frequency responses) or the fixed semi-implicit step.
struct IntegrationSetup {
  model::Integration mode = model::Integration::Accurate;  // `mode`: accurate or fixed
  double step_s = 5e-4;                        // fixed: the largest step
  double accuracy = 1e-5;                      // accurate: relative accuracy
};

// One run of the scenario: the top-level variant fields with a variant's (or each matrix
// axis's value's) fields applied (docs/scenario-format.md, "variants and matrix").
struct VariantSetup {
  std::string name;                            // "base" without variants
  std::vector<std::pair<std::string, std::string>> axes;  // matrix axis -> value name
  std::vector<std::pair<std::string, double>> axis_values;  // matrix axis -> the value's `value` (where given)
  RobotSetup robot;                            // `robot`
  std::vector<ControllerSetup> controllers;    // `controllers`, stepped in this order at a shared tick
  std::vector<sim::ReferenceSpec> references;       // `references`
  std::vector<sim::ForceSpec> forces;               // `forces`
  double duration_s = 1;                       // `duration_s`: simulated time, s (--duration overrides it)
  double log_rate_hz = 1000;                   // `log_rate_hz`: log rows per second
  bool sensor_noise = false;                   // `sensors.noise`: quantised, noisy sensors (off: exact)
  uint64_t seed = 1;                           // `sensors.seed`: of the sensor noise
  double force_noise_N = 0;                    // `sensors.force_noise_N`: std. deviation on J.force, N
  sim::Cooling cooling = sim::Cooling::On;               // `thermal.cooling`: which thermal models are logged
  IntegrationSetup integration;                // `integration`
  // `bus_controllers` (and the deprecated `osc`, `balance`): robot-level controllers on
  // the bus (control/registry.hpp), each a type's options, stepped after `controllers`.
  std::vector<std::shared_ptr<const control::BusControllerOptions>> bus_controllers;
  std::optional<sim::EndOnFall> end_on_fall;        // end the run once the robot is down (floating base)
  std::optional<PushSetup> push;               // `push` (merged key by key; already appended to `forces`)
};

// A scenario file read and checked (load_scenario; docs/scenario-format.md).
struct Scenario {
  std::string name,         // `name` (default: the file name without its extension)
      description,          // `description` (may be empty)
      file;                 // the path it was read from, as given to load_scenario
  // Every run, in order: the one "base", the `variants`, or every combination of the
  // `matrix` axes' values (the first axis varying slowest).
  std::vector<VariantSetup> variants;
  FrameSetup frames;              // `frames`
  std::vector<PlotSetup> plots;   // `plots`
  std::vector<SweepPlotSetup> sweep_plots;  // `sweep_plots`
  experiments::ExperimentSetup experiment;  // `experiment` (type "" without one)
  // `log`: signals kept for the log alone (a controller output nothing else reads is
  // otherwise refused as a likely misspelling).
  std::vector<std::string> log_signals;
  // `log_only`: the signals every run's log keeps (patterns; empty: all), each with where
  // it was written (a pattern that matches no signal is an error there).
  std::vector<sim::SimulationSpec::LogPattern> log_only;
  // One line each: deprecated keys that were read (printed by dmbd simulate).
  std::vector<std::string> notes;
};

// Reads and checks a scenario. Throws InputError "FILE:LINE:COL: what was expected",
// one line per problem found in the file (not only the first), or "FILE: cannot read
// the scenario file: REASON".
Scenario load_scenario(const std::string& path);

// How run_variant runs a variant.
struct RunOptions {
  std::optional<double> duration_s;            // overrides every variant's duration
  std::function<void(double)> on_progress;     // the fraction of the run done (0..1), about every 1 %
};

// The robot a variant simulates (its URDF with the welded joints, payloads and test
// inertias applied) and the plant's options (base, actuators, contact, integration).
// Throws InputError naming where in the scenario a joint, link or load is wrong.
struct VariantPlant {
  model::RobotDescription robot;  // welded, with payloads and load discs
  model::PlantOptions options;    // base, X_WB, gravity, contact, integration, actuators (the actuator file's)
};
// The VariantPlant of variant v of s; where a mistake was written is taken from
// v.robot.where (else s.file names it). Also InputError for actuators without an actuator
// file, and the model's ModelError for a URDF or actuator file it cannot read or a weld
// it refuses.
VariantPlant variant_plant(const Scenario& s, const VariantSetup& v);
// What a user should read before the runs, one line each: the scenario's notes
// (deprecated keys), each robot's URDF warnings (once per URDF) and, under `actuators:
// all`, the moving joints the actuator file has no entry for (driven by ideal torques).
// Throws what loading the URDF or the actuator file throws.
std::vector<std::string> scenario_notes(const Scenario& s);

// A joint's angle at t = 0: robot.initial, else robot.lock, else 0.
double initial_angle(const RobotSetup& r, const std::string& joint);

// Builds the plant and the controllers of a variant and runs it. Throws InputError for a
// mistake found while building (variant_plant's, a controller's diagram or binding, the
// Simulation's) and DivergenceError when the run diverges; run_scenario prepends the
// scenario file and the variant.
sim::VariantResult run_variant(const Scenario& s, const VariantSetup& v, const RunOptions& options);

}  // namespace dmbd::scenario
