#pragma once
// Internal to report/: which rows of a log the frames draw and the camera they draw them
// from. The 3-D replay (replay.cpp) starts its view at the same camera.
#include <cstddef>

#include "dmbd/report/report.hpp"
#include "dmbd/viz/renderer.hpp"
#include "log_poses.hpp"

namespace dmbd::report::detail {

// Every n-th row: about fps frames a simulated second, played in real time at
// 1 / (n dt) frames per second; when that gives more than max_frames, fewer frames
// played at fps (a time-lapse).
struct Step {
  std::size_t n = 1;
  double video_fps = 30, speedup = 1;
};
Step row_step(const sim::Log& log, const scenario::FrameSetup& f);

// The camera of the scenario or the options (the options' size and pose first), else a
// three-quarter view from the front left that frames the robot's bounds over every n-th
// row of the log (a robot that rises or walks stays in view).
viz::Camera frame_camera(const scenario::FrameSetup& f, const ReportOptions& o, const model::RobotDescription& robot,
                         const sim::Log& log, const PoseColumns& c, std::size_t n, const viz::Scene& scene);

}  // namespace dmbd::report::detail
