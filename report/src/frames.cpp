// The frame variant drawn from its log: the joints' logged angles through the robot's
// forward kinematics, the logged base pose for a floating robot, the logged contact
// forces as arrows, the centre of mass from the description's masses.
#include "frames.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>

#include <fmt/format.h>

#include "dmbd/base/error.hpp"
#include "dmbd/base/file.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/report/robot_scene.hpp"
#include "dmbd/viz/plot.hpp"
#include "dmbd/viz/renderer.hpp"
#include "dmbd/viz/video.hpp"

namespace dmbd::report::detail {

namespace fs = std::filesystem;

namespace {

// Where a variant's log holds what a frame needs.
struct PoseColumns {
  std::vector<int> joint;  // per robot.joints: the column of "<name>.q", or -1 (no coordinate)
  int base = -1;           // floating: "base.x", then y, z, roll, pitch, yaw
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();  // fixed base
  struct Sphere {
    int link;
    Eigen::Vector3d center_L;
    double radius;
    int force;  // "contact.K.fx" (then fy, fz), or -1
  };
  std::vector<Sphere> spheres;
};

bool one_dof(model::JointType t) {
  return t == model::JointType::Revolute || t == model::JointType::Continuous || t == model::JointType::Prismatic;
}

PoseColumns pose_columns(const model::RobotDescription& robot, const sim::VariantResult& r, const sim::VariantSetup& v,
                         const std::string& file) {
  PoseColumns c;
  for (const auto& j : robot.joints) {
    c.joint.push_back(one_dof(j.type) ? r.log.find(j.name + ".q") : -1);
    if (one_dof(j.type) && c.joint.back() < 0)
      throw InputError(file + ": variant '" + r.name + "' logged no '" + j.name + ".q': its frames cannot be drawn");
  }
  c.X_WB = v.robot.X_WB;
  if (v.robot.base == model::BaseMode::Floating) {
    c.base = r.log.find("base.x");
    if (c.base < 0) throw InputError(file + ": variant '" + r.name + "' logged no 'base.x': its frames cannot be drawn");
  }
  int k = 0;
  for (std::size_t l = 0; l < robot.links.size(); ++l)
    for (const auto& sh : robot.links[l].collisions)
      if (sh.geometry.kind == model::Geometry::Kind::Sphere)
        c.spheres.push_back({static_cast<int>(l), Eigen::Vector3d(sh.X_LG.translation()), sh.geometry.radius_m,
                             r.log.find(fmt::format("contact.{}.fx", k++))});
  return c;
}

double at(const sim::Log& log, int column, std::size_t row) { return log.column(column)[row]; }

// R = Rz(yaw) Ry(pitch) Rx(roll), as the simulation logs it.
Eigen::Isometry3d base_pose(const sim::Log& log, const PoseColumns& c, std::size_t row) {
  if (c.base < 0) return c.X_WB;
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() << at(log, c.base, row), at(log, c.base + 1, row), at(log, c.base + 2, row);
  X.linear() = (Eigen::AngleAxisd(at(log, c.base + 5, row), Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(at(log, c.base + 4, row), Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(at(log, c.base + 3, row), Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return X;
}

std::vector<Eigen::Isometry3d> link_poses(const model::RobotDescription& robot, const sim::Log& log, const PoseColumns& c,
                                          std::size_t row) {
  std::vector<double> q(robot.joints.size(), 0.0);
  for (std::size_t j = 0; j < q.size(); ++j)
    if (c.joint[j] >= 0) q[j] = at(log, c.joint[j], row);
  return model::link_frames(robot, q, base_pose(log, c, row));
}

viz::Overlays overlays(const model::RobotDescription& robot, const sim::Log& log, const PoseColumns& c, std::size_t row,
                       const std::vector<Eigen::Isometry3d>& X, const std::string& title) {
  viz::Overlays o;
  o.text_lines = {title, fmt::format("t = {:.3f} s", log.time()[row])};
  o.com_W = model::center_of_mass(robot, X);
  for (const auto& s : c.spheres) {
    if (s.force < 0) continue;
    const Eigen::Vector3d f(at(log, s.force, row), at(log, s.force + 1, row), at(log, s.force + 2, row));
    const Eigen::Vector3d p = X[static_cast<std::size_t>(s.link)] * s.center_L - s.radius * Eigen::Vector3d::UnitZ();
    if (f.allFinite() && f.norm() > 1e-3) o.forces.push_back({p, f, viz::Color{230, 50, 40}});
  }
  return o;
}

// A three-quarter view from the front left that frames the robot's bounds, unless the
// scenario or the options give the camera.
viz::Camera make_camera(const sim::FrameSetup& f, const ReportOptions& o, const viz::Scene& scene,
                        const std::vector<Eigen::Isometry3d>& X, int w, int h) {
  viz::Camera cam;
  cam.width_px = w;
  cam.height_px = h;
  const auto pos = o.camera_position ? o.camera_position : f.camera_position;
  const auto look = o.camera_look_at ? o.camera_look_at : f.camera_look_at;
  if (pos && look) {
    cam.position = *pos;
    cam.look_at = *look;
    return cam;
  }
  const Eigen::AlignedBox3d b = viz::scene_bounds(scene, X);
  const double size = std::max(b.diagonal().norm(), 0.6);
  cam.look_at = b.center();
  cam.position = b.center() + 1.5 * size * Eigen::Vector3d(0.62, -0.70, 0.35).normalized();
  return cam;
}

// Every n-th row: about fps frames a simulated second, played in real time at
// 1 / (n dt) frames per second; when that gives more than max_frames, fewer frames
// played at fps (a time-lapse).
struct Step {
  std::size_t n = 1;
  double video_fps = 30, speedup = 1;
};
Step row_step(const sim::Log& log, const sim::FrameSetup& f) {
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

}  // namespace

Frames write_frames(const sim::ScenarioRun& run, const std::string& dir, const ReportOptions& options) {
  const sim::Scenario& s = run.scenario;
  Frames out;
  out.variant = s.frames.variant.empty() ? run.runs.front().name : s.frames.variant;
  const auto r = std::find_if(run.runs.begin(), run.runs.end(), [&](const auto& x) { return x.name == out.variant; });
  const auto v = std::find_if(s.variants.begin(), s.variants.end(), [&](const auto& x) { return x.name == out.variant; });
  if (r == run.runs.end() || v == s.variants.end() || r->log.rows() == 0) return out;
  const model::RobotDescription robot = sim::variant_plant(s, *v).robot;
  for (const auto& m : robot.meshes_missing)
    out.warnings.push_back(fmt::format("{}: mesh '{}' could not be read: the frames draw the robot without it", robot.source, m));
  const PoseColumns cols = pose_columns(robot, *r, *v, s.file);
  const int w = options.width_px.value_or(s.frames.width_px), h = options.height_px.value_or(s.frames.height_px);
  const viz::Scene scene = scene_from_robot(robot);
  viz::Renderer renderer(w, h);
  renderer.set_scene(scene);
  const Step step = row_step(r->log, s.frames);
  const std::size_t n = step.n;
  out.video_fps = step.video_fps;
  out.speedup = step.speedup;
  fs::create_directories(fs::path(dir) / "frames");
  viz::VideoWriter video((fs::path(dir) / "video.mp4").string(), out.video_fps);
  std::optional<viz::Camera> cam;
  for (std::size_t row = 0; row < r->log.rows(); row += n) {
    const auto X = link_poses(robot, r->log, cols, row);
    if (!cam) cam = make_camera(s.frames, options, scene, X, w, h);
    const auto t0 = std::chrono::steady_clock::now();
    const cv::Mat& img = renderer.render(X, *cam, overlays(robot, r->log, cols, row, X, s.name + "  |  " + out.variant));
    out.render_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const std::string name = fmt::format("frames/frame_{:05d}.png", out.frames.size());
    write_file_atomic((fs::path(dir) / name).string(), viz::encode_png(img));
    video.write(img);
    out.frames.push_back({name, r->log.time()[row]});
  }
  video.finish();
  return out;
}

}  // namespace dmbd::report::detail
