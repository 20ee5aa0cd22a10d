#pragma once
// The paper's experiments as analyses of a scenario's variant logs: each turns the logs
// into the metrics of metrics.json and the figures of plots/ (docs/scenario-format.md,
// "experiment"). Types:
//   step_response   overshoot, rise time, steady-state error of a step window and RMS
//                   tracking error of a sinusoid window, per variant (paper Fig. 5b,c)
//   force_tracking  RMS force error per variant, nested by the matrix axes
//   thermal         peak winding temperature with cooling on and off
//   sysid_rfsea     RFSEA parameters identified from current chirps, locked and free
//                   output (paper Fig. 5a), against the simulator's values
//   standing        a floating robot standing (and pushed): fell, largest tilt, largest
//                   torso drop, tilt at the end
//   osc_table       operational space control of the table-mounted robot (paper Fig. 6):
//                   the point's RMS and largest error, each joint's torque error, current
//                   saturation and the controller's evaluation time, per variant
//   balance         unsupported balancing by stepping (paper Fig. 7): fell, time balanced,
//                   steps, landing error, lateral CoM velocity reversals, knee winding
//                   peaks, QP failures, the controller's tick time, pushes survived
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "dmbd/sim/scenario.hpp"
#include "dmbd/base/figure.hpp"

namespace dmbd::sim {

// What an experiment makes of the runs (run_scenario writes it; report/ draws it).
struct ExperimentResult {
  // The experiment's part of metrics.json, by type (docs/scenario-format.md, "experiment";
  // empty without an experiment); may hold inf or NaN (finite_json writes them).
  nlohmann::json metrics = nlohmann::json::object();
  // File name in plots/ -> the figure as data (report/ draws it; sim draws nothing).
  std::vector<std::pair<std::string, plot::Figure>> figures;
  std::vector<std::string> notes;                            // one line each, for the report
  // Outcomes the user should not miss (a run shorter than the experiment's windows):
  // one line each, printed by dmbd simulate and listed in the report.
  std::vector<std::string> warnings;
};

// Step metrics of y following a step of r at t_step, over the window [t_step, t_end)
// (half-open: a reference stepping back at t_end is not in it). y0 and r1 are y and r
// at t_step (the first sample at or after it); overshoot = max(0, peak of
// (y - y0)/(r1 - y0) - 1) in %, rise time from 10 % to 90 % (first samples at or past
// them; infinite if not reached), steady-state error = |mean(y - r)| over the window's
// last 20 %. All three are 0 when r1 == y0 (no step to measure).
struct StepMetrics {
  // Overshoot in % of the step r1 - y0 (0 when y never passes r1).
  double overshoot_pct = 0,
      rise_time_s = 0,         // 10 % to 90 %, s; +inf when either is not reached in the window
      steady_state_error = 0;  // |mean(y - r)|, y's unit; NaN when no sample is in the last 20 %
};
// The StepMetrics above of y (and r) sampled at t (ascending, s), all three the same length.
StepMetrics step_metrics(const std::vector<double>& t, const std::vector<double>& r, const std::vector<double>& y, double t_step,
                         double t_end);
// RMS of y - r over samples with t in [t0, t1] (closed; y's unit); NaN when there is none.
double rms_error(const std::vector<double>& t, const std::vector<double>& r, const std::vector<double>& y, double t0, double t1);

// The scenario's experiment (if any) and its `plots:`, from the runs' logs (and truth,
// timing_us). Throws InputError naming the scenario file: a signal that is not in a
// run's log, a plot's variant that does not exist, or runs that do not fit the type
// (thermal without `cooling: both`, sysid_rfsea without a locked and a free run or on
// a joint without an actuator).
ExperimentResult evaluate_experiment(const Scenario& s, const std::vector<VariantResult>& runs);

}  // namespace dmbd::sim
