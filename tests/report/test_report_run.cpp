// Reports drawn from runs (dmbd::report): frames from the logged poses show the robot
// moving, a fixed base on a table, the operational space controller's desired and
// measured paths when they were logged; a report redrawn from the run directory (scenario::read_run, `dmbd report`) is the
// one drawn straight after the simulation, pixel for pixel (and its 3-D replay's data byte
// for byte); the files listed are the files written, every file the page refers to is
// there, nothing else is left behind, stale frames are removed.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "dmbd/control/balance_controller.hpp"
#include "dmbd/control/osc_controller.hpp"
#include "sim_test_support.hpp"
#include "dmbd/report/report.hpp"
#include "dmbd/scenario/run_directory.hpp"
#include "dmbd/viz/renderer.hpp"

namespace {

namespace fs = std::filesystem;
using dmbd::scenario::load_scenario;
using dmbd::sim::test::read_text;
using dmbd::sim::test::TempDir;
using dmbd::sim::test::write_text;

const std::string kSourceDir = DMBD_SOURCE_DIR;

// Frames drawn from a run's log show the robot and it moves between them. The knee is
// driven by a constant 6 A (no controller) for 0.3 s, frames at 10/s from a fixed
// camera, 320 x 240. "Shows the robot": the pixels that differ from the same camera's
// view of the empty scene (ground, grid, sky). "Moves": the first and the last frame
// differ, where a run with the knee locked gives (all but) identical frames. The
// overlay's text panel (top rows, with the time) is left out of both measures.
TEST(ReportFrames, FramesShowTheRobotMoving) {
  TempDir dir;
  auto scenario = [&](bool locked) {
    const std::string path = dir.file(locked ? "still.yaml" : "swing.yaml");
    write_text(path, std::string("name: swing\n"
                                 "robot: {name: draco, base: fixed, base_pose: {xyz: [0, 0, 1.3]}, moving: [l_knee], actuators: [l_knee], "
                                 "initial: {l_knee: 1.0}") +
                         (locked ? ", lock: {l_knee: 1.0}" : "") +
                         "}\n"
                         "duration_s: 0.3\n"
                         "references:\n"
                         "  l_knee.current: {type: constant, value: 6.0}\n"
                         "frames: {fps: 10, width: 320, height: 240, camera: {position: [1.6, -1.6, 1.0], look_at: [0, 0, 0.8]}}\n");
    return load_scenario(path);
  };
  const int text_rows = 60;  // the overlay's text panel: two lines at the top
  auto differing = [&](const cv::Mat& a, const cv::Mat& b) {
    cv::Mat d;
    cv::absdiff(a.rowRange(text_rows, a.rows), b.rowRange(text_rows, b.rows), d);
    std::vector<cv::Mat> ch;
    cv::split(d, ch);
    cv::Mat m = cv::max(cv::max(ch[0], ch[1]), ch[2]) > 30;
    return static_cast<double>(cv::countNonZero(m)) / static_cast<double>(a.total());
  };
  dmbd::viz::Camera camera;
  camera.position = {1.6, -1.6, 1.0};
  camera.look_at = {0, 0, 0.8};
  camera.width_px = 320;
  camera.height_px = 240;
  dmbd::viz::Renderer empty(320, 240);
  empty.set_scene(dmbd::viz::Scene{});
  const cv::Mat background = empty.render({}, camera, {}).clone();

  double moved_fraction[2] = {0, 0};
  for (bool locked : {false, true}) {
    SCOPED_TRACE(locked ? "knee locked" : "knee driven");
    const std::string out = dir.file(locked ? "still" : "swing");
    const auto run = dmbd::scenario::run_scenario(scenario(locked), out);
    const auto r = dmbd::report::write_report(run, out);
    ASSERT_EQ(r.frames, 4);  // t = 0, 0.1, 0.2, 0.3 s
    EXPECT_TRUE(fs::exists(out + "/video.mp4"));
    std::vector<cv::Mat> frames;
    for (int k = 0; k < 4; ++k) {
      frames.push_back(cv::imread(out + "/frames/frame_0000" + std::to_string(k) + ".png", cv::IMREAD_COLOR));
      ASSERT_FALSE(frames.back().empty()) << "frame " << k;
      ASSERT_EQ(frames.back().size(), cv::Size(320, 240));
      // DRACO (1.3 m tall, 1.6-2.3 m from the camera) covers several % of the picture.
      EXPECT_GT(differing(frames.back(), background), 0.03) << "frame " << k << " hardly differs from the empty scene";
    }
    const auto& q = run.runs[0].log.column("l_knee.q");
    if (!locked) {
      EXPECT_GT(std::abs(q.back() - q.front()), 0.1) << "the knee did not swing";
    }
    moved_fraction[locked] = differing(frames.front(), frames.back());
  }
  std::printf("pixels changed between the first and last frame: driven %.4f, locked %.4f\n", moved_fraction[0], moved_fraction[1]);
  EXPECT_GT(moved_fraction[0], 0.005);
  EXPECT_LT(moved_fraction[1], 0.001);
}

// ---------------------------------------------------------------------------------
// Tables and paths in the frames. DRACO with its torso at 1.3 m, fixed or floating,
// the knee driven for 0.1 s, seen from a fixed camera at 640 x 360 (frames at t = 0,
// 0.1 s).

const Eigen::Vector3d kCameraPosition(1.6, -1.6, 1.0), kCameraLookAt(0, 0, 0.8);

dmbd::scenario::ScenarioRun short_run(const TempDir& dir, const std::string& name, bool fixed) {
  const std::string path = dir.file(name + ".yaml");
  write_text(path, "name: " + name + "\n" +
                       "robot: {name: draco, base: " + (fixed ? "fixed" : "floating") +
                       ", base_pose: {xyz: [0, 0, 1.3]}, moving: [l_knee], actuators: [l_knee], initial: {l_knee: 1.0}}\n"
                       "duration_s: 0.1\n"
                       "references:\n"
                       "  l_knee.current: {type: constant, value: 2.0}\n"
                       "frames: {fps: 10, width: 640, height: 360, camera: {position: [1.6, -1.6, 1.0], look_at: [0, 0, 0.8]}}\n");
  return dmbd::scenario::run_scenario(load_scenario(path), dir.file(name));
}

dmbd::viz::Camera test_camera() {
  dmbd::viz::Camera c;
  c.position = kCameraPosition;
  c.look_at = kCameraLookAt;
  c.width_px = 640;
  c.height_px = 360;
  return c;
}

// The table's wood, as shaded: hue 30-44 deg (the top's colour, sRGB (199, 163, 107),
// is at 36 deg; DRACO's orange actuators are at 26 deg and stay there when their edges
// blend into grey), saturation 0.25-0.65 (the orange's is 0.9), not dark.
cv::Mat table_coloured(const cv::Mat& bgr) {
  cv::Mat hsv;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);  // H in [0, 180)
  cv::Mat m;
  cv::inRange(hsv, cv::Scalar(15, 64, 50), cv::Scalar(22, 166, 255), m);
  return m;
}

// A fixed base is drawn on a table: the first frame has many wood-coloured pixels, and
// they lie under the torso in the picture (below the base origin's projection, down to
// where the ground is), where the floating robot's frame, the same robot from the same
// camera without the table, has none.
TEST(ReportFrames, FixedBaseStandsOnATableFloatingBaseDoesNot) {
  TempDir dir;
  const dmbd::viz::Camera cam = test_camera();
  const Eigen::Vector2d torso = *dmbd::viz::project(cam, Eigen::Vector3d(0, 0, 1.3));
  const Eigen::Vector2d low = *dmbd::viz::project(cam, Eigen::Vector3d(0, 0, 0.4));
  for (bool fixed : {true, false}) {
    SCOPED_TRACE(fixed ? "fixed base" : "floating base");
    const std::string name = fixed ? "fixed" : "floating";
    const auto run = short_run(dir, name, fixed);
    ASSERT_EQ(dmbd::report::write_report(run, dir.file(name)).frames, 2);
    const cv::Mat frame = cv::imread(dir.file(name) + "/frames/frame_00000.png", cv::IMREAD_COLOR);
    ASSERT_EQ(frame.size(), cv::Size(640, 360));
    const cv::Mat wood = table_coloured(frame);
    const int n = cv::countNonZero(wood);
    if (!fixed) {
      EXPECT_EQ(n, 0);
      continue;
    }
    EXPECT_GT(n, 0.02 * 640 * 360);
    const cv::Moments m = cv::moments(wood, true);
    EXPECT_GT(m.m01 / m.m00, torso.y()) << "the table's centroid is not below the torso";
    const cv::Rect box = cv::boundingRect(wood);
    EXPECT_LT(box.y, torso.y() + 20) << "the table top is not up at the torso";
    EXPECT_GT(box.y + box.height, low.y()) << "the table's legs do not go down";
    // Wood right under the torso's projection (within 100 px of its column).
    EXPECT_GT(cv::countNonZero(wood(cv::Rect(int(torso.x()) - 100, int(torso.y()), 200, 360 - int(torso.y())))), 500);
  }
}

// The balancing controller's overlays: the planned foothold, marked on the ground in
// orange ((255, 140, 0)) around the logged point, and the phase by its name as a third
// line of the frame's text panel (the panel one text line taller). The columns are added
// to a real run's log (a foothold at (-0.2, 0.5), phase 4: swing).
TEST(ReportFrames, TheBalancingControllersFootholdAndPhase) {
  TempDir dir;
  auto run = short_run(dir, "bal", true);
  const auto plain_page = dmbd::report::write_report(run, dir.file("bal"));
  ASSERT_EQ(plain_page.frames, 2);
  const cv::Mat plain = cv::imread(dir.file("bal") + "/frames/frame_00001.png", cv::IMREAD_COLOR);
  for (auto& v : run.scenario.variants) v.bus_controllers.push_back(std::make_shared<dmbd::control::BalanceSetup>());
  const dmbd::sim::Log& old = run.runs[0].log;
  dmbd::sim::Log log;
  for (std::size_t c = 1; c < old.columns(); ++c) log.add_column(old.name(int(c)), old.unit(int(c)));
  const int phase = log.add_column("balance.phase", "");
  const int fx = log.add_column("balance.foothold_x", "m");
  log.add_column("balance.foothold_y", "m");
  for (std::size_t r = 0; r < old.rows(); ++r) {
    log.begin_row(old.time()[r]);
    for (std::size_t c = 1; c < old.columns(); ++c) log.set(int(c), old.column(int(c))[r]);
    log.set(phase, 4.0);
    log.set(fx, -0.2);
    log.set(fx + 1, 0.5);
  }
  run.runs[0].log = log;
  ASSERT_EQ(dmbd::report::write_report(run, dir.file("bal")).frames, 2);
  const cv::Mat frame = cv::imread(dir.file("bal") + "/frames/frame_00001.png", cv::IMREAD_COLOR);
  const dmbd::viz::Camera cam = test_camera();
  const cv::Vec3b orange(0, 140, 255);  // BGR
  int on_ring = 0;
  for (int i = 0; i < 36; ++i) {
    const double a = 2 * M_PI * i / 36;
    const Eigen::Vector2d uv = *dmbd::viz::project(cam, Eigen::Vector3d(-0.2 + 0.06 * std::cos(a), 0.5 + 0.06 * std::sin(a), 0));
    ASSERT_TRUE(uv.x() > 2 && uv.x() < 637 && uv.y() > 2 && uv.y() < 357) << uv.transpose();
    bool hit = false;
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc) hit = hit || frame.at<cv::Vec3b>(int(uv.y()) + dr, int(uv.x()) + dc) == orange;
    on_ring += hit;
  }
  EXPECT_GT(on_ring, 30);  // the ring's 6 cm around the foothold (the robot may hide a few points)
  // The text panel (top-left, the sky darkened to 45 % behind it): one line taller with
  // the phase.
  const auto panel_rows = [](const cv::Mat& img) {
    int rows = 0;
    for (int r = 0; r < img.rows / 3; ++r) rows += img.at<cv::Vec3b>(r, 10)[1] < 130;
    return rows;
  };
  EXPECT_GT(panel_rows(frame), panel_rows(plain) + 10) << panel_rows(frame) << " vs " << panel_rows(plain);
}

// A log with the operational space controller's six columns (osc.x_d ... osc.z) gets
// the desired (dashed, (0, 190, 255)) and measured (solid, (255, 40, 200)) paths: the
// paths' colours along the projections of the logged points, in the picture away
// from the legend; the same log without those columns has neither colour anywhere.
// The columns are added to a real run's log: circles in the plane y = 0 in front of
// the robot, centred 0.35 m ahead at 0.7 m up, the desired one of 0.15 m radius and the
// measured one of 0.09 m, once round in the run's 0.1 s.
TEST(ReportFrames, OscPathsInTheirColours) {
  TempDir dir;
  auto run = short_run(dir, "osc", true);
  // The scenario's operational space controller declares the two paths (its overlays).
  for (auto& v : run.scenario.variants) v.bus_controllers.push_back(std::make_shared<dmbd::control::OscSetup>());
  const dmbd::sim::Log& old = run.runs[0].log;
  const Eigen::Vector3d centre(0.35, 0, 0.7);
  const auto point = [&](double t, double radius) {
    const double a = 2 * M_PI * t / 0.1;
    return Eigen::Vector3d(centre + radius * Eigen::Vector3d(std::cos(a), 0, std::sin(a)));
  };
  dmbd::sim::Log log;
  for (std::size_t c = 1; c < old.columns(); ++c) log.add_column(old.name(int(c)), old.unit(int(c)));
  const int osc = log.add_column("osc.x_d", "m");
  for (const char* n : {"osc.y_d", "osc.z_d", "osc.x", "osc.y", "osc.z"}) log.add_column(n, "m");
  for (std::size_t r = 0; r < old.rows(); ++r) {
    const double t = old.time()[r];
    log.begin_row(t);
    for (std::size_t c = 1; c < old.columns(); ++c) log.set(int(c), old.column(int(c))[r]);
    const Eigen::Vector3d d = point(t, 0.15), m = point(t, 0.09);
    for (int k = 0; k < 3; ++k) {
      log.set(osc + k, d[k]);
      log.set(osc + 3 + k, m[k]);
    }
  }
  const cv::Vec3b desired(255, 190, 0), measured(200, 40, 255);  // BGR
  const auto count = [](const cv::Mat& img, const cv::Vec3b& c) {
    int n = 0;
    for (int r = 0; r < img.rows; ++r)
      for (int k = 0; k < img.cols; ++k) n += img.at<cv::Vec3b>(r, k) == c;
    return n;
  };
  // Without the columns: neither colour.
  ASSERT_EQ(dmbd::report::write_report(run, dir.file("osc")).frames, 2);
  const cv::Mat plain = cv::imread(dir.file("osc") + "/frames/frame_00001.png", cv::IMREAD_COLOR);
  EXPECT_EQ(count(plain, desired), 0);
  EXPECT_EQ(count(plain, measured), 0);

  run.runs[0].log = log;
  ASSERT_EQ(dmbd::report::write_report(run, dir.file("osc")).frames, 2);
  const cv::Mat frame = cv::imread(dir.file("osc") + "/frames/frame_00001.png", cv::IMREAD_COLOR);  // t = 0.1 s
  // Walking round each circle in 360 steps (under 1 px each), the path's colour within
  // 1 px: all the way round the measured one; on and off round the desired one, the
  // dashes (10 px on, 8 px off) turning on and off about twice per 18 px.
  const dmbd::viz::Camera cam = test_camera();
  const auto near = [&](const Eigen::Vector3d& p, const cv::Vec3b& c) {
    const Eigen::Vector2d uv = *dmbd::viz::project(cam, p);
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc)
        if (frame.at<cv::Vec3b>(int(uv.y()) + dr, int(uv.x()) + dc) == c) return true;
    return false;
  };
  int on_desired = 0, on_measured = 0, switches = 0;
  double circumference_px = 0;
  bool prev = near(point(0, 0.15), desired);
  for (int i = 0; i < 360; ++i) {
    const double t = 0.1 * i / 360;
    const bool d = near(point(t, 0.15), desired);
    on_desired += d;
    switches += d != prev;
    prev = d;
    on_measured += near(point(t, 0.09), measured);
    circumference_px +=
        (*dmbd::viz::project(cam, point(t + 0.1 / 360, 0.15)) - *dmbd::viz::project(cam, point(t, 0.15))).norm();
  }
  EXPECT_GE(on_measured, 355);
  EXPECT_GT(on_desired, 0.35 * 360);
  EXPECT_LT(on_desired, 0.85 * 360);
  EXPECT_GT(switches, 0.5 * 2 * circumference_px / 18);
  EXPECT_LT(switches, 1.5 * 2 * circumference_px / 18);
}


// Every PNG under `a` (plots, frames) decodes to the same pixels as its namesake under b.
void expect_same_images(const std::string& a, const std::string& b) {
  int compared = 0;
  for (const auto& e : fs::recursive_directory_iterator(a)) {
    if (e.path().extension() != ".png") continue;
    const fs::path rel = fs::relative(e.path(), a);
    const cv::Mat x = cv::imread(e.path().string(), cv::IMREAD_UNCHANGED), y = cv::imread((fs::path(b) / rel).string(), cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(y.empty()) << rel << " missing from the redrawn report";
    ASSERT_EQ(x.size(), y.size()) << rel;
    cv::Mat d;
    cv::absdiff(x, y, d);
    EXPECT_EQ(cv::countNonZero(d.reshape(1)), 0) << rel << " differs";
    ++compared;
  }
  EXPECT_GT(compared, 0);
}

// The dmbd binary of the same build: <build>/apps/dmbd, the test being <build>/tests/report/NAME.
fs::path dmbd_binary() { return fs::read_symlink("/proc/self/exe").parent_path().parent_path().parent_path() / "apps" / "dmbd"; }

int run_dmbd(const std::string& args) {
  const int rc = std::system(("'" + dmbd_binary().string() + "' " + args + " > /dev/null 2>&1 < /dev/null").c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

// Issue 13: `dmbd report` redraws a shipped scenario's plots (and frames) from its run
// directory pixel-identical to what `dmbd simulate` wrote. position_controllers for 1 s:
// its three variants, the step plots, 30 frames of the encoder variant.
TEST(ReportRedraw, DmbdReportRedrawsTheShippedScenarioPixelForPixel) {
  if (!fs::exists(dmbd_binary())) GTEST_SKIP() << dmbd_binary() << " is not built (target dmbd)";
  TempDir dir;
  const std::string a = dir.file("simulated"), b = dir.file("redrawn");
  ASSERT_EQ(run_dmbd("simulate '" + kSourceDir + "/examples/scenarios/position_controllers.yaml' --out '" + a + "' --duration 1"), 0);
  fs::create_directories(b);
  for (const char* f : {"log.csv", "metrics.json"}) fs::copy_file(fs::path(a) / f, fs::path(b) / f);
  ASSERT_EQ(run_dmbd("report '" + b + "'"), 0);
  expect_same_images(a, b);
  EXPECT_EQ(read_text(a + "/report.html"), read_text(b + "/report.html"));
  // The replay's data, byte for byte (the log read back is the log written).
  int replayed = 0;
  for (const auto& e : fs::directory_iterator(fs::path(a) / "replay")) {
    EXPECT_EQ(read_text(e.path().string()), read_text((fs::path(b) / "replay" / e.path().filename()).string())) << e.path().filename();
    ++replayed;
  }
  EXPECT_EQ(replayed, 3 + 1 + 3) << "three.js, its controls and licence, one scene, three variants";
  EXPECT_TRUE(fs::exists(b + "/video.mp4"));
}

// Every file report.html refers to (src, href, poster, and the replay's data-track and
// data-scene), percent-decoded and relative to the directory; and the references found.
std::vector<std::string> page_references(const std::string& dir) {
  const std::string html = read_text(dir + "/report.html");
  std::vector<std::string> refs;
  const std::regex attr(R"re(\b(?:src|href|poster|data-track|data-scene)="([^"]*)")re");
  for (auto it = std::sregex_iterator(html.begin(), html.end(), attr); it != std::sregex_iterator(); ++it) {
    const std::string url = (*it)[1];
    std::string path;
    for (std::size_t i = 0; i < url.size(); ++i)
      if (url[i] == '%' && i + 2 < url.size()) {
        path += static_cast<char>(std::stoi(url.substr(i + 1, 2), nullptr, 16));
        i += 2;
      } else {
        path += url[i];
      }
    refs.push_back(path);
  }
  return refs;
}

// Every reference of the page is a file in the directory, and every file of replay/ is
// referred to by the page (the scripts, the data, the licence).
void expect_links_resolve(const std::string& dir) {
  const std::vector<std::string> refs = page_references(dir);
  for (const auto& r : refs) EXPECT_TRUE(fs::is_regular_file(fs::path(dir) / r)) << "report.html refers to a missing file: " << r;
  ASSERT_TRUE(fs::is_directory(fs::path(dir) / "replay"));
  for (const auto& e : fs::directory_iterator(fs::path(dir) / "replay")) {
    const std::string rel = "replay/" + e.path().filename().string();
    EXPECT_NE(std::find(refs.begin(), refs.end(), rel), refs.end()) << rel << " is not referred to by report.html";
  }
}

// The report's files are what it lists (no temporary left), every file the page refers to
// is there, and a second report into the same folder with fewer frames leaves none of the
// first's behind; the replay is written with or without frames.
TEST(ReportFiles, ListedFilesOnlyAndNoStaleFrames) {
  TempDir dir;
  const std::string path = dir.file("s.yaml");
  write_text(path, "name: hold\nrobot: {name: draco, base: fixed, base_pose: {xyz: [0, 0, 1.3]}, moving: [l_knee], actuators: [l_knee], "
                   "initial: {l_knee: 1.0}}\nduration_s: 0.2\nreferences:\n  l_knee.current: {type: constant, value: 2.0}\n"
                   "frames: {fps: 20, width: 160, height: 120}\n"
                   "plots:\n  - {title: Knee, y_label: rad, file: knee.png, signals: [l_knee.q]}\n");
  const std::string out = dir.file("out");
  const auto run = dmbd::scenario::run_scenario(load_scenario(path), out);
  const auto first = dmbd::report::write_report(run, out);
  EXPECT_EQ(first.frames, 5);  // 0, 50, ..., 200 ms
  std::vector<std::string> listed = run.files;
  listed.insert(listed.end(), first.files.begin(), first.files.end());
  for (const auto& e : fs::recursive_directory_iterator(out)) {
    if (e.is_directory()) continue;
    const std::string rel = fs::relative(e.path(), out).string();
    EXPECT_NE(std::find(listed.begin(), listed.end(), rel), listed.end()) << "unlisted file " << rel;
  }
  expect_links_resolve(out);
  EXPECT_EQ(first.replay_variants, 1);
  dmbd::report::ReportOptions none;
  none.frames = false;
  const auto second = dmbd::report::write_report(run, out, none);
  EXPECT_EQ(second.frames, 0);
  EXPECT_FALSE(fs::exists(out + "/frames"));
  EXPECT_FALSE(fs::exists(out + "/video.mp4"));
  EXPECT_EQ(read_text(out + "/report.html").find("frames/"), std::string::npos);
  EXPECT_EQ(second.replay_variants, 1);
  expect_links_resolve(out);
}

}  // namespace
