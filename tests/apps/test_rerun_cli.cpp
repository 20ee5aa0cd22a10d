// Issue 28 row 9: a run directory written again never keeps a report that links files of
// the run before, and an interrupted run leaves no temporary file. A re-run loses
// report.html before it writes anything; SIGINT while the video is being encoded removes
// video.tmp.mp4 (and the process ends by the signal); what a kill -9 left (*.tmp,
// video.tmp.mp4) is swept by the next run or `dmbd report`.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_support.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using dmbd::cli_testing::run_dmbd;
using dmbd::cli_testing::slurp;

const std::string kScenario = std::string(DMBD_SOURCE_DIR) + "/examples/scenarios/position_controllers.yaml";

class Rerun : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dmbd_rerun_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // A first complete run with frames and video into dir/run.
  void first_run() const {
    const auto r = run_dmbd({"simulate", kScenario, "--out", (dir_ / "run").string(), "--duration", "0.4"}, dir_);
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_TRUE(fs::exists(dir_ / "run/report.html"));
    ASSERT_TRUE(fs::exists(dir_ / "run/video.mp4"));
  }
  // What a kill -9 leaves behind.
  void plant_stale_temporaries() const {
    for (const char* f : {"video.tmp.mp4", "log.csv.tmp", "metrics.json.tmp", "plots/current.png.tmp"})
      std::ofstream(dir_ / "run" / f) << "stale";
  }
  void expect_no_temporaries() const {
    for (const char* f : {"video.tmp.mp4", "log.csv.tmp", "metrics.json.tmp", "report.html.tmp", "plots/current.png.tmp"})
      EXPECT_FALSE(fs::exists(dir_ / "run" / f)) << f;
  }
  fs::path dir_;
};

// The scenario with a plot of a signal no variant logs: the run fails after log.csv.
std::string failing_scenario() {
  std::string text = slurp(kScenario);
  for (std::string::size_type p; (p = text.find("../diagrams/")) != std::string::npos;)
    text.replace(p, 12, std::string(DMBD_SOURCE_DIR) + "/examples/diagrams/");
  return text + "  - {title: Missing, y_label: x, file: missing.png, signals: [l_knee.no_such_signal]}\n";
}

TEST_F(Rerun, ARunThatFailsAfterItsLogLeavesNoEarlierReportAndNoTemporaries) {
  first_run();
  plant_stale_temporaries();
  const fs::path bad = dir_ / "bad.yaml";
  std::ofstream(bad) << failing_scenario();
  const auto r = run_dmbd({"simulate", bad.string(), "--out", (dir_ / "run").string(), "--duration", "0.2"}, dir_);
  ASSERT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("logged no signal 'l_knee.no_such_signal'"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "run/log.csv"));         // the new log, there to look at
  EXPECT_FALSE(fs::exists(dir_ / "run/report.html"));    // not the old page beside it
  expect_no_temporaries();
}

TEST_F(Rerun, ReportSweepsWhatAKilledRunLeft) {
  first_run();
  plant_stale_temporaries();
  const auto r = run_dmbd({"report", (dir_ / "run").string(), "--no-frames"}, dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  expect_no_temporaries();
  EXPECT_TRUE(fs::exists(dir_ / "run/report.html"));
  EXPECT_FALSE(fs::exists(dir_ / "run/video.mp4"));  // --no-frames: no video the page could link
}

// Starts dmbd with `args`, output to /dev/null; its pid.
pid_t start_dmbd(const std::vector<std::string>& args) {
  std::vector<std::string> words{DMBD_EXE};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = -1;
  const int err = posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  return err == 0 ? pid : -1;
}

TEST_F(Rerun, SigintWhileTheVideoIsWrittenRemovesItsTemporaryFile) {
  first_run();
  for (int sig : {SIGINT, SIGTERM}) {
    SCOPED_TRACE(sig);
    const pid_t pid = start_dmbd({"simulate", kScenario, "--out", (dir_ / "run").string(), "--duration", "8"});
    ASSERT_GT(pid, 0);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (!fs::exists(dir_ / "run/video.tmp.mp4") && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    const bool writing = fs::exists(dir_ / "run/video.tmp.mp4");
    ::kill(pid, sig);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(writing) << "the video was never begun";
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << status;
    EXPECT_FALSE(fs::exists(dir_ / "run/video.tmp.mp4"));
    EXPECT_FALSE(fs::exists(dir_ / "run/report.html"));  // the old page went before the new log came
    EXPECT_TRUE(fs::exists(dir_ / "run/log.csv"));
  }
}

}  // namespace
