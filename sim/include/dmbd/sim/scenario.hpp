#pragma once
// Scenarios: what `dmbd simulate` runs (docs/scenario-format.md). A scenario file names
// the robot and how it is mounted, which joints its actuators drive and which are
// welded or locked, the controllers (diagram files lowered to loop programs) and how
// their ports bind to bus signals, references, disturbances, duration and outputs, and
// optionally `variants` or a `matrix` of variants (each overriding fields of the base)
// and an `experiment` that turns the variants' logs into metrics and figures.
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "dmbd/model/dynamics.hpp"
#include "dmbd/model/plant.hpp"
#include "dmbd/sim/balance_controller.hpp"
#include "dmbd/sim/osc_controller.hpp"
#include "dmbd/sim/simulation.hpp"

namespace dmbd::sim {

// A rigid mass bolted to a link: mass at com_L (link frame), principal moments about
// axes parallel to the link frame's.
struct Payload {
  std::string link;
  double mass_kg = 0;
  Eigen::Vector3d com_L = Eigen::Vector3d::Zero();
  Eigen::Vector3d inertia_kgm2 = Eigen::Vector3d::Zero();
};

// An inertia disc on a joint's axis, sized so that the load the joint's actuator sees,
// reflected through the linkage at the joint's initial angle, is reflected_mass_kg:
// (I_subtree + I_disc) N_l(q0)^2 = M_l. Its centre is on the axis: no gravity torque.
struct ReflectedLoad {
  std::string joint;
  double reflected_mass_kg = 0;
};

struct RobotSetup {
  std::string urdf = "draco";                  // "draco" or a path (relative to the scenario)
  model::BaseMode base = model::BaseMode::Fixed;
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  bool all_actuators = false;
  std::vector<std::string> actuators;          // joints driven through their VLCA
  bool freeze_all_others = false;              // weld every 1-dof joint not in `moving`
  std::vector<std::string> moving;
  std::vector<std::pair<std::string, double>> freeze;   // welded at these angles (others at 0 clamped into limits)
  std::vector<std::pair<std::string, double>> initial;  // joint angles at t = 0
  std::vector<std::pair<std::string, double>> lock;     // locked outputs
  std::vector<Payload> payloads;
  std::vector<ReflectedLoad> loads;
  bool contact = false;
  double gravity_m_s2 = 9.81;
  std::optional<SupportSpec> support;          // a floating base held horizontally until released
  // Where each named entry was written ("file:line:col"), keyed "moving:NAME",
  // "actuators:NAME", "freeze:NAME", "initial:NAME", "lock:NAME", "loads:NAME",
  // "payloads:LINK": mistakes found only when the robot is built are reported there.
  std::map<std::string, std::string> where;
};

// What runs a scenario controller's loop program: codegen's interpreter, or its
// generated code compiled by the system compiler and loaded (software in the loop).
enum class Implementation { Interpreter, Generated };

struct ControllerSetup {
  std::string name;
  std::string diagram;                         // resolved path
  std::vector<std::pair<std::string, double>> parameters;
  double rate_hz = 1000;
  double delay_s = 0;
  Scalar scalar = Scalar::Double;
  int word_bits = 32;
  Implementation implementation = Implementation::Interpreter;  // interpreter or generated code
  std::vector<std::pair<std::string, std::string>> inputs;   // program input -> bus signal
  std::vector<std::pair<std::string, std::string>> outputs;  // program output -> bus signal
  std::string where;                                         // "file:line:col" of the controller
  std::vector<std::string> input_where, output_where;        // ... of each binding
};

struct FrameSetup {
  bool enabled = true;
  double fps = 30;
  int width_px = 1280, height_px = 720;
  int max_frames = 240;                        // longer runs render at a lower rate (time-lapse)
  std::optional<Eigen::Vector3d> camera_position, camera_look_at;
  std::string variant;                         // which variant is rendered (default: the first)
  std::string phase_signal;                    // optional overlay text source
};

struct PlotSetup {
  std::string title, y_label, file;
  std::vector<std::string> signals;            // "signal" or "variant:signal"
};

// How the plant is integrated (model::PlantOptions): error-controlled (accurate, for
// identification and frequency responses) or the fixed semi-implicit step.
struct IntegrationSetup {
  model::Integration mode = model::Integration::Accurate;
  double step_s = 5e-4;                        // fixed: the largest step
  double accuracy = 1e-5;                      // accurate: relative accuracy
};

struct VariantSetup {
  std::string name;                            // "base" without variants
  std::vector<std::pair<std::string, std::string>> axes;  // matrix axis -> value name
  RobotSetup robot;
  std::vector<ControllerSetup> controllers;
  std::vector<ReferenceSpec> references;
  std::vector<ForceSpec> forces;
  double duration_s = 1;
  double log_rate_hz = 1000;
  bool sensor_noise = false;
  uint64_t seed = 1;
  double force_noise_N = 0;
  Cooling cooling = Cooling::On;
  IntegrationSetup integration;
  std::optional<OscSetup> osc;                 // an operational space controller on the bus (fixed base)
  std::optional<BalanceSetup> balance;         // the balancing controller on the bus (floating base)
  std::optional<EndOnFall> end_on_fall;        // end the run once the robot is down (floating base)
};

struct ExperimentSetup {
  std::string type;                            // "", sysid_rfsea, force_tracking, step_response, thermal, standing, osc_table, balance
  std::string joint = "l_knee";
  std::map<std::string, std::string> text;     // further string fields (signal names ...)
  std::map<std::string, double> number;        // further numeric fields (windows ...)
};

struct Scenario {
  std::string name, description, file;
  std::vector<VariantSetup> variants;
  FrameSetup frames;
  std::vector<PlotSetup> plots;
  ExperimentSetup experiment;
};

// Reads and checks a scenario. Throws InputError "FILE:LINE:COL: what was expected".
Scenario load_scenario(const std::string& path);

// One run of one variant.
// A controller run in fixed point: its predicted error bound on each output over the
// run (codegen::predicted_error_bound, horizon = the run's steps up to 200000; the
// bound holds while no saturation engages) against each output's range.
struct FixedPointFacts {
  std::string controller, output, unit;
  int word_bits = 0;
  double bound = 0;                            // +inf: none (an integrator in the loop)
  double range = 0;                            // the output's largest magnitude (its declared range)
};

// A controller of the run as its generated code (implementation: generated).
struct SilController {
  std::string controller;                      // its name in the scenario
  std::string scalar;                          // double, float, fixed16 or fixed32
  std::string object;                          // 16 hex digits naming the compiled text (identical
                                               // controllers share one object)
  double compile_s = 0;                        // wall time of its compilation (once per object and process)
  std::optional<unsigned long long> saturations;  // fixed point: words the generated code saturated
};

// The run's generated controllers and what compiled them.
struct SilFacts {
  std::string compiler;                        // the command: $CXX, or c++
  std::string version;                         // the first line of its --version
  std::string flags;                           // what it compiled with
  std::vector<SilController> controllers;      // in list order
};

struct VariantResult {
  std::string name;
  std::vector<std::pair<std::string, std::string>> axes;
  Log log;
  double wall_s = 0;                           // wall-clock time of the run
  double real_time_factor = 0;                 // simulated / wall time
  long long integrator_steps = 0;
  std::vector<long long> controller_steps;
  // Saturation blocks engaged, per controller; none for a controller that does not count
  // them (Controller::counts_clamp_events: the generated code).
  std::vector<std::optional<unsigned long long>> clamp_events;
  std::optional<SilFacts> sil;                 // when a controller ran as its generated code
  std::map<std::string, double> truth;         // the simulator's true values the experiment may need
  std::vector<FixedPointFacts> fixed_point;    // per fixed-point controller output
  std::vector<std::string> warnings;           // one line each (a fixed-point bound beyond its range)
  // Wall-time figures of controllers that time themselves (osc_tick_us_median,
  // osc_tick_us_max: one evaluation of the operational space controller), µs.
  std::map<std::string, double> timing_us;
};

struct RunOptions {
  std::optional<double> duration_s;            // overrides every variant's duration
  std::function<void(double)> on_progress;
};

// The robot a variant simulates (its URDF with the welded joints, payloads and test
// inertias applied) and the plant's options (base, actuators, contact, integration).
// Throws InputError naming where in the scenario a joint, link or load is wrong.
struct VariantPlant {
  model::RobotDescription robot;
  model::PlantOptions options;
};
VariantPlant variant_plant(const Scenario& s, const VariantSetup& v);
// A joint's angle at t = 0: robot.initial, else robot.lock, else 0.
double initial_angle(const RobotSetup& r, const std::string& joint);

// Builds the plant and the controllers of a variant and runs it.
VariantResult run_variant(const Scenario& s, const VariantSetup& v, const RunOptions& options);

}  // namespace dmbd::sim
