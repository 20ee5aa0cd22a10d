// The command line on files that are not what it expects (issue 13, item 4, and build
// 2's limits): exit 2, the reason said (a directory, not text, a tab, a limit at its
// line), and never a control byte of the file on the terminal.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_support.hpp"

namespace {

namespace fs = std::filesystem;
using dmbd::cli_testing::run_dmbd;

class CliFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dmbd_cli_files_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& bytes) {
    std::ofstream(dir_ / name, std::ios::binary) << bytes;
    return (dir_ / name).string();
  }
  fs::path dir_;
};

bool printable(const std::string& s) {
  return std::all_of(s.begin(), s.end(), [](char c) { return c == '\n' || (static_cast<unsigned char>(c) >= 0x20 && c != 0x7f); });
}

TEST_F(CliFiles, ADirectoryGivenAsADiagramIsNamedAsOne) {
  const auto r = run_dmbd({"analyze", dir_.string(), "--from", "u", "--to", "y"}, dir_);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("it is a directory"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("expected a map"), std::string::npos) << r.err;
}

TEST_F(CliFiles, ABinaryFileIsNotTextAndNothingOfItIsPrinted) {
  const std::string bin = write("tool.yaml", std::string("\x7f" "ELF\x02\x01\x01\0\0\0\x1b[2J\x07", 15));
  for (const std::vector<std::string>& args : {std::vector<std::string>{"analyze", bin, "--from", "u", "--to", "y"},
                                               std::vector<std::string>{"simulate", bin, "--out", (dir_ / "out").string()}}) {
    const auto r = run_dmbd(args, dir_);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find("the file is not text"), std::string::npos) << r.err;
    EXPECT_TRUE(printable(r.err)) << "control bytes on stderr";
  }
}

TEST_F(CliFiles, TabsAndLimitsAreNamedAtTheirLine) {
  const std::string tabs = write("tabs.yaml", "name: s\nrobot:\n\tbase: fixed\n");
  auto r = run_dmbd({"simulate", tabs, "--out", (dir_ / "out").string()}, dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find(tabs + ":3:1: tabs are not allowed in YAML indentation"), std::string::npos) << r.err;
  const std::string long_run = write("long.yaml", "name: s\nduration_s: 1e12\n");
  r = run_dmbd({"simulate", long_run, "--out", (dir_ / "out").string()}, dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find(long_run + ":2:13: duration_s: 1e+12 s is too long"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

TEST_F(CliFiles, EveryProblemOfAScenarioIsALineOfItsOwn) {
  const std::string s = write("s.yaml", "name: s\nduration_s: 1e12\nlog_rate_hz: fast\nsensors: {seed: -1}\n");
  const auto r = run_dmbd({"simulate", s, "--out", (dir_ / "out").string()}, dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "dmbd: error: " + s + ":2:13: duration_s: 1e+12 s is too long (the simulation counts nanoseconds: below 1e9 s)\n" +
                       "dmbd: error: " + s + ":3:14: log_rate_hz: expected a number, got 'fast'\n" +
                       "dmbd: error: " + s + ":4:17: sensors.seed: expected a whole number from 0 to 9007199254740992\n");
}

}  // namespace
