// The frame variant drawn from its log: the joints' logged angles through the robot's
// forward kinematics, the logged base pose for a floating robot, the logged contact
// forces as arrows (every colliding shape's, where contact_sites.hpp puts them), the
// centre of mass from the description's masses, the paths the variant's bus
// controllers and experiment declare (when logged), and a table under a fixed base.
// Links whose visual meshes are missing are drawn from their collision shapes
// (robot_scene.hpp), named in one warning.
#include "frames.hpp"

#include "contact_sites.hpp"
#include "frame_view.hpp"
#include "log_poses.hpp"
#include "table.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <exception>
#include <filesystem>
#include <mutex>
#include <optional>
#include <thread>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "dmbd/base/error.hpp"
#include "dmbd/base/file.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/report/robot_scene.hpp"
#include "dmbd/scenario/evaluate.hpp"
#include "dmbd/viz/plot.hpp"
#include "dmbd/viz/renderer.hpp"
#include "dmbd/viz/video.hpp"

namespace dmbd::report::detail {

namespace fs = std::filesystem;

namespace {

// A Text overlay's line: "LABEL: NAME" for a value with a name, else "LABEL: VALUE".
std::string text_of(const sim::Overlay& o, double v) {
  const double k = std::round(v);
  if (std::isfinite(v) && k >= 0 && k < static_cast<double>(o.value_names.size()) && std::abs(v - k) < 1e-9)
    return o.label + ": " + o.value_names[static_cast<std::size_t>(k)];
  return fmt::format("{}: {:.4g}", o.label, v);
}

// Each declared path over the last window_s of the run up to the frame's sample (that
// sample included), in the order declared (a later one is drawn over an earlier one).
// Samples that are not finite (none logged yet) break the line.
void add_paths(const sim::Log& log, const PoseColumns& c, std::size_t row, viz::Overlays& o) {
  const std::vector<double>& t = log.time();
  for (const auto& p : c.paths) {
    const auto first = static_cast<std::size_t>(
        std::lower_bound(t.begin(), t.begin() + static_cast<std::ptrdiff_t>(row), t[row] - p.overlay.window_s) - t.begin());
    viz::PathOverlay path;
    path.color = viz::Color{p.overlay.rgb[0], p.overlay.rgb[1], p.overlay.rgb[2]};
    path.dashed = p.overlay.dashed;
    path.label = p.overlay.label;
    for (std::size_t i = first; i <= row; ++i) path.points_W.push_back(point_at(log, p.column, i));
    o.paths.push_back(std::move(path));
  }
  for (const auto& m : c.markers)
    o.markers.push_back({point_at(log, m.column, row), viz::Color{m.overlay.rgb[0], m.overlay.rgb[1], m.overlay.rgb[2]}, 0.06, m.overlay.label});
  for (const auto& x : c.texts) o.text_lines.push_back(text_of(x.overlay, at(log, x.column[0], row)));
}

viz::Overlays overlays(const model::RobotDescription& robot, const sim::Log& log, const PoseColumns& c, std::size_t row,
                       const std::vector<Eigen::Isometry3d>& X, const std::string& title) {
  viz::Overlays o;
  o.text_lines = {title, fmt::format("t = {:.3f} s", log.time()[row])};
  add_paths(log, c, row, o);
  o.com_W = model::center_of_mass(robot, X);
  for (const auto& k : c.contacts) {
    const Eigen::Vector3d f(at(log, k.force, row), at(log, k.force + 1, row), at(log, k.force + 2, row));
    if (f.allFinite() && f.norm() > 1e-3)
      o.forces.push_back({contact_point(k.site, X[static_cast<std::size_t>(k.site.link)]), f, viz::Color{230, 50, 40}});
  }
  return o;
}

// True when a missing mesh was used only as the visual of links drawn from their
// collision shapes instead (robot_scene.hpp): the stand-ins' line covers it.
bool replaced_by_collisions(const model::RobotDescription& robot, const std::string& uri) {
  const auto missing = [&](const model::Shape& s) {
    return s.geometry.kind == model::Geometry::Kind::Mesh && !s.geometry.mesh && s.geometry.mesh_uri == uri;
  };
  bool used = false;
  for (const model::Link& link : robot.links) {
    if (std::any_of(link.collisions.begin(), link.collisions.end(), missing)) return false;
    if (!std::any_of(link.visuals.begin(), link.visuals.end(), missing)) continue;
    if (!drawn_from_collisions(link)) return false;
    used = true;
  }
  return used;
}

// One line per missing mesh the robot is drawn without, and one naming the links drawn
// from their collision shapes.
std::vector<std::string> mesh_warnings(const model::RobotDescription& robot) {
  std::vector<std::string> w;
  for (const auto& m : robot.meshes_missing)
    if (!replaced_by_collisions(robot, m))
      w.push_back(fmt::format("{}: mesh '{}' could not be read: the frames draw the robot without it", robot.source, m));
  if (const auto stand_ins = links_drawn_from_collisions(robot); !stand_ins.empty())
    w.push_back(fmt::format("{}: {} links drawn from their collision shapes (a visual mesh missing, or no visual): {}",
                            robot.source, stand_ins.size(), fmt::join(stand_ins, ", ")));
  return w;
}

// The frames' files and the video written on three threads while the next frames are
// rendered: a frame is copied into one of a few buffers made once (the renderer's
// image is overwritten by the next render), one of two PNG writers (even and odd
// frames: compressing a 1920 x 1080 frame takes longer than rendering it) encodes and
// writes it, the video writer feeds it to the encoder in the frames' order, and the
// buffer is used again when both are done with it. A frame waits for its buffer to be
// free, so at most kBuffers frames are in flight. An error on any thread (a full disk, a folder that
// cannot be written) stops them all, and push() or finish() rethrows it as it was thrown
// (the same type and message the command line turns into its one line and exit code);
// the video's temporary file is removed by its writer, and a PNG is written whole
// (write_file_atomic) or not at all. Destroyed without finish() (an error on the
// rendering side), it stops the threads without writing the frames still queued.
class FrameWriter {
 public:
  static constexpr int kBuffers = 6;
  static constexpr std::size_t kPngThreads = 2;

  FrameWriter(const std::string& dir, double video_fps, int w, int h)
      : dir_(dir), video_((fs::path(dir) / "video.mp4").string(), video_fps) {
    for (auto& b : buffers_) b.image.create(h, w, CV_8UC3);
    for (std::size_t i = 0; i < kPngThreads; ++i) png_threads_[i] = std::thread([this, i] { run(kPng, i, kPngThreads); });
    video_thread_ = std::thread([this] { run(kVideo, 0, 1); });
  }
  ~FrameWriter() { stop(); }
  FrameWriter(const FrameWriter&) = delete;
  FrameWriter& operator=(const FrameWriter&) = delete;

  // Queues a copy of `image` to be written as `name` (relative to the folder) and
  // appended to the video. Blocks while the frame's buffer (frame next_ - kBuffers's)
  // is still being written: the two PNG threads finish frames out of order.
  void push(const cv::Mat& image, const std::string& name) {
    std::unique_lock<std::mutex> lock(mutex_);
    Buffer& b = buffers_[next_ % kBuffers];
    space_.wait(lock, [&] { return error_ || b.pending == 0; });
    if (error_) std::rethrow_exception(error_);
    lock.unlock();  // the buffer is free: no thread reads it until it is queued
    image.copyTo(b.image);  // same size and type: no allocation
    b.name = name;
    lock.lock();
    b.pending = 2;
    ++next_;
    work_.notify_all();
  }

  // Waits for every frame to be written and finishes the video (renamed into place).
  void finish() {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      closing_ = true;
      work_.notify_all();
    }
    join();
    if (error_) std::rethrow_exception(error_);
    video_.finish();
  }

 private:
  enum Role { kPng = 0, kVideo = 1 };
  struct Buffer {
    cv::Mat image;
    std::string name;
    int pending = 0;  // writers yet to write it (its PNG thread, the video thread)
  };

  // Writes frames first, first + stride, ... as they are queued.
  void run(Role role, std::size_t first, std::size_t stride) {
    std::size_t k = first;  // this thread's next frame
    for (;;) {
      std::unique_lock<std::mutex> lock(mutex_);
      work_.wait(lock, [&] { return error_ || stopping_ || k < next_ || closing_; });
      if (error_ || stopping_ || (k >= next_ && closing_)) return;
      Buffer& b = buffers_[k % kBuffers];
      lock.unlock();
      try {
        if (role == kPng)
          write_file_atomic((fs::path(dir_) / b.name).string(), viz::encode_png(b.image));
        else
          video_.write(b.image);
      } catch (...) {
        lock.lock();
        if (!error_) error_ = std::current_exception();
        space_.notify_all();
        work_.notify_all();
        return;
      }
      lock.lock();
      if (--b.pending == 0) space_.notify_all();
      k += stride;
    }
  }

  void join() {
    for (std::thread& t : png_threads_)
      if (t.joinable()) t.join();
    if (video_thread_.joinable()) video_thread_.join();
  }

  void stop() {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      stopping_ = true;
      work_.notify_all();
    }
    join();
  }

  std::string dir_;
  viz::VideoWriter video_;  // written by the video thread only, finished after it ends
  Buffer buffers_[kBuffers];
  std::mutex mutex_;
  std::condition_variable work_, space_;
  std::size_t next_ = 0;  // frames queued so far
  bool closing_ = false, stopping_ = false;
  std::exception_ptr error_;
  std::thread png_threads_[kPngThreads], video_thread_;  // last: started once everything above exists
};

}  // namespace

Frames write_frames(const scenario::ScenarioRun& run, const std::string& dir, const ReportOptions& options) {
  const scenario::Scenario& s = run.scenario;
  Frames out;
  out.variant = s.frames.variant.empty() ? run.runs.front().name : s.frames.variant;
  const auto r = std::find_if(run.runs.begin(), run.runs.end(), [&](const auto& x) { return x.name == out.variant; });
  const auto v = std::find_if(s.variants.begin(), s.variants.end(), [&](const auto& x) { return x.name == out.variant; });
  if (r == run.runs.end() || v == s.variants.end() || r->log.rows() == 0) return out;
  const model::RobotDescription robot = scenario::variant_plant(s, *v).robot;
  out.warnings = mesh_warnings(robot);
  const PoseColumns cols = pose_columns(robot, *r, *v, scenario::variant_overlays(s, *v), s.file);
  const viz::Scene scene = scene_from_robot(robot);
  // A fixed base without ground contact is clamped to a table (the paper's table tests):
  // one more scene body, after the links; a fixed base with contact (a test rig standing
  // on the floor) gets none. The camera still frames the robot alone (make_camera
  // below), so it is as large as without it.
  std::optional<Table> table;
  if (v->robot.base == model::BaseMode::Fixed && !v->robot.contact && !scene.bodies.empty())
    table = table_under(scene, link_poses(robot, r->log, cols, 0), cols.X_WB);
  viz::Scene drawn = scene;
  if (table) drawn.bodies.push_back(table->body);
  const Step step = row_step(r->log, s.frames);
  const std::size_t n = step.n;
  out.video_fps = step.video_fps;
  out.speedup = step.speedup;
  const viz::Camera cam = frame_camera(s.frames, options, robot, r->log, cols, n, scene);
  viz::Renderer renderer(cam.width_px, cam.height_px);
  renderer.set_scene(drawn);
  fs::create_directories(fs::path(dir) / "frames");
  FrameWriter writer(dir, out.video_fps, cam.width_px, cam.height_px);
  for (std::size_t row = 0; row < r->log.rows(); row += n) {
    const auto X = link_poses(robot, r->log, cols, row);
    std::vector<Eigen::Isometry3d> X_drawn = X;
    if (table) X_drawn.push_back(table->X_WT);
    const auto t0 = std::chrono::steady_clock::now();
    const cv::Mat& img =
        renderer.render(X_drawn, cam, overlays(robot, r->log, cols, row, X, s.name + "  |  " + out.variant));
    out.render_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const std::string name = fmt::format("frames/frame_{:05d}.png", out.frames.size());
    writer.push(img, name);
    out.frames.push_back({name, r->log.time()[row]});
  }
  writer.finish();
  return out;
}

}  // namespace dmbd::report::detail
