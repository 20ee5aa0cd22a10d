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

struct ExperimentResult {
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
// at t_step; overshoot = max(0, peak of (y - y0)/(r1 - y0) - 1) in %, rise time from
// 10 % to 90 % (first samples at or past them; infinite if not reached), steady-state
// error = |mean(y - r)| over the window's last 20 %.
struct StepMetrics {
  double overshoot_pct = 0, rise_time_s = 0, steady_state_error = 0;
};
StepMetrics step_metrics(const std::vector<double>& t, const std::vector<double>& r, const std::vector<double>& y, double t_step,
                         double t_end);
// RMS of y - r over samples with t in [t0, t1].
double rms_error(const std::vector<double>& t, const std::vector<double>& r, const std::vector<double>& y, double t0, double t1);

// The scenario's experiment (if any) and its `plots:`. Throws InputError naming a
// signal that is not in the log.
ExperimentResult evaluate_experiment(const Scenario& s, const std::vector<VariantResult>& runs);

}  // namespace dmbd::sim
