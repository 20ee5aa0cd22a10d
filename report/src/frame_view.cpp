// The frames' rows and camera (moved here from frames.cpp: the replay starts at that camera).
#include "frame_view.hpp"

#include <algorithm>
#include <cmath>

namespace dmbd::report::detail {

namespace {

// The scene's bounds over every n-th row; a robot with nothing to draw (no mesh loaded, no
// collision shape) is framed by its links' origins instead.
Eigen::AlignedBox3d robot_bounds(const model::RobotDescription& robot, const sim::Log& log, const PoseColumns& c, std::size_t n,
                                 const viz::Scene& scene) {
  Eigen::AlignedBox3d b, origins;
  for (std::size_t row = 0; row < log.rows(); row += n) {
    const std::vector<Eigen::Isometry3d> X = link_poses(robot, log, c, row);
    b.extend(viz::scene_bounds(scene, X));
    for (const auto& x : X) origins.extend(x.translation());
  }
  return b.isEmpty() ? origins : b;
}

}  // namespace

viz::Camera frame_camera(const scenario::FrameSetup& f, const ReportOptions& o, const model::RobotDescription& robot,
                         const sim::Log& log, const PoseColumns& c, std::size_t n, const viz::Scene& scene) {
  viz::Camera cam;
  cam.width_px = o.width_px.value_or(f.width_px);
  cam.height_px = o.height_px.value_or(f.height_px);
  const auto pos = o.camera_position ? o.camera_position : f.camera_position;
  const auto look = o.camera_look_at ? o.camera_look_at : f.camera_look_at;
  if (pos && look) {
    cam.position = *pos;
    cam.look_at = *look;
    return cam;
  }
  const Eigen::AlignedBox3d b = robot_bounds(robot, log, c, n, scene);
  const double size = std::max(b.diagonal().norm(), 0.6);
  cam.look_at = b.center();
  cam.position = b.center() + 1.5 * size * Eigen::Vector3d(0.62, -0.70, 0.35).normalized();
  return cam;
}

Step row_step(const sim::Log& log, const scenario::FrameSetup& f) {
  Step st;
  const std::size_t rows = log.rows();
  if (rows < 2) return st;
  const double dt = (log.time().back() - log.time().front()) / static_cast<double>(rows - 1);
  st.n = std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(1.0 / (f.fps * dt))));
  st.video_fps = 1.0 / (static_cast<double>(st.n) * dt);
  const auto cap = static_cast<std::size_t>(std::max(1, f.max_frames));
  if ((rows - 1) / st.n + 1 > cap) {
    st.n = (rows - 1 + cap - 1) / cap;
    st.video_fps = f.fps;
    st.speedup = static_cast<double>(st.n) * dt * f.fps;
  }
  return st;
}

}  // namespace dmbd::report::detail
