// Reports drawn from runs (dmbd::report): frames from the logged poses show the robot
// moving; a report redrawn from the run directory (sim::read_run, `dmbd report`) is the
// one drawn straight after the simulation, pixel for pixel; the files listed are the
// files written, nothing else is left behind, stale frames are removed.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "../sim/sim_test_support.hpp"
#include "dmbd/report/report.hpp"
#include "dmbd/sim/run_directory.hpp"
#include "dmbd/viz/renderer.hpp"

namespace {

namespace fs = std::filesystem;
using dmbd::sim::load_scenario;
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
                                 "robot: {base: fixed, base_pose: {xyz: [0, 0, 1.3]}, moving: [l_knee], actuators: [l_knee], "
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
    const auto run = dmbd::sim::run_scenario(scenario(locked), out);
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
  EXPECT_TRUE(fs::exists(b + "/video.mp4"));
}

// The report's files are what it lists (no temporary left), and a second report into the
// same folder with fewer frames leaves none of the first's behind.
TEST(ReportFiles, ListedFilesOnlyAndNoStaleFrames) {
  TempDir dir;
  const std::string path = dir.file("s.yaml");
  write_text(path, "name: hold\nrobot: {base: fixed, base_pose: {xyz: [0, 0, 1.3]}, moving: [l_knee], actuators: [l_knee], "
                   "initial: {l_knee: 1.0}}\nduration_s: 0.2\nreferences:\n  l_knee.current: {type: constant, value: 2.0}\n"
                   "frames: {fps: 20, width: 160, height: 120}\n"
                   "plots:\n  - {title: Knee, y_label: rad, file: knee.png, signals: [l_knee.q]}\n");
  const std::string out = dir.file("out");
  const auto run = dmbd::sim::run_scenario(load_scenario(path), out);
  const auto first = dmbd::report::write_report(run, out);
  EXPECT_EQ(first.frames, 5);  // 0, 50, ..., 200 ms
  std::vector<std::string> listed = run.files;
  listed.insert(listed.end(), first.files.begin(), first.files.end());
  for (const auto& e : fs::recursive_directory_iterator(out)) {
    if (e.is_directory()) continue;
    const std::string rel = fs::relative(e.path(), out).string();
    EXPECT_NE(std::find(listed.begin(), listed.end(), rel), listed.end()) << "unlisted file " << rel;
  }
  dmbd::report::ReportOptions none;
  none.frames = false;
  const auto second = dmbd::report::write_report(run, out, none);
  EXPECT_EQ(second.frames, 0);
  EXPECT_FALSE(fs::exists(out + "/frames"));
  EXPECT_FALSE(fs::exists(out + "/video.mp4"));
  EXPECT_EQ(read_text(out + "/report.html").find("frames/"), std::string::npos);
}

}  // namespace
