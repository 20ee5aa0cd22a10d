// The frames' writers run on their own threads (report/src/frames.cpp): an error there
// reaches the caller as it was thrown (its type and message, which the command line
// turns into its one line and exit code), without a hang, and leaves no temporary file.
// Here the video cannot be opened: its temporary path is a folder that cannot be
// removed. (A full disk, the PNG writer's OutputError, was checked by hand on a 6 MB
// tmpfs: the same line and exit code 2 as before the threads.)
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "dmbd/report/report.hpp"
#include "dmbd/scenario/run_directory.hpp"
#include "sim_test_support.hpp"

namespace {

namespace fs = std::filesystem;
using dmbd::scenario::load_scenario;
using dmbd::sim::test::TempDir;
using dmbd::sim::test::write_text;

TEST(ReportFrames, AWriterThreadsErrorReachesTheCallerAsThrown) {
  TempDir dir;
  const std::string path = dir.file("s.yaml");
  write_text(path, "name: hold\nrobot: {name: draco, base: fixed, base_pose: {xyz: [0, 0, 1.3]}, moving: [l_knee], actuators: [l_knee], "
                   "initial: {l_knee: 1.0}}\nduration_s: 0.5\nreferences:\n  l_knee.current: {type: constant, value: 2.0}\n"
                   "frames: {fps: 20, width: 160, height: 120}\n");
  const std::string out = dir.file("out");
  const auto run = dmbd::scenario::run_scenario(load_scenario(path), out);
  fs::create_directories(fs::path(out) / "video.tmp.mp4" / "in_the_way");
  try {
    dmbd::report::write_report(run, out);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot write video '" + out + "/video.mp4'"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(fs::path(out) / "video.mp4"));
  for (const auto& e : fs::recursive_directory_iterator(fs::path(out) / "frames"))
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
  // Drawn again with the way clear: every frame and the video.
  fs::remove_all(fs::path(out) / "video.tmp.mp4");
  const auto r = dmbd::report::write_report(run, out);
  EXPECT_EQ(r.frames, 11);
  EXPECT_TRUE(fs::exists(fs::path(out) / "video.mp4"));
  for (int k = 0; k < r.frames; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05d.png", k);
    EXPECT_TRUE(fs::exists(fs::path(out) / "frames" / name)) << name;
  }
}

}  // namespace
