#pragma once
// Internal to report/: the frame variant drawn from its log into frames/ and video.mp4.
#include <string>
#include <vector>

#include "dmbd/report/report.hpp"
#include "dmbd/viz/report.hpp"

namespace dmbd::report::detail {

struct Frames {
  std::string variant;
  std::vector<viz::ReportFrame> frames;  // relative paths and times
  double video_fps = 0;                  // as written into video.mp4
  double speedup = 1;                    // simulated seconds per second of video
  double render_s = 0;                   // wall time spent rendering
  std::vector<std::string> warnings;     // meshes the robot is drawn without; links drawn from collisions
};

// Frames at every n-th logged row, n chosen so the video plays in real time at about
// the scenario's fps (a time-lapse of at most max_frames frames for long runs).
Frames write_frames(const scenario::ScenarioRun& run, const std::string& dir, const ReportOptions& options);

}  // namespace dmbd::report::detail
