// Temporary files an interrupted run must not leave (base/temporaries.hpp, issue 28 row
// 9): a registered path is unlinked on SIGINT and SIGTERM and the process still ends by
// the signal; an unregistered one stays; stale ones are swept.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>

#include "dmbd/base/temporaries.hpp"

namespace {

namespace fs = std::filesystem;

class Temporaries : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dmbd_temporaries_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path touch(const std::string& name) const {
    std::ofstream(dir_ / name) << "x";
    return dir_ / name;
  }
  fs::path dir_;
};

TEST_F(Temporaries, ARegisteredFileIsRemovedOnTheSignalWhichStillEndsTheProcess) {
  for (int sig : {SIGINT, SIGTERM}) {
    const fs::path tmp = touch("log.csv.tmp"), kept = touch("kept.tmp"), released = touch("released.tmp");
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      dmbd::remove_temporaries_on_signals();
      { const dmbd::TemporaryPath done(released.string()); }
      const dmbd::TemporaryPath t(tmp.string());
      std::raise(sig);
      ::_exit(0);  // not reached
    }
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << status;
    EXPECT_FALSE(fs::exists(tmp));
    EXPECT_TRUE(fs::exists(kept));
    EXPECT_TRUE(fs::exists(released));  // registered once, no longer
  }
}

TEST_F(Temporaries, StaleOnesAreSweptAndNothingElse) {
  for (const char* f : {"log.csv.tmp", "video.tmp.mp4", "log.csv", "video.mp4", "report.html", "tmp"}) touch(f);
  fs::create_directories(dir_ / "frames.tmp");
  dmbd::remove_stale_temporaries(dir_.string());
  EXPECT_FALSE(fs::exists(dir_ / "log.csv.tmp"));
  EXPECT_FALSE(fs::exists(dir_ / "video.tmp.mp4"));
  for (const char* f : {"log.csv", "video.mp4", "report.html", "tmp", "frames.tmp"}) EXPECT_TRUE(fs::exists(dir_ / f)) << f;
  dmbd::remove_stale_temporaries((dir_ / "no_such_folder").string());  // quietly nothing
}

}  // namespace
