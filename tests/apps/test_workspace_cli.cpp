// `dmbd model workspace`: DRACO's foot workspace (the files, the summary, the JSON
// against the URDF's limits), the same seed giving the same JSON and another seed the
// same extents within the sample count's tolerance, a continuous joint sampled over
// [-pi, pi], and mistakes: exit 2, one line on stderr naming what was wrong.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using dmbd::cli_testing::Result;
using dmbd::cli_testing::slurp;

class WorkspaceCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("dmbd_workspace_cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
            "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "work");
  }
  void TearDown() override { fs::remove_all(dir_); }

  // DRACO's (--robot draco) unless the arguments name a URDF.
  Result run(std::vector<std::string> args) {
    if (std::none_of(args.begin(), args.end(), [](const std::string& a) { return a.size() > 5 && a.rfind(".urdf") == a.size() - 5; }))
      args.insert(args.begin(), {"--robot", "draco"});
    args.insert(args.begin(), {"model", "workspace"});
    return dmbd::cli_testing::run_dmbd(args, dir_, dir_ / "work");
  }
  nlohmann::json json_of(const std::string& out) { return nlohmann::json::parse(slurp(dir_ / out / "workspace.json")); }

  // Exit 2, one line on stderr starting "dmbd: error: " and holding `fragment`, nothing
  // on stdout, nothing written in the working folder.
  void expect_bad(const std::vector<std::string>& args, const std::string& fragment) {
    const Result r = run(args);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind("dmbd: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(fragment), std::string::npos) << "missing '" << fragment << "' in: " << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_TRUE(fs::is_empty(dir_ / "work"));
  }

  fs::path dir_;
};

bool is_png(const fs::path& p) { return slurp(p).rfind("\x89PNG\r\n\x1a\n", 0) == 0; }

TEST_F(WorkspaceCli, DracoFootWritesTheMapsTheFigureAndTheJsonWithTheUrdfLimits) {
  const Result r = run({"--link", "l_foot", "--out", "ws", "--samples", "20000", "--seed", "5"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  for (const char* f : {"workspace_xz.png", "workspace_yz.png", "range_of_motion.png", "workspace.json"}) {
    EXPECT_NE(r.out.find("wrote ws/" + std::string(f) + "\n"), std::string::npos) << f << " in\n" << r.out;
    EXPECT_TRUE(fs::exists(dir_ / "work/ws" / f)) << f;
  }
  for (const char* f : {"workspace_xz.png", "workspace_yz.png", "range_of_motion.png"})
    EXPECT_TRUE(is_png(dir_ / "work/ws" / f)) << f;
  EXPECT_NE(r.out.find("sampling: 20000 samples of 5 joints, uniform within the limits, seed 5"), std::string::npos)
      << r.out;
  const nlohmann::json j = json_of("work/ws");
  EXPECT_EQ(j["samples"], 20000);
  EXPECT_EQ(j["seed"], 5);
  EXPECT_EQ(j["link"], "l_foot");
  EXPECT_EQ(j["relative_to"], "torso");
  // The joints and their limits as `dmbd model info --json` reads them.
  const Result info = dmbd::cli_testing::run_dmbd({"model", "info", "--json", "--robot", "draco"}, dir_);
  ASSERT_EQ(info.code, 0) << info.err;
  const nlohmann::json robot = nlohmann::json::parse(info.out);
  const std::vector<std::string> chain{"l_hip_yaw", "l_hip_roll", "l_hip_pitch", "l_knee", "l_ankle"};
  ASSERT_EQ(j["joints"].size(), chain.size());
  for (std::size_t i = 0; i < chain.size(); ++i) {
    const auto& got = j["joints"][i];
    EXPECT_EQ(got["name"], chain[i]);
    for (const auto& joint : robot["joints"])
      if (joint["name"] == chain[i]) {
        EXPECT_EQ(got["lower"], joint["lower"]);
        EXPECT_EQ(got["upper"], joint["upper"]);
        EXPECT_NEAR(got["range_rad"].get<double>(), joint["upper"].get<double>() - joint["lower"].get<double>(), 1e-15);
      }
  }
  // Each map's grid covers the extents it shows, with cells of the stated size.
  for (const auto& map : j["density_maps"]) {
    const std::string plane = map["plane"];
    const double cell = map["cell_m"];
    EXPECT_EQ(cell, 0.02);
    for (int k = 0; k < 2; ++k) {
      const std::string axis(1, plane[static_cast<std::size_t>(k)]);
      const double lo = map["origin_m"][k], n = map[k == 0 ? "cols" : "rows"];
      EXPECT_LE(lo, j["extents"][axis]["min_m"].get<double>()) << plane << " " << axis;
      EXPECT_GT(lo + cell, j["extents"][axis]["min_m"].get<double>()) << plane << " " << axis;
      EXPECT_GE(lo + n * cell, j["extents"][axis]["max_m"].get<double>()) << plane << " " << axis;
      EXPECT_LT(lo + (n - 1) * cell, j["extents"][axis]["max_m"].get<double>()) << plane << " " << axis;
    }
  }
}

// The same seed gives the same JSON byte for byte; another seed gives extents that
// differ by less than the tolerance the sample count allows each of them below the
// exact extreme (Workspace.SampledExtentsLieWithinTheExactExtremesByTheSampleCountsTolerance,
// N = 10^5: x max 0.058, x min 0.044, y max 0.070, y min 0.177, z max 0.071, z min 0.013 m).
TEST_F(WorkspaceCli, SameSeedSameJsonAndAnotherSeedAgreesWithinTheSampleCountsTolerance) {
  for (const char* out : {"a", "b"}) ASSERT_EQ(run({"--link", "l_foot", "--out", out, "--seed", "11"}).code, 0);
  ASSERT_EQ(run({"--link", "l_foot", "--out", "c", "--seed", "12"}).code, 0);
  EXPECT_EQ(slurp(dir_ / "work/a/workspace.json"), slurp(dir_ / "work/b/workspace.json"));
  const nlohmann::json a = json_of("work/a"), c = json_of("work/c");
  EXPECT_EQ(a["samples"], 100000);
  EXPECT_NE(a["extents"], c["extents"]);  // other samples
  const std::vector<std::pair<std::string, double>> tol{{"x max_m", 0.058}, {"x min_m", 0.044}, {"y max_m", 0.070},
                                                        {"y min_m", 0.177}, {"z max_m", 0.071}, {"z min_m", 0.013}};
  for (const auto& [key, t] : tol) {
    const std::string axis = key.substr(0, 1), which = key.substr(2);
    EXPECT_NEAR(a["extents"][axis][which].get<double>(), c["extents"][axis][which].get<double>(), t) << key;
  }
}

TEST_F(WorkspaceCli, ContinuousJointIsSampledOverMinusPiToPiAndSaysSo) {
  const std::string arm = (fs::path(DMBD_SOURCE_DIR) / "tests/model/data/urdf/ws/arm_description/urdf/arm.urdf").string();
  const Result r = run({arm, "--link", "forearm", "--out", "arm", "--samples", "2000"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("joint shoulder_yaw: -3.142 .. 3.142 (6.283 rad, 360.0 deg): no limits, sampled over [-pi, pi]"),
            std::string::npos)
      << r.out;
  const nlohmann::json j = json_of("work/arm");
  EXPECT_EQ(j["joints"][0]["name"], "shoulder_yaw");
  EXPECT_EQ(j["joints"][0]["lower"], -M_PI);
  EXPECT_EQ(j["joints"][0]["upper"], M_PI);
  EXPECT_EQ(j["joints"][0]["limits"], "none: sampled over [-pi, pi]");
}

TEST_F(WorkspaceCli, MistakesAreOneLineAndExitTwo) {
  expect_bad({"--link", "l_fot", "--out", "ws"}, "no link 'l_fot'");
  expect_bad({"--link", "torso", "--out", "ws"}, "link 'torso' is not below a moving joint");
  expect_bad({"--link", "l_foot", "--relative-to", "pelvis", "--out", "ws"}, "no link 'pelvis'");
  expect_bad({"--link", "l_foot", "--out", "ws", "--samples", "0"}, "--samples '0'");
  expect_bad({"--link", "l_foot", "--out", "ws", "--samples", "2.5"}, "--samples '2.5'");
  expect_bad({"--link", "l_foot", "--out", "ws", "--cell", "-1"}, "--cell '-1'");
  std::ofstream(dir_ / "a_file") << "x";
  expect_bad({"--link", "l_foot", "--out", (dir_ / "a_file" / "ws").string()}, "--out '");
  expect_bad({"--link", "l_foot", "--out", (dir_ / "a_file").string()}, "--out '");
  expect_bad({"--out", "ws"}, "--link");  // required
}

}  // namespace
