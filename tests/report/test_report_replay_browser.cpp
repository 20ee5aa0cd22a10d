// The report's 3-D replay in headless Chromium (/usr/bin/chromium, Debian's): the page
// loads with no message on the console, and a picture of the replay at time t shows the
// robot where the frame at t shows it. DRACO (its meshes), the leg rig (primitives) and
// Simbody's Atlas (drawn from its collision shapes), each falling or dropping for 0.3 s,
// frames at 10/s, 480 x 360.
//
// Chromium runs with --headless --no-sandbox (root in a container) and WebGL on
// SwiftShader, its software renderer (--use-angle=swiftshader --enable-unsafe-swiftshader:
// without a GPU, Chromium refuses WebGL unless told that software rendering is wanted),
// --enable-logging=stderr --v=0 (the page's console messages and uncaught errors come as
// "CONSOLE" lines on stderr; the player writes none unless something fails).
//
// The comparison: the page with ?view=replay&t=T&variant=V&ground=0&overlays=0 shows the
// view alone at the frames' size, the robot over a sky gradient (constant along a row), so
// the robot's pixels are those away from their row's median colour. The frame's robot
// pixels are those the renderer's body ids give when the test draws the robot at the
// same row's poses from the same camera (checked against the frame image itself: they are
// the frame's pixels there), kept where they would stand out from the same sky. Masks:
// intersection over union >= 0.85, centroids within 3 px; the robot having moved by more
// than 15 px between t = 0 and T, a replay showing the wrong time would fail.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "atlas_scenario.hpp"
#include "dmbd/base/process.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/report/report.hpp"
#include "dmbd/report/robot_scene.hpp"
#include "dmbd/scenario/run_directory.hpp"
#include "dmbd/viz/renderer.hpp"
#include "sim_test_support.hpp"

namespace {

namespace fs = std::filesystem;
using dmbd::sim::test::read_text;
using dmbd::sim::test::TempDir;
using dmbd::sim::test::write_text;

constexpr int kW = 480, kH = 360;

// Chromium on the page: a screenshot (non-empty `png`) or the DOM (`dom`), and the
// console's lines.
struct Browser {
  std::string out, console;
};
Browser chromium(const std::string& url, const std::string& dir, const std::string& png) {
  const std::string chromium = dmbd::viz::test::find_chromium();
  if (chromium.empty()) throw std::runtime_error("chromium is not installed (needed for the replay's browser test): run scripts/setup");
  std::vector<std::string> argv = {"timeout", "60", chromium, "--headless", "--no-sandbox", "--use-angle=swiftshader",
                                   "--enable-unsafe-swiftshader", "--enable-logging=stderr", "--v=0", "--hide-scrollbars",
                                   fmt::format("--window-size={},{}", kW, kH), "--user-data-dir=" + dir + "/profile"};
  if (png.empty()) {
    argv.insert(argv.end(), {"--virtual-time-budget=5000", "--dump-dom"});
  } else {
    argv.push_back("--screenshot=" + png);
  }
  argv.push_back(url);
  const dmbd::ProgramRun r = dmbd::run_program(argv, dir + "/out.txt", dir + "/err.txt");
  Browser b{read_text(dir + "/out.txt"), ""};
  const std::string err = read_text(dir + "/err.txt");
  if (!r.ok()) throw std::runtime_error(fmt::format("{} failed ({} {}): {}", dmbd::shell_line(argv), r.exit_code, r.why, err));
  std::size_t start = 0;
  while (start < err.size()) {
    const std::size_t end = std::min(err.find('\n', start), err.size());
    if (err.find("CONSOLE", start) < end) b.console += err.substr(start, end - start) + "\n";
    start = end + 1;
  }
  return b;
}

// The background of the replay's picture: each row's median colour (the sky gradient is
// constant along a row, and the robot covers less than half of any row).
std::vector<cv::Vec3b> row_medians(const cv::Mat& img) {
  std::vector<cv::Vec3b> out;
  std::vector<int> c;
  for (int y = 0; y < img.rows; ++y) {
    cv::Vec3b median;
    for (int k = 0; k < 3; ++k) {
      c.clear();
      for (int x = 0; x < img.cols; ++x) c.push_back(img.at<cv::Vec3b>(y, x)[k]);
      std::nth_element(c.begin(), c.begin() + img.cols / 2, c.end());
      median[k] = static_cast<unsigned char>(c[static_cast<std::size_t>(img.cols / 2)]);
    }
    out.push_back(median);
  }
  return out;
}

// The pixels (within `where`) whose colour is more than 24 (of 255, any channel) from the
// background's row colour: the robot as it stands out from the sky gradient.
cv::Mat standing_out(const cv::Mat& img, const std::vector<cv::Vec3b>& background, const cv::Mat& where) {
  cv::Mat mask(img.size(), CV_8U, cv::Scalar(0));
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x) {
      const cv::Vec3b p = img.at<cv::Vec3b>(y, x), b = background[static_cast<std::size_t>(y)];
      int d = 0;
      for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(p[k] - b[k]));
      mask.at<unsigned char>(y, x) = d > 24 && where.at<unsigned char>(y, x) ? 255 : 0;
    }
  return mask;
}

struct Shape {
  double area = 0;
  cv::Point2d centroid;
};
Shape shape(const cv::Mat& mask) {
  const cv::Moments m = cv::moments(mask, true);
  return {m.m00, m.m00 > 0 ? cv::Point2d(m.m10 / m.m00, m.m01 / m.m00) : cv::Point2d()};
}
double iou(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat i, u;
  cv::bitwise_and(a, b, i);
  cv::bitwise_or(a, b, u);
  return static_cast<double>(cv::countNonZero(i)) / std::max(1, cv::countNonZero(u));
}

// The frames' drawing of the variant's robot at `row` without overlays, from the
// scenario's camera; `ids` gets the mask of the robot's pixels.
cv::Mat robot_drawn(const dmbd::scenario::ScenarioRun& run, std::size_t variant, std::size_t row, cv::Mat& ids) {
  const auto& v = run.scenario.variants[variant];
  const auto& log = run.runs[variant].log;
  const auto robot = dmbd::scenario::variant_plant(run.scenario, v).robot;
  std::vector<double> q(robot.joints.size(), 0.0);
  for (std::size_t j = 0; j < q.size(); ++j)
    if (log.find(robot.joints[j].name + ".q") >= 0) q[j] = log.column(robot.joints[j].name + ".q")[row];
  Eigen::Isometry3d X = v.robot.X_WB;
  if (v.robot.base == dmbd::model::BaseMode::Floating) {
    const auto c = [&](const char* n) { return log.column(std::string("base.") + n)[row]; };
    X.linear() = (Eigen::AngleAxisd(c("yaw"), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(c("pitch"), Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(c("roll"), Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    X.translation() << c("x"), c("y"), c("z");
  }
  dmbd::viz::Camera cam;
  cam.position = *run.scenario.frames.camera_position;
  cam.look_at = *run.scenario.frames.camera_look_at;
  cam.width_px = kW;
  cam.height_px = kH;
  dmbd::viz::Renderer r(kW, kH);
  r.set_scene(dmbd::report::scene_from_robot(robot));
  const cv::Mat img = r.render(dmbd::model::link_frames(robot, q, X), cam).clone();
  ids = r.body_ids() >= 0;
  return img;
}

// Runs the scenario text, writes its report, and compares the replay of `variant` at
// frame `frame` (time frame / 10 s) with the frame.
void expect_replay_shows_the_frame(const std::string& yaml, std::size_t variant, int frame) {
  TempDir dir;
  write_text(dir.file("s.yaml"), yaml);
  const std::string out = dir.file("out");
  const auto run = dmbd::scenario::run_scenario(dmbd::scenario::load_scenario(dir.file("s.yaml")), out);
  const auto rep = dmbd::report::write_report(run, out);
  ASSERT_GT(rep.frames, frame);
  const auto& log = run.runs[variant].log;
  const double t = 0.1 * frame;
  const auto row = static_cast<std::size_t>(std::lower_bound(log.time().begin(), log.time().end(), t - 1e-9) - log.time().begin());
  ASSERT_NEAR(log.time()[row], t, 1e-9);

  // The frame shows the robot where the test's drawing of it is.
  cv::Mat frame_mask, start_mask;
  const cv::Mat drawn = robot_drawn(run, variant, row, frame_mask);
  const cv::Mat image = cv::imread(fmt::format("{}/frames/frame_{:05d}.png", out, frame), cv::IMREAD_COLOR);
  ASSERT_EQ(image.size(), cv::Size(kW, kH));
  cv::Mat diff, same;
  cv::absdiff(image, drawn, diff);
  cv::cvtColor(diff, diff, cv::COLOR_BGR2GRAY);
  cv::bitwise_and(diff <= 6, frame_mask, same);
  const double agree = static_cast<double>(cv::countNonZero(same)) / cv::countNonZero(frame_mask);
  EXPECT_GT(agree, 0.85) << "the frame image is not the robot drawn at that row (overlays cover the rest)";

  // The replay at that time.
  const std::string png = dir.file("replay.png");
  const Browser b = chromium(fmt::format("file://{}/report.html?view=replay&t={}&variant={}&ground=0&overlays=0", out, t,
                                         run.runs[variant].name),
                             dir.path().string(), png);
  EXPECT_EQ(b.console, "") << "console messages";
  const cv::Mat shot = cv::imread(png, cv::IMREAD_COLOR);
  ASSERT_EQ(shot.size(), cv::Size(kW, kH));
  if (const char* keep = std::getenv("DMBD_KEEP_SCREENSHOT"))
    fs::copy_file(png, fmt::format("{}_{}.png", keep, run.scenario.name), fs::copy_options::overwrite_existing);
  // The robot's pixels that stand out from the sky in the replay, and those of the frame's
  // robot that would stand out from the same sky (a part as light as the sky's lower
  // rows, the leg rig's base plate, is in neither).
  const std::vector<cv::Vec3b> sky = row_medians(shot);
  const cv::Mat replay = standing_out(shot, sky, cv::Mat(shot.size(), CV_8U, cv::Scalar(255)));
  frame_mask = standing_out(drawn, sky, frame_mask);
  const cv::Mat start = robot_drawn(run, variant, 0, start_mask);
  start_mask = standing_out(start, sky, start_mask);
  const Shape r = shape(replay), f = shape(frame_mask), s = shape(start_mask);
  const double overlap = iou(replay, frame_mask), moved = cv::norm(f.centroid - s.centroid), off = cv::norm(r.centroid - f.centroid);
  std::printf("%s: robot %.0f px in the replay, %.0f in the frame; IoU %.3f; centroids %.2f px apart; moved %.1f px since t = 0\n",
              run.scenario.name.c_str(), r.area, f.area, overlap, off, moved);
  EXPECT_GT(f.area, 0.02 * kW * kH) << "the robot is too small in the picture to compare";
  EXPECT_GT(overlap, 0.85);
  EXPECT_LT(off, 3.0);
  EXPECT_GT(moved, 15.0) << "the robot hardly moved: a replay at the wrong time would pass";
}

TEST(ReplayBrowser, DracoFallingWhereItsFrameShowsIt) {
  expect_replay_shows_the_frame(
      "name: draco_fall\n"
      "robot: {name: draco, base: floating, base_pose: {xyz: [0, 0, 1.4], rpy: [0.2, 0.1, 0.4]}, moving: [l_knee, r_knee],\n"
      "        actuators: [l_knee], initial: {l_knee: 1.0, r_knee: 0.5}}\n"
      "duration_s: 0.3\n"
      "references:\n  l_knee.current: {type: constant, value: 6.0}\n"
      "variants:\n  - name: still\n    robot: {base: fixed, base_pose: {xyz: [0, 0, 1.3]}}\n  - name: falling\n"
      "frames: {fps: 10, width: 480, height: 360, variant: falling, camera: {position: [2.2, -2.0, 1.2], look_at: [0, 0, 0.8]}}\n",
      1, 2);
}

TEST(ReplayBrowser, LegRigDroppingWhereItsFrameShowsIt) {
  expect_replay_shows_the_frame(
      "name: rig_drop\n"
      "robot: {name: leg_rig, base: fixed, contact: true, initial: {rail: 0.78, hip: -0.5, knee: 1.0, ankle: -0.5}}\n"
      "integration: {mode: fixed, step_s: 0.0005}\nduration_s: 0.3\nlog_rate_hz: 500\n"
      "frames: {fps: 10, width: 480, height: 360, camera: {position: [1.35, -1.25, 0.85], look_at: [0.0, 0.0, 0.4]}}\n",
      0, 2);
}

TEST(ReplayBrowser, AtlasFromItsCollisionShapesWhereItsFrameShowsIt) {
  if (!fs::exists(dmbd::test::atlas::kAtlasGz)) GTEST_SKIP() << dmbd::test::atlas::kAtlasGz << " is absent (simbody's docs)";
  TempDir dir;
  const std::string urdf = dir.file("atlas.urdf");
  ASSERT_TRUE(dmbd::test::atlas::decompress_atlas(urdf));
  expect_replay_shows_the_frame(
      "name: atlas_fall\n"
      "robot: {urdf: '" + urdf + "', base: floating, base_pose: {xyz: [0, 0, 1.2], rpy: [0, 0.3, 0.5]}}\n"
      "duration_s: 0.3\nlog_rate_hz: 200\n"
      "frames: {fps: 10, width: 480, height: 360, camera: {position: [3.0, -2.6, 1.4], look_at: [0, 0, 0.7]}}\n",
      0, 2);
}

// The whole page (three variants, two scenes) loads: the replay says it is ready, at the
// first sample of the frames' variant, with nothing on the console.
TEST(ReplayBrowser, ThePageLoadsWithoutConsoleMessages) {
  TempDir dir;
  write_text(dir.file("s.yaml"),
             "name: page\n"
             "robot: {name: draco, base: floating, base_pose: {xyz: [0, 0, 1.4]}, moving: [l_knee], actuators: [l_knee], initial: {l_knee: 1.0}}\n"
             "duration_s: 0.1\nreferences:\n  l_knee.current: {type: constant, value: 6.0}\n"
             "variants:\n  - name: a\n  - name: b\n    robot: {base: fixed, base_pose: {xyz: [0, 0, 1.3]}}\n  - name: c\n"
             "frames: {fps: 10, width: 320, height: 240, variant: b}\n");
  const std::string out = dir.file("out");
  const auto run = dmbd::scenario::run_scenario(dmbd::scenario::load_scenario(dir.file("s.yaml")), out);
  dmbd::report::write_report(run, out);
  const Browser b = chromium("file://" + out + "/report.html", dir.path().string(), "");
  EXPECT_EQ(b.console, "") << "console messages";
  EXPECT_NE(b.out.find("<section id=\"replay\" data-state=\"ready\" data-time=\"0.000000\">"), std::string::npos) << b.out.substr(0, 4000);
  EXPECT_NE(b.out.find("selected=\"\">b</option>"), std::string::npos) << "the frames' variant shown first";
  // A page whose data is missing says so (on the page and on the console): the check can fail.
  fs::remove(out + "/replay/variant_1.js");
  const Browser broken = chromium("file://" + out + "/report.html", dir.path().string(), "");
  EXPECT_NE(broken.out.find("data-state=\"error\""), std::string::npos);
  EXPECT_NE(broken.console.find("cannot load replay/variant_1.js"), std::string::npos) << broken.console;
}

}  // namespace
