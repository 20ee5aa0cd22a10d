#pragma once
// Experiments: what a scenario's `experiment` names (docs/scenario-format.md,
// "experiment"). An experiment is an entry of one registry (registry.hpp): which keys it
// reads, what it records of the plant before a variant runs, how it turns the variants'
// logs into the metrics of metrics.json and the figures of plots/ (as data: report/
// draws them), and the overlays it asks the frames to draw. Built in (the paper's):
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
//   push_map        a matrix of pushed balancing runs against the pendulum's capture
//                   verdict: the certified set's survival, the largest force survived
//                   per direction, the analytic boundary F_max(phase) (issue 27)
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "dmbd/base/figure.hpp"
#include "dmbd/control/bus_controller.hpp"
#include "dmbd/model/plant.hpp"
#include "dmbd/sim/overlay.hpp"
#include "dmbd/sim/run_result.hpp"
#include "dmbd/sim/simulation.hpp"

namespace dmbd::experiments {

// The scenario's `experiment` map: its type and keys (docs/scenario-format.md).
struct ExperimentSetup {
  std::string type;                            // `type`: a registered experiment ("" without one)
  // `joint`: the joint the analysis looks at ("" when not given).
  std::string joint;
  // `figure_labels`: figure name (its file name without .png; a per-variant figure by
  // the name before "_VARIANT") -> a label appended to its title in brackets, e.g.
  // osc_ankle: "paper Fig. 6c". A figure without one has none.
  std::map<std::string, std::string> figure_labels;
  std::map<std::string, std::string> text;     // further string fields (signal names ...)
  std::map<std::string, double> number;        // further numeric fields (windows ...)
  std::map<std::string, std::vector<std::string>> names;  // further lists of names (joints ...)
  std::map<std::string, std::vector<double>> numbers;     // further lists of numbers (a sweep's values ...)
  std::string file;                            // the scenario file (messages name it)
  // Where each key was written ("file:line:col"), by key ("type", "joint", ...).
  std::map<std::string, std::string> where;
};

// The kind of a key an experiment reads besides type, joint and figure_labels: text, a
// number, the name of one of the robot's joints or links, a list of joint names (names
// are checked against the robot before anything runs), or a non-empty list of numbers.
enum class KeyKind { Text, Number, Joint, Link, Joints, Numbers };

// What an experiment knows of one variant besides its run: the parts of its set-up an
// analysis may need (the scenario module fills it from the variant).
struct VariantFacts {
  std::string name;                                        // the variant's
  double duration_s = 0;                                   // its duration, s (as set in the scenario)
  std::vector<sim::ForceSpec> forces;                      // the forces applied to the robot
  sim::Cooling cooling = sim::Cooling::On;                 // which thermal models were logged
  // The bus controllers' options, in list order (each a type's own struct).
  std::vector<std::shared_ptr<const control::BusControllerOptions>> bus_controllers;
  double gravity_m_s2 = 9.81;                              // the scenario's robot.gravity
  // The options of the first bus controller whose options are a T, or null.
  template <class T>
  const T* bus_controller() const {
    for (const auto& o : bus_controllers)
      if (const auto* t = dynamic_cast<const T*>(o.get())) return t;
    return nullptr;
  }
};

// What an experiment makes of the runs (the scenario's run writes it; report/ draws it).
struct ExperimentResult {
  // The experiment's part of metrics.json, by type (docs/scenario-format.md, "experiment";
  // empty without an experiment); may hold inf or NaN (finite_json writes them).
  nlohmann::json metrics = nlohmann::json::object();
  // File name in plots/ -> the figure as data (report/ draws it; the experiment draws nothing).
  std::vector<std::pair<std::string, plot::Figure>> figures;
  std::vector<std::string> notes;                            // one line each, for the report
  // Outcomes the user should not miss (a run shorter than the experiment's windows):
  // one line each, printed by dmbd simulate and listed in the report.
  std::vector<std::string> warnings;
};

// What an experiment may read of a variant's plant before it runs (Experiment::record).
struct RecordContext {
  const model::Plant& plant;                                   // built, in its initial state
  const model::RobotDescription& robot;                        // as simulated (welds, payloads applied)
  std::vector<std::pair<std::string, double>> initial_angles;  // each moving joint's angle at t = 0, rad
};

// An experiment type: one entry of the registry (registry.hpp).
class Experiment {
 public:
  virtual ~Experiment() = default;
  // The keys it reads besides type, joint and figure_labels, and their kinds.
  virtual std::map<std::string, KeyKind> keys() const = 0;
  // Whether `joint` must be given.
  virtual bool needs_joint() const { return false; }
  // The simulator's true values its evaluation needs, into truth (metrics.json
  // runs.RUN.truth), before the variant runs. None by default.
  virtual void record(const ExperimentSetup& setup, const RecordContext& context, std::map<std::string, double>& truth) const;
  // Overlays the frames draw for it (none by default).
  virtual std::vector<sim::Overlay> overlays(const ExperimentSetup& setup) const;
  // The metrics and figures of the runs (their logs and run facts), in the scenario's
  // variant order; variants[k] is the set-up of runs[k]. Throws InputError naming
  // setup.file: a signal that is not in a run's log, or runs that do not fit the
  // experiment.
  virtual ExperimentResult evaluate(const ExperimentSetup& setup, const std::vector<sim::VariantResult>& runs,
                                    const std::vector<VariantFacts>& variants) const = 0;
};

// A figure's title with the scenario's label for it: "TITLE (LABEL)", or TITLE alone.
std::string labelled(const ExperimentSetup& setup, const std::string& figure, const std::string& title);

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

}  // namespace dmbd::experiments
