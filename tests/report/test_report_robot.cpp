// DRACO's scene (dmbd::report::scene_from_robot) rendered by the mesh renderer: the
// scene against the description, poses from model::link_frames, images of the robot,
// overlays, and no heap allocation per frame.
//
// Set DMBD_RENDER_SAMPLE_DIR to a folder to also write the DRACO frames as PNG files.
#include "dmbd/base/file.hpp"
#include "dmbd/viz/renderer.hpp"

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sanitizer.hpp"
#include <opencv2/imgproc.hpp>

#include "dmbd/model/robot_description.hpp"
#include "dmbd/viz/plot.hpp"
#include "dmbd/report/robot_scene.hpp"
#include "dmbd/viz/primitives.hpp"

// ---------------------------------------------------------------------------------
// Allocation counter: the C allocation functions are replaced in this executable (glibc
// exports its own as __libc_*), so every heap allocation made by the process, by
// operator new, OpenCV's fastMalloc (posix_memalign) or C code, is counted while
// g_counting is set.
namespace {
volatile bool g_counting = false;
volatile long g_allocations = 0;
[[maybe_unused]] void count_one() {
  if (g_counting) g_allocations = g_allocations + 1;
}
}  // namespace

#if !DMBD_ASAN
extern "C" {
void* __libc_malloc(std::size_t);
void __libc_free(void*);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
}

extern "C" {
void* malloc(std::size_t n) noexcept {
  count_one();
  return __libc_malloc(n);
}
void free(void* p) noexcept { __libc_free(p); }
void* calloc(std::size_t a, std::size_t b) noexcept {
  count_one();
  return __libc_calloc(a, b);
}
void* realloc(void* p, std::size_t n) noexcept {
  count_one();
  return __libc_realloc(p, n);
}
void* memalign(std::size_t alignment, std::size_t n) noexcept {
  count_one();
  return __libc_memalign(alignment, n);
}
void* aligned_alloc(std::size_t alignment, std::size_t n) noexcept {
  count_one();
  return __libc_memalign(alignment, n);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t n) noexcept {
  count_one();
  void* p = __libc_memalign(alignment, n);
  if (p == nullptr) return ENOMEM;
  *out = p;
  return 0;
}
}
#endif  // !DMBD_ASAN

namespace dmbd::viz {
namespace {

using dmbd::model::link_frames;
using dmbd::report::scene_from_robot;

constexpr int kW = 640, kH = 360;  // small frames keep the tests fast



Camera camera(const Eigen::Vector3d& position, const Eigen::Vector3d& look_at, int w = kW, int h = kH,
              double fov_deg = 40) {
  Camera c;
  c.position = position;
  c.look_at = look_at;
  c.width_px = w;
  c.height_px = h;
  c.fov_y_deg = fov_deg;
  return c;
}




int count_ids(const cv::Mat& ids, int id) {
  int n = 0;
  for (int r = 0; r < ids.rows; ++r)
    for (int c = 0; c < ids.cols; ++c) n += ids.at<std::int16_t>(r, c) == id ? 1 : 0;
  return n;
}



// ---------------------------------------------------------------------------------
// DRACO.

class Draco : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    robot_ = new model::RobotDescription(model::load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf"));
    scene_ = new Scene(scene_from_robot(*robot_));
  }
  static void TearDownTestSuite() {
    delete scene_;
    delete robot_;
  }
  static std::vector<double> zeros() { return std::vector<double>(robot_->joints.size(), 0.0); }
  static model::RobotDescription* robot_;
  static Scene* scene_;
};
model::RobotDescription* Draco::robot_ = nullptr;
Scene* Draco::scene_ = nullptr;

void save_sample(const cv::Mat& img, const std::string& name) {
  if (const char* dir = std::getenv("DMBD_RENDER_SAMPLE_DIR"))
    dmbd::write_file_atomic(std::string(dir) + "/" + name, encode_png(img));
}

TEST_F(Draco, SceneFromRobot) {
  ASSERT_EQ(scene_->bodies.size(), robot_->links.size());
  std::size_t visuals = 0;
  for (std::size_t i = 0; i < robot_->links.size(); ++i) {
    EXPECT_EQ(scene_->bodies[i].name, robot_->links[i].name);
    for (const auto& s : robot_->links[i].visuals)
      visuals += (s.geometry.kind != model::Geometry::Kind::Mesh || s.geometry.mesh) ? 1 : 0;
  }
  std::size_t meshes = 0;
  for (const auto& b : scene_->bodies) meshes += b.meshes.size();
  EXPECT_EQ(meshes, visuals);
  EXPECT_EQ(meshes, 46u);  // 29 meshes + 17 primitives (robots/draco/README.md)
  EXPECT_GT(scene_->triangle_count(), 10000u);
  // Every part is closed and outward wound (the README's claim), so all are culled safely.
  Renderer renderer(kW, kH);
  renderer.set_scene(*scene_);
  EXPECT_EQ(renderer.closed_mesh_count(), meshes);
  // Preview kinematics agree with the model's default pose; standing, the visuals are 1.30 m tall.
  const auto X_zero = link_frames(*robot_, zeros());
  const auto X_model = model::default_pose_link_frames(*robot_);
  ASSERT_EQ(X_zero.size(), X_model.size());
  for (std::size_t i = 0; i < X_zero.size(); ++i) EXPECT_TRUE(X_zero[i].isApprox(X_model[i], 1e-12)) << i;
  auto X = X_zero;
  place_on_ground(*scene_, X);
  const Eigen::AlignedBox3d box = scene_bounds(*scene_, X);
  EXPECT_NEAR(box.min().z(), 0.0, 1e-9);
  EXPECT_NEAR(box.max().z(), 1.30, 0.01);
}

TEST_F(Draco, RendersTheRobotAndTheBentKnee) {
  Renderer renderer(1280, 720);
  renderer.set_scene(*scene_);
  auto X = link_frames(*robot_, zeros());
  const double lift = place_on_ground(*scene_, X);
  const Camera cam = default_robot_camera(1.30);
  const cv::Mat straight = renderer.render(X, cam).clone();
  const cv::Mat ids = renderer.body_ids().clone();
  save_sample(straight, "draco_render.png");

  // Many robot pixels, all well inside the frame, the robot filling most of its height.
  const cv::Mat robot = ids >= 0;
  const int n_robot = cv::countNonZero(robot);
  EXPECT_GT(n_robot, 0.03 * 1280 * 720);  // DRACO is slim: ~4.5% of this frame
  const cv::Rect bbox = cv::boundingRect(robot);
  EXPECT_GT(bbox.x, 0.05 * 1280);
  EXPECT_GT(bbox.y, 0.05 * 720);
  EXPECT_LT(bbox.x + bbox.width, 0.95 * 1280);
  EXPECT_LT(bbox.y + bbox.height, 0.95 * 720);
  EXPECT_GT(bbox.height, 0.6 * 720);
  // The torso, thighs, shanks and feet are all visible.
  for (const char* name : {"torso", "l_thigh", "r_thigh", "l_shank", "r_shank", "l_foot", "r_foot"}) {
    const int id = robot_->link_index(name);
    ASSERT_GE(id, 0) << name;
    EXPECT_GT(count_ids(ids, id), 300) << name;
  }
  // Lit, not black or blown out, and shaded (not one flat colour).
  cv::Mat grey;
  cv::cvtColor(straight, grey, cv::COLOR_BGR2GRAY);
  cv::Scalar mean, stddev;
  cv::meanStdDev(grey, mean, stddev, robot);
  EXPECT_GT(mean[0], 50);
  EXPECT_LT(mean[0], 210);
  EXPECT_GT(stddev[0], 15);
  // The torso is above the thighs in the image.
  const cv::Moments torso = cv::moments(ids == robot_->link_index("torso"), true);
  const cv::Moments shank = cv::moments(ids == robot_->link_index("l_shank"), true);
  EXPECT_LT(torso.m01 / torso.m00, shank.m01 / shank.m00);

  // Left knee bent by 1 rad, the torso where it was: the left leg's pixels change, the torso's do not.
  std::vector<double> q = zeros();
  q[robot_->joint_index("l_knee")] = 1.0;
  auto X_bent = link_frames(*robot_, q);
  for (auto& Xi : X_bent) Xi.translation().z() += lift;
  const cv::Mat bent = renderer.render(X_bent, cam).clone();
  const cv::Mat ids_bent = renderer.body_ids().clone();
  save_sample(bent, "draco_render_knee_bent.png");
  const int l_shank = robot_->link_index("l_shank"), l_foot = robot_->link_index("l_foot"),
            torso_id = robot_->link_index("torso");
  const cv::Mat leg = (ids == l_shank) | (ids == l_foot) | (ids_bent == l_shank) | (ids_bent == l_foot);
  cv::Mat diff;
  cv::absdiff(straight, bent, diff);
  cv::Mat diff_grey;
  cv::cvtColor(diff, diff_grey, cv::COLOR_BGR2GRAY);
  const cv::Mat changed = diff_grey > 20;
  const int leg_pixels = cv::countNonZero(leg);
  const int leg_changed = cv::countNonZero(changed & leg);
  EXPECT_GT(leg_changed, 0.5 * leg_pixels) << leg_changed << " of " << leg_pixels;
  const cv::Mat torso_mask = ids == torso_id;
  EXPECT_EQ(cv::countNonZero(torso_mask ^ (ids_bent == torso_id)), 0);
  EXPECT_EQ(cv::countNonZero(changed & torso_mask), 0);
}

// ---------------------------------------------------------------------------------
// Overlays.

TEST(Overlays, DrawnWhereProjected) {
  const Camera cam = camera({2.5, 1.8, 1.4}, {0, 0, 0.5});
  Renderer renderer(kW, kH);
  renderer.set_scene(Scene{});
  const cv::Mat base = renderer.render({}, cam).clone();

  Overlays ov;
  ov.text_lines = {"t = 1.234 s", "phase: left swing"};
  ov.com_W = Eigen::Vector3d(0.1, -0.1, 0.8);
  ov.com_color = {255, 220, 0};
  ov.forces.push_back({Eigen::Vector3d(-0.3, 0.4, 0.0), Eigen::Vector3d(50, 0, 400), {0, 60, 255}});
  ov.force_scale_m_per_N = 0.001;
  const cv::Mat img = renderer.render({}, cam, ov).clone();

  const auto is_com = [](const cv::Vec3b& p) { return p[2] > 200 && p[1] > 170 && p[0] < 90; };
  const auto is_force = [](const cv::Vec3b& p) { return p[0] > 200 && p[2] < 80; };
  const auto any_near = [](const cv::Mat& m, const Eigen::Vector2d& uv, int radius, auto pred) {
    for (int dr = -radius; dr <= radius; ++dr)
      for (int dc = -radius; dc <= radius; ++dc)
        if (pred(m.at<cv::Vec3b>(int(uv.y()) + dr, int(uv.x()) + dc))) return true;
    return false;
  };
  // CoM crosshair at the CoM's projection, a marker at its ground point.
  const Eigen::Vector2d com = *project(cam, *ov.com_W);
  EXPECT_TRUE(any_near(img, com, 1, is_com));
  EXPECT_FALSE(any_near(base, com, 1, is_com));
  const Eigen::Vector2d com_ground = *project(cam, Eigen::Vector3d(0.1, -0.1, 0.0));
  EXPECT_TRUE(any_near(img, com_ground, 1, is_com));
  // The ground ring (5 cm radius) passes through the point 5 cm from the ground point.
  EXPECT_TRUE(any_near(img, *project(cam, Eigen::Vector3d(0.15, -0.1, 0.0)), 1, is_com));
  // The arrow's shaft through the projection of the middle of the force segment, the head at its tip.
  const Eigen::Vector3d tail = ov.forces[0].p_W, tip = tail + 0.001 * ov.forces[0].f_W_N;
  EXPECT_TRUE(any_near(img, *project(cam, 0.5 * (tail + tip)), 1, is_force));
  EXPECT_TRUE(any_near(img, *project(cam, tip - 0.02 * (tip - tail)), 1, is_force));
  EXPECT_FALSE(any_near(base, *project(cam, 0.5 * (tail + tip)), 1, is_force));
  // Nothing is drawn far from the overlays: the bottom-right corner is untouched.
  const cv::Rect corner(kW - 60, kH - 40, 60, 40);
  EXPECT_EQ(cv::norm(img(corner), base(corner), cv::NORM_INF), 0.0);
  // Text on a dark panel in the top-left corner: darker on average, with white strokes.
  const cv::Rect panel(8, 8, 90, 26);
  cv::Mat grey, grey_base;
  cv::cvtColor(img(panel), grey, cv::COLOR_BGR2GRAY);
  cv::cvtColor(base(panel), grey_base, cv::COLOR_BGR2GRAY);
  EXPECT_LT(cv::mean(grey)[0], 0.8 * cv::mean(grey_base)[0]);
  EXPECT_GT(cv::countNonZero(grey > 200), 30);
  // An arrow whose tail is behind the camera is clipped, not garbage.
  Overlays behind;
  behind.forces.push_back(
      {cam.position - 2.0 * (cam.look_at - cam.position), Eigen::Vector3d(0, 0, 1000), {0, 60, 255}});
  EXPECT_NO_THROW(renderer.render({}, cam, behind));
}

// ---------------------------------------------------------------------------------
// No allocation per frame.

TEST_F(Draco, NoHeapAllocationPerFrameAfterWarmUp) {
  DMBD_SKIP_UNDER_ASAN();
  Renderer renderer(kW, kH);
  renderer.set_scene(*scene_);
  std::vector<std::vector<Eigen::Isometry3d>> poses;
  for (int k = 0; k < 4; ++k) {
    std::vector<double> q = zeros();
    q[robot_->joint_index("l_knee")] = 0.3 * k;
    q[robot_->joint_index("r_hip_pitch")] = -0.2 * k;
    poses.push_back(link_frames(*robot_, q));
    place_on_ground(*scene_, poses.back());
  }
  Overlays ov;
  ov.text_lines = {"t = 0.000 s", "phase: stance"};
  ov.com_W = Eigen::Vector3d(0, 0, 0.8);
  ov.forces.push_back({Eigen::Vector3d(0, 0.17, 0), Eigen::Vector3d(0, 0, 180), {230, 50, 40}});
  // Paths, solid and dashed, with legend entries; both cross the near plane of cams[3].
  PathOverlay measured, desired;
  for (int i = 0; i < 500; ++i) {
    const double a = 2 * M_PI * i / 250;
    measured.points_W.emplace_back(0.5 * std::cos(a), 0.2 + 0.5 * std::sin(a), 0.4);
    desired.points_W.emplace_back(0.5 * std::cos(a), 0.2 + 0.5 * std::sin(a), 0.45);
  }
  measured.label = "measured";
  desired.dashed = true;
  desired.label = "desired";
  ov.paths = {measured, desired};
  std::vector<Camera> cams;
  for (int k = 0; k < 4; ++k) {
    Camera c = default_robot_camera(1.3, kW, kH);
    c.position += Eigen::Vector3d(0.2 * k, -0.3 * k, 0.1 * k);
    cams.push_back(c);
  }
  cams[3].position = Eigen::Vector3d(0.4, 0.0, 0.9);  // the near plane cuts through the legs
  cams[3].look_at = Eigen::Vector3d(-1, 0, 0.9);
  cams[3].near_m = 0.3;
  renderer.render(poses[0], cams[0], ov);  // warm-up
  const unsigned char* data = renderer.image().data;

  // The counter sees allocations (so a zero below means something).
  g_allocations = 0;
  g_counting = true;
  std::vector<int>* probe = new std::vector<int>(100);
  void* c_probe = std::malloc(64);
  g_counting = false;
  delete probe;
  std::free(c_probe);
  ASSERT_GE(g_allocations, 3);

  std::size_t clipped = 0;
  g_allocations = 0;
  g_counting = true;
  for (int k = 0; k < 8; ++k) {
    renderer.render(poses[k % 4], cams[(k * 3) % 4], ov);
    clipped += renderer.stats().triangles_clipped;
  }
  g_counting = false;
  EXPECT_EQ(g_allocations, 0);
  EXPECT_EQ(renderer.image().data, data);  // the same buffer
  EXPECT_GT(clipped, 0u);                  // the clipping path ran too
}

}  // namespace
}  // namespace dmbd::viz
