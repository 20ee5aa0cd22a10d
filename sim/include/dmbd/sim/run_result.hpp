#pragma once
// What one run of a simulation leaves: its log and the facts metrics.json keeps of it
// (metrics.json runs.RUN): wall time, step counts, controller saturations, the
// generated controllers that ran, the simulator's true values an experiment needs, and
// the fixed-point error bounds of controllers run in fixed point.
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dmbd/sim/log.hpp"

namespace dmbd::sim {

// A controller run in fixed point: its predicted error bound on each output over the
// run (codegen::predicted_error_bound, horizon = the run's steps up to 200000; the
// bound holds while no saturation engages) against each output's range.
struct FixedPointFacts {
  std::string controller,  // the controller's name in the scenario
      output,              // the diagram output's name
      unit;                // the output's unit
  int word_bits = 0;                           // 16 or 32
  double bound = 0;                            // +inf: none (an integrator in the loop)
  double range = 0;                            // the output's largest magnitude (its declared range; NaN: none)
};

// A controller of the run as its generated code (implementation: generated).
struct SilController {
  std::string controller;                      // its name in the scenario
  std::string scalar;                          // double, float, fixed16 or fixed32
  std::string object;                          // 16 hex digits naming the compiled text (shared by identical ones)
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

// A joint that ran faster than its URDF velocity limit (<limit velocity>) during a run.
struct VelocityExcess {
  double limit = 0;        // the URDF's limit, rad/s (m/s for a prismatic joint)
  double peak = 0;         // the largest |rate| seen, rad/s (m/s)
  long long samples = 0;   // plant advances that ended above the limit
};

// One run of one variant: its log and the facts metrics.json keeps of it (runs.RUN).
struct VariantResult {
  std::string name;                            // the variant's (VariantSetup::name)
  std::vector<std::pair<std::string, std::string>> axes;  // its matrix axis -> value name (none: empty)
  Log log;                                     // every bus and logged-only signal at the log rate (simulation.hpp)
  double wall_s = 0;                           // wall-clock time of the run
  double real_time_factor = 0;                 // simulated / wall time
  long long integrator_steps = 0;              // the plant integrator's steps over the run
  // Steps per controller: the scenario's in list order, then osc, then balance.
  std::vector<long long> controller_steps;
  // Saturation blocks engaged, per controller; none for a controller that does not count
  // them (Controller::counts_clamp_events: the generated code).
  std::vector<std::optional<unsigned long long>> clamp_events;
  std::optional<SilFacts> sil;                 // when a controller ran as its generated code
  std::map<std::string, double> truth;         // the simulator's true values the experiment may need
  std::vector<FixedPointFacts> fixed_point;    // per fixed-point controller output
  std::vector<std::string> warnings;           // one line each (a fixed-point bound beyond its range)
  // Wall-time figures of controllers that time themselves (osc_tick_us_median,
  // osc_tick_us_max: one evaluation of the operational space controller; wbc_tick_us_*
  // the same of the balancing controller), µs.
  std::map<std::string, double> timing_us;
  // Per joint (only those with any): ideal torques clamped to the URDF effort limit
  // (model::Plant::effort_clamp_events).
  std::map<std::string, long long> effort_clamp_events;
  // Per joint (only those that did): the URDF velocity limit exceeded.
  std::map<std::string, VelocityExcess> velocity_limit_exceeded;
};

}  // namespace dmbd::sim
