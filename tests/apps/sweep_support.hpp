#pragma once
// What the sweep tests share (docs/sweeps.md, "What is equal, and what is not"): the
// 16-run scenario, a scratch folder, running a shell command in a folder, and the
// comparison of a run directory with the single process's. DMBD_SOURCE_DIR is set by
// tests/apps/CMakeLists.txt.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "cli_support.hpp"

namespace dmbd::sweep_testing {

namespace fs = std::filesystem;

// A 4 x 4 matrix of 0.3 s runs (force_dob's force loop, with and without the observer, two
// noise levels, four loads).
inline const std::string kScenario = std::string(DMBD_SOURCE_DIR) + "/tests/apps/data/sweep16.yaml";

// A fresh folder per test, removed afterwards.
class Scratch {
 public:
  explicit Scratch(const std::string& name) : dir_(fs::temp_directory_path() / ("dmbd_sweep_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  ~Scratch() { fs::remove_all(dir_); }
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
  const fs::path& dir() const { return dir_; }

 private:
  fs::path dir_;
};

// metrics.json without what depends on the machine's speed: each run's wall_s and
// real_time_factor (wall-clock measurements, different in every run), and scenario_file
// (the absolute path of the scenario: a plan runs its own copy), checked separately.
inline nlohmann::json comparable_metrics(const fs::path& dir) {
  nlohmann::json m = nlohmann::json::parse(cli_testing::slurp(dir / "metrics.json"));
  for (auto& [name, run] : m["runs"].items()) {
    EXPECT_TRUE(run.contains("wall_s")) << name;
    run.erase("wall_s");
    run.erase("real_time_factor");
  }
  m.erase("scenario_file");
  return m;
}

// The two run directories of kScenario hold the same results.
inline void expect_same_run(const fs::path& a, const fs::path& b) {
  using cli_testing::slurp;
  const std::string log = slurp(a / "log.csv");
  EXPECT_GT(log.size(), 100000u);
  EXPECT_TRUE(log == slurp(b / "log.csv")) << a << " and " << b << ": log.csv differ";
  const nlohmann::json ma = comparable_metrics(a), mb = comparable_metrics(b);
  EXPECT_EQ(ma["runs"].size(), 16u);
  EXPECT_EQ(ma["rms_error_N"].size(), 4u) << ma.dump();  // the experiment's metrics: per controller, per load
  EXPECT_EQ(ma, mb) << a << " and " << b << ": metrics.json differ";
  for (const char* png : {"plots/force_tracking.png", "plots/force_error.png"})
    EXPECT_TRUE(slurp(a / png) == slurp(b / png) && !slurp(a / png).empty()) << png;
}

// Runs a shell command in `cwd`; its exit status.
inline int shell(const std::string& command, const fs::path& cwd) {
  const int status = std::system(("cd " + cli_testing::quote(cwd.string()) + " && " + command + " >/dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

}  // namespace dmbd::sweep_testing
