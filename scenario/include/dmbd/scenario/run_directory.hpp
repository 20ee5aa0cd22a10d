#pragma once
// A run directory: what a scenario's simulation leaves for everything after it (report/,
// `dmbd report`, scripts): log.csv, every signal of every variant with its unit
// (combined_csv below), and metrics.json, the experiment's metrics plus, per run, its
// wall time, real-time factor, step counts and the simulator's true values, and the
// scenario file it came from. sim writes it and reads it back; it draws nothing
// (docs/architecture.md). Files are written atomically (dmbd/base/file.hpp).
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dmbd/experiments/experiment.hpp"
#include "dmbd/scenario/scenario.hpp"

namespace dmbd::scenario {

// How run_scenario runs a scenario (dmbd simulate's options).
struct ScenarioRunOptions {
  std::optional<double> duration_s;            // overrides the scenario's durations (s; --duration)
  // Progress of the whole scenario (0..1, by simulated time over every variant's
  // duration) and the name of the variant running; called about every 1 % of a run.
  std::function<void(double, const std::string&)> on_progress;
};

// A run directory's content in memory: what run_scenario wrote, or read_run read back.
struct ScenarioRun {
  Scenario scenario;                           // as given, or (read_run) reloaded from its file
  std::vector<sim::VariantResult> runs;             // per variant, in order (read_run: those metrics.json lists)
  experiments::ExperimentResult experiment;                 // metrics and figures (as data)
  nlohmann::json metrics;                      // as in metrics.json
  std::vector<std::string> files;              // written (read), relative to the directory: log.csv, metrics.json
};

// Runs every variant and writes DIR/log.csv and DIR/metrics.json (DIR created if
// missing). Throws InputError: scenario mistakes found while building a variant and
// divergences name the scenario file and the variant; a folder or file that cannot be
// written is an OutputError. Generated controllers are compiled first (one that does not
// compile stops it before any run); nothing is written until every variant has run, and
// an experiment's error comes after log.csv is written.
ScenarioRun run_scenario(const Scenario& s, const std::string& dir, const ScenarioRunOptions& options = {});

// One variant of s run as run_scenario runs it: progress reported into the whole
// scenario's (`done` of `total` simulated seconds before it), a mistake or a divergence
// prefixed with the scenario file and the variant. Generated controllers not yet built
// are compiled by the run itself.
sim::VariantResult run_scenario_variant(const Scenario& s, const VariantSetup& v, const ScenarioRunOptions& options,
                                   double done = 0, double total = 1);

// The back half of run_scenario: the runs of s (in the scenario's variant order) written
// as DIR/log.csv, then the experiment evaluated on them and DIR/metrics.json. dmbd
// simulate --jobs and dmbd sweep collect write their merged runs through it, so their
// files are run_scenario's. Throws OutputError for a folder or file that cannot be
// written, InputError for the experiment's errors (after log.csv).
ScenarioRun write_run(const Scenario& s, std::vector<sim::VariantResult> runs, const std::string& dir);

// A run directory read back: the scenario reloaded from the file metrics.json names,
// each variant's log split out of log.csv, its run figures from metrics.json, and the
// experiment evaluated again on those logs. The logs hold every value to 17
// significant digits, so the metrics and figures are the run's own. Throws InputError
// naming the file that is missing or malformed.
ScenarioRun read_run(const std::string& dir);

// A run directory about to be written again (write_run, report::write_report): its
// report.html removed first, so that an interrupted or failed run never leaves a page
// that links the frames or video of the run before, and the temporary files a killed run
// left (*.tmp, video.tmp.mp4; base/temporaries.hpp) swept, in it and in plots/. A folder
// where the page goes is left for the page's writer to report. OutputError when the page
// cannot be removed.
void forget_earlier_report(const std::string& dir);

// The log of several variants as one table: columns "variant/signal", one row per
// instant any run logged (variants may log at different rates or for different
// durations); a run's cells are empty at an instant it did not log. A single variant
// keeps plain names.
std::string combined_csv(const std::vector<sim::VariantResult>& runs);
// The inverse: the logs of the named variants from combined_csv's text (file names it in
// messages). InputError "FILE:LINE: ..." for a column of no listed variant, a row with
// another number of cells than the header, or a cell that is not a number.
std::vector<sim::Log> split_csv(const std::string& csv, const std::vector<std::string>& variants, const std::string& file);

// JSON cannot hold inf or NaN: they become the strings "inf", "-inf", "NaN".
nlohmann::json finite_json(const nlohmann::json& j);

}  // namespace dmbd::scenario
