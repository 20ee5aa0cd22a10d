#pragma once
// A run's report (docs/architecture.md: sim produces run directories, report/ draws
// them, viz is the drawing): plots/*.png (the experiment's figures and the scenario's
// plots), frames/frame_NNNNN.png and video.mp4 (the frame variant drawn from its logged
// joint angles, base pose and contact forces), replay/ (a 3-D replay of the variants in
// the page: three.js, the robots' meshes, the links' poses; written with or without
// frames) and report.html, one self-contained page linking only to files in the
// directory. Made from a scenario::ScenarioRun: straight after
// the simulation (`dmbd simulate`) or from its run directory (scenario::read_run,
// `dmbd report DIR`), with the same files pixel for pixel. Every file is written
// atomically; frames of an earlier report are removed first.
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "dmbd/scenario/run_directory.hpp"

namespace dmbd::report {

struct ReportOptions {
  bool frames = true;                                    // frames/ and video.mp4
  std::optional<int> width_px, height_px;                // instead of the scenario's frames size
  std::optional<Eigen::Vector3d> camera_position, camera_look_at;  // instead of the scenario's camera
};

struct ReportResult {
  std::vector<std::string> files;  // written, relative to the directory
  std::string page;                // DIR/report.html
  int frames = 0;
  double render_fps = 0;           // frames rendered per wall-clock second (0: none)
  int replay_variants = 0;         // variants in the 3-D replay (replay/; 0: none)
  double replay_s = 0;             // wall time spent writing replay/
  // The experiment's warnings and the report's own (a mesh the robot is drawn without;
  // the links drawn from their collision shapes, one line), one line each; also on the page.
  std::vector<std::string> warnings;
};

// Throws InputError for a scenario the frames cannot be drawn from (a joint of the
// robot missing from the log, or contact forces logged for another number of shapes
// than the robot's colliding ones) and OutputError for a file that cannot be written.
ReportResult write_report(const scenario::ScenarioRun& run, const std::string& dir, const ReportOptions& options = {});

}  // namespace dmbd::report
