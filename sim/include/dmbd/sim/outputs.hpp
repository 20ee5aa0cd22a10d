#pragma once
// Everything `dmbd simulate SCENARIO --out DIR` writes: log.csv, metrics.json,
// plots/*.png, frames/frame_NNNNN.png, video.mp4 and report.html (one self-contained
// page linking only to files in DIR). Every file is written to a temporary name and
// renamed, so an interrupted run leaves no half-written file.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "dmbd/sim/experiments.hpp"
#include "dmbd/sim/scenario.hpp"

namespace dmbd::sim {

struct ScenarioRunOptions {
  bool frames = true;                          // render frames, the video and the strip
  std::optional<double> duration_s;            // overrides the scenario's durations
  // Progress of the whole scenario (0..1) and the variant running.
  std::function<void(double, const std::string&)> on_progress;
};

struct ScenarioRunResult {
  std::vector<VariantResult> runs;
  ExperimentResult experiment;
  std::vector<std::string> files;              // written, relative to DIR
  std::string report;                          // DIR/report.html
  double render_fps = 0;                       // frames rendered per wall-clock second (0: none)
  int frames = 0;
};

// Runs every variant and writes the outputs into out_dir (created if missing).
ScenarioRunResult run_scenario(const Scenario& s, const std::string& out_dir, const ScenarioRunOptions& options = {});

// The log of several variants as one table: columns "variant/signal", one row per
// instant any run logged (variants may log at different rates or for different
// durations); a run's cells are empty at an instant it did not log. A single variant
// keeps plain names.
std::string combined_csv(const std::vector<VariantResult>& runs);

}  // namespace dmbd::sim
