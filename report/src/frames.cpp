// The frame variant drawn from its log: the joints' logged angles through the robot's
// forward kinematics, the logged base pose for a floating robot, the logged contact
// forces as arrows (every colliding shape's, where contact_sites.hpp puts them), the
// centre of mass from the description's masses, the paths the variant's bus
// controllers and experiment declare (when logged), and a table under a fixed base.
// Links whose visual meshes are missing are drawn from their collision shapes
// (robot_scene.hpp), named in one warning.
#include "frames.hpp"

#include "contact_sites.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <exception>
#include <filesystem>
#include <limits>
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
#include "dmbd/viz/primitives.hpp"
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
  // Every colliding shape (contact_sites.hpp) with the column of its logged force
  // "contact.K.fx" (then fy, fz); none when the log has no contact forces.
  struct Contact {
    ContactSite site;
    int force;
  };
  std::vector<Contact> contacts;
  // What the variant's bus controllers and experiment declare (sim::Overlay: paths,
  // markers, text), each with the columns of its signals (-1: an empty signal, 0); drawn
  // only when every named signal was logged.
  struct Path {
    sim::Overlay overlay;
    std::array<int, 3> column;
  };
  std::vector<Path> paths, markers, texts;
};

bool one_dof(model::JointType t) {
  return t == model::JointType::Revolute || t == model::JointType::Continuous || t == model::JointType::Prismatic;
}

// The contact forces' columns, one per colliding shape in the plant's order. A log whose
// contact columns do not count the robot's colliding shapes was written for another
// robot: an error, as a missing joint angle is.
void add_contacts(const model::RobotDescription& robot, const sim::VariantResult& r, const std::string& file,
                  PoseColumns& c) {
  if (r.log.find("contact.0.fx") < 0) return;
  const std::vector<ContactSite> sites = contact_sites(robot);
  std::size_t logged = 0;
  while (r.log.find(fmt::format("contact.{}.fx", logged)) >= 0) ++logged;
  if (logged != sites.size())
    throw InputError(fmt::format("{}: variant '{}' logged the contact forces of {} shapes, its robot has {} colliding "
                                 "shapes: its frames cannot be drawn",
                                 file, r.name, logged, sites.size()));
  for (std::size_t k = 0; k < sites.size(); ++k)
    c.contacts.push_back({sites[k], r.log.find(fmt::format("contact.{}.fx", k))});
}

PoseColumns pose_columns(const model::RobotDescription& robot, const sim::VariantResult& r, const scenario::VariantSetup& v,
                         const std::vector<sim::Overlay>& overlays, const std::string& file) {
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
  for (const sim::Overlay& o : overlays) {
    std::array<int, 3> col{-1, -1, -1};
    bool logged = true;
    for (int k = 0; k < 3; ++k)
      if (!o.signals[static_cast<std::size_t>(k)].empty()) {
        col[static_cast<std::size_t>(k)] = r.log.find(o.signals[static_cast<std::size_t>(k)]);
        logged = logged && col[static_cast<std::size_t>(k)] >= 0;
      }
    if (!logged) continue;
    auto& list = o.kind == sim::Overlay::Kind::Path ? c.paths : o.kind == sim::Overlay::Kind::Marker ? c.markers : c.texts;
    list.push_back({o, col});
  }
  add_contacts(robot, r, file, c);
  return c;
}

double at(const sim::Log& log, int column, std::size_t row) { return column < 0 ? 0.0 : log.column(column)[row]; }

Eigen::Vector3d point_at(const sim::Log& log, const std::array<int, 3>& column, std::size_t row) {
  return {at(log, column[0], row), at(log, column[1], row), at(log, column[2], row)};
}

// A Text overlay's line: "LABEL: NAME" for a value with a name, else "LABEL: VALUE".
std::string text_of(const sim::Overlay& o, double v) {
  const double k = std::round(v);
  if (std::isfinite(v) && k >= 0 && k < static_cast<double>(o.value_names.size()) && std::abs(v - k) < 1e-9)
    return o.label + ": " + o.value_names[static_cast<std::size_t>(k)];
  return fmt::format("{}: {:.4g}", o.label, v);
}

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

// The table a fixed base is clamped to (the paper's table tests), one scene body in the
// world at X_WT: T at the base origin, z up, x along the base's heading (its x axis
// seen from above). The top (kTableDepth_m along x, kTableWidth_m across, kTableTop_m
// thick) has its upper face at the bottom of the root link's geometry (at the base
// origin for a root without geometry). Its front edge is kTableClear_m behind every
// other link's mesh that reaches into the top's height (DRACO's hips), so the legs hang
// free in front of the table and the three-quarter front view sees them; the torso's
// rear rests on it. A top centred under the torso would hide the thighs from that view
// and have the legs pass through it. It is centred under the root's geometry instead
// when nothing reaches into it, or when the edge would leave the root's geometry
// wholly in front of it. Four legs go down to the ground (z = 0) when the top's
// underside is at least kTableMinLegs_m above it. Placed once, from the first frame.
constexpr double kTableDepth_m = 0.5, kTableWidth_m = 0.6, kTableTop_m = 0.04, kTableLeg_m = 0.04,
                 kTableClear_m = 0.02, kTableMinLegs_m = 0.1;
const Eigen::Vector4f kTableTopRgba{0.78f, 0.64f, 0.42f, 1.0f}, kTableLegRgba{0.62f, 0.50f, 0.33f, 1.0f};

struct Table {
  viz::SceneBody body;
  Eigen::Isometry3d X_WT = Eigen::Isometry3d::Identity();
};

Table table_under(const viz::Scene& robot_scene, const std::vector<Eigen::Isometry3d>& X, const Eigen::Isometry3d& X_WB) {
  Table t;
  t.body.name = "table";
  const Eigen::Vector3d x_B = X_WB.linear().col(0);
  t.X_WT.translation() = X_WB.translation();
  t.X_WT.linear() = Eigen::AngleAxisd(std::atan2(x_B.y(), x_B.x()), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Isometry3d X_TW = t.X_WT.inverse();
  // Bounds in T of each mesh at the first frame.
  const auto mesh_box = [&](std::size_t body, const viz::SceneMesh& m) {
    Eigen::AlignedBox3d b;
    const Eigen::Isometry3d X_TL = X_TW * X[body];
    for (const auto& v : m.vertices) b.extend(X_TL * v.cast<double>());
    return b;
  };
  Eigen::AlignedBox3d root;
  for (const auto& m : robot_scene.bodies.front().meshes) root.extend(mesh_box(0, m));
  const double z_top = root.isEmpty() ? 0.0 : root.min().z();
  const double x_mid = root.isEmpty() ? 0.0 : root.center().x(), y_mid = root.isEmpty() ? 0.0 : root.center().y();
  double x_behind = std::numeric_limits<double>::infinity();  // the rearmost point reaching into the top
  for (std::size_t b = 1; b < robot_scene.bodies.size(); ++b)
    for (const auto& m : robot_scene.bodies[b].meshes) {
      const Eigen::AlignedBox3d box = mesh_box(b, m);
      if (!box.isEmpty() && box.min().z() < z_top && box.max().z() > z_top - kTableTop_m - kTableClear_m)
        x_behind = std::min(x_behind, box.min().x());
    }
  double x_front = x_mid + 0.5 * kTableDepth_m;
  if (std::isfinite(x_behind) && (root.isEmpty() || x_behind - kTableClear_m > root.min().x()))
    x_front = x_behind - kTableClear_m;
  const Eigen::Vector3d top_centre(x_front - 0.5 * kTableDepth_m, y_mid, z_top - 0.5 * kTableTop_m);
  viz::SceneMesh top = viz::transformed(viz::box_mesh({kTableDepth_m, kTableWidth_m, kTableTop_m}),
                                        Eigen::Isometry3d(Eigen::Translation3d(top_centre)));
  top.rgba = kTableTopRgba;
  t.body.meshes.push_back(std::move(top));
  const double underside_W = X_WB.translation().z() + z_top - kTableTop_m;  // T is level: z differs by the origin's
  if (underside_W >= kTableMinLegs_m)
    for (const double sx : {-1.0, 1.0})
      for (const double sy : {-1.0, 1.0}) {
        const double inset = 0.03 + 0.5 * kTableLeg_m;
        const Eigen::Vector3d centre(top_centre.x() + sx * (0.5 * kTableDepth_m - inset),
                                     top_centre.y() + sy * (0.5 * kTableWidth_m - inset),
                                     z_top - kTableTop_m - 0.5 * underside_W);
        viz::SceneMesh leg = viz::transformed(viz::box_mesh({kTableLeg_m, kTableLeg_m, underside_W}),
                                              Eigen::Isometry3d(Eigen::Translation3d(centre)));
        leg.rgba = kTableLegRgba;
        t.body.meshes.push_back(std::move(leg));
      }
  return t;
}

// The robot's bounds over every frame's pose (a robot that rises or walks stays in view).
Eigen::AlignedBox3d robot_bounds(const model::RobotDescription& robot, const sim::Log& log, const PoseColumns& c, std::size_t n,
                                 const viz::Scene& scene) {
  Eigen::AlignedBox3d b;
  for (std::size_t row = 0; row < log.rows(); row += n) b.extend(viz::scene_bounds(scene, link_poses(robot, log, c, row)));
  return b;
}

// A three-quarter view from the front left that frames the robot's bounds over the run,
// unless the scenario or the options give the camera.
template <class Bounds>
viz::Camera make_camera(const scenario::FrameSetup& f, const ReportOptions& o, const Bounds& bounds, int w, int h) {
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
  const Eigen::AlignedBox3d b = bounds();
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
  const int w = options.width_px.value_or(s.frames.width_px), h = options.height_px.value_or(s.frames.height_px);
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
  viz::Renderer renderer(w, h);
  renderer.set_scene(drawn);
  const Step step = row_step(r->log, s.frames);
  const std::size_t n = step.n;
  out.video_fps = step.video_fps;
  out.speedup = step.speedup;
  fs::create_directories(fs::path(dir) / "frames");
  const viz::Camera cam = make_camera(s.frames, options, [&] { return robot_bounds(robot, r->log, cols, n, scene); }, w, h);
  FrameWriter writer(dir, out.video_fps, w, h);
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
