// Mesh renderer speed: DRACO at 1280x720 and 1920x1080 (goal: >= 30 frames/s), with
// the camera moving (every frame draws everything) and fixed (a run's frames: the
// background is kept), split into its parts (background + ground + grid, shadow map,
// meshes, overlays), and the one-off scene conversion.
//
//   build/bench/bench_viz --benchmark_counters_tabular=true
//
// BM_DracoFrame/W/H and BM_DracoFrameFixedCamera/W/H use the renderer's default
// thread count (min(2, cores)); the *Threads variants take the thread count as a third
// argument (1: the single-threaded path, 2: the caller's thread and one helper), so
// both figures are printed. The thread count is in each result's `threads` counter.
//
// Each frame poses the robot anew (a precomputed 60-frame walk-like cycle of hip, knee
// and ankle angles) and orbits the camera a little, so no frame repeats the previous one.
#include <chrono>
#include <cmath>
#include <cstddef>
#include <vector>

#include <benchmark/benchmark.h>

#include "dmbd/model/robot_description.hpp"
#include "dmbd/viz/renderer.hpp"
#include "dmbd/report/robot_scene.hpp"
#include "dmbd/viz/primitives.hpp"

namespace {

using dmbd::viz::Camera;
using dmbd::viz::Renderer;

struct DracoFrames {
  dmbd::model::RobotDescription robot;
  dmbd::viz::Scene scene;
  std::vector<std::vector<Eigen::Isometry3d>> poses;  // one per frame of the cycle
  std::vector<Camera> cameras;
  dmbd::viz::Overlays overlays;

  DracoFrames()
      : robot(dmbd::model::load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf")), scene(dmbd::report::scene_from_robot(robot)) {
    constexpr int kFrames = 60;
    const auto joint = [&](const char* name) { return robot.joint_index(name); };
    double lift = 0;
    for (int k = 0; k < kFrames; ++k) {
      const double ph = 2 * M_PI * k / kFrames;
      std::vector<double> q(robot.joints.size(), 0.0);
      q[joint("l_hip_pitch")] = -0.4 + 0.35 * std::sin(ph);
      q[joint("r_hip_pitch")] = -0.4 - 0.35 * std::sin(ph);
      q[joint("l_knee")] = 0.8 + 0.4 * std::max(0.0, std::cos(ph));
      q[joint("r_knee")] = 0.8 + 0.4 * std::max(0.0, -std::cos(ph));
      q[joint("l_ankle")] = -0.4;
      q[joint("r_ankle")] = -0.4;
      auto X = dmbd::model::link_frames(robot, q);
      if (k == 0)
        lift = dmbd::viz::place_on_ground(scene, X);
      else
        for (auto& Xi : X) Xi.translation().z() += lift;
      poses.push_back(std::move(X));
      Camera cam = dmbd::viz::default_robot_camera(1.30);
      const double orbit = 0.15 * std::sin(ph);  // rad about the vertical through the robot
      const Eigen::Vector3d rel = cam.position - cam.look_at;
      cam.position = cam.look_at + Eigen::AngleAxisd(orbit, Eigen::Vector3d::UnitZ()) * rel;
      cameras.push_back(cam);
    }
    overlays.text_lines = {"t = 1.234 s", "phase: left swing", "CoM height 0.912 m"};
    overlays.com_W = Eigen::Vector3d(0.0, 0.0, 0.9);
    overlays.forces.push_back({Eigen::Vector3d(0.02, 0.167, 0.0), Eigen::Vector3d(10, -5, 250), {230, 50, 40}});
    overlays.forces.push_back({Eigen::Vector3d(0.02, -0.167, 0.0), Eigen::Vector3d(-8, 4, 120), {40, 120, 230}});
  }
};

const DracoFrames& draco() {
  static const DracoFrames frames;
  return frames;
}

// Wall-clock seconds since `start`.
double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// frames_per_s is per second of wall-clock time over the timed loop (`seconds`): a
// kIsRate counter would divide by the benchmark thread's CPU time, which leaves out
// the renderer's helper threads.
void report(benchmark::State& state, const Renderer& renderer, double seconds) {
  state.counters["frames_per_s"] = static_cast<double>(state.iterations()) / seconds;
  state.counters["threads"] = static_cast<double>(renderer.thread_count());
  state.counters["triangles"] = static_cast<double>(renderer.triangle_count());
  state.counters["tri_rasterised"] = static_cast<double>(renderer.stats().triangles_rasterised);
}

// The whole frame: sky, ground with grid and soft shadow, the robot, overlays, drawn by
// `threads` threads (0: the renderer's default).
void draco_frames(benchmark::State& state, int threads) {
  const DracoFrames& d = draco();
  const int w = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  Renderer renderer(w, h, threads);
  renderer.set_scene(d.scene);
  std::size_t k = 0;
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    Camera cam = d.cameras[k % d.cameras.size()];
    cam.width_px = w;
    cam.height_px = h;
    const cv::Mat& img = renderer.render(d.poses[k % d.poses.size()], cam, d.overlays);
    benchmark::DoNotOptimize(img.data);
    ++k;
  }
  report(state, renderer, seconds_since(start));
}
void BM_DracoFrame(benchmark::State& state) { draco_frames(state, 0); }
BENCHMARK(BM_DracoFrame)->Args({1280, 720})->Args({1920, 1080})->Args({640, 360})->Unit(benchmark::kMillisecond);
void BM_DracoFrameThreads(benchmark::State& state) { draco_frames(state, static_cast<int>(state.range(2))); }
BENCHMARK(BM_DracoFrameThreads)
    ->ArgsProduct({{1280}, {720}, {1, 2}})
    ->ArgsProduct({{1920}, {1080}, {1, 2}})
    ->Unit(benchmark::kMillisecond);

// The frames of a run (report/src/frames.cpp): one camera for every frame, so the
// renderer keeps the background (sky, ground, grid) and draws again only the ground
// that may be in the shadow, the robot and the overlays.
void draco_frames_fixed_camera(benchmark::State& state, int threads) {
  const DracoFrames& d = draco();
  const int w = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  Renderer renderer(w, h, threads);
  renderer.set_scene(d.scene);
  Camera cam = d.cameras.front();
  cam.width_px = w;
  cam.height_px = h;
  std::size_t k = 0;
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    const cv::Mat& img = renderer.render(d.poses[k % d.poses.size()], cam, d.overlays);
    benchmark::DoNotOptimize(img.data);
    ++k;
  }
  report(state, renderer, seconds_since(start));
}
void BM_DracoFrameFixedCamera(benchmark::State& state) { draco_frames_fixed_camera(state, 0); }
BENCHMARK(BM_DracoFrameFixedCamera)->Args({1280, 720})->Args({1920, 1080})->Unit(benchmark::kMillisecond);
void BM_DracoFrameFixedCameraThreads(benchmark::State& state) {
  draco_frames_fixed_camera(state, static_cast<int>(state.range(2)));
}
BENCHMARK(BM_DracoFrameFixedCameraThreads)
    ->ArgsProduct({{1280}, {720}, {1, 2}})
    ->ArgsProduct({{1920}, {1080}, {1, 2}})
    ->Unit(benchmark::kMillisecond);

// Parts of the 1280x720 frame, by switching the others off (default thread count).
enum Part { kBackgroundOnly, kGroundGrid, kGroundGridShadow, kRobotNoGround };
void BM_DracoParts(benchmark::State& state) {
  const DracoFrames& d = draco();
  const auto part = static_cast<Part>(state.range(0));
  Renderer renderer(1280, 720);
  renderer.style().ground = part != kBackgroundOnly && part != kRobotNoGround;
  renderer.style().shadows = part == kGroundGridShadow;
  const bool robot = part == kRobotNoGround || part == kGroundGridShadow;
  if (robot) renderer.set_scene(d.scene);
  const std::vector<Eigen::Isometry3d> none;
  std::size_t k = 0;
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    const cv::Mat& img = renderer.render(robot ? d.poses[k % d.poses.size()] : none, d.cameras[k % d.cameras.size()]);
    benchmark::DoNotOptimize(img.data);
    ++k;
  }
  report(state, renderer, seconds_since(start));
  static const char* names[] = {"background only", "ground + grid", "ground + grid + shadow + robot",
                                "robot on background"};
  state.SetLabel(names[part]);
}
BENCHMARK(BM_DracoParts)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

// One-off costs: URDF description -> Scene, and Scene -> renderer (closedness check etc.).
void BM_SceneFromRobot(benchmark::State& state) {
  const DracoFrames& d = draco();
  for (auto _ : state) benchmark::DoNotOptimize(dmbd::report::scene_from_robot(d.robot));
}
BENCHMARK(BM_SceneFromRobot)->Unit(benchmark::kMillisecond);

void BM_SetScene(benchmark::State& state) {
  const DracoFrames& d = draco();
  Renderer renderer(1280, 720);
  for (auto _ : state) renderer.set_scene(d.scene);
}
BENCHMARK(BM_SetScene)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
