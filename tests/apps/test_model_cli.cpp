// `dmbd model info`: the table and the JSON of real-world-style URDFs (checked against
// the files' own text), package paths, --strict, DRACO's description by default, and
// bad input: exit code 2, one line on stderr naming the file and line, nothing on
// stdout, no file written.
#include "cli_support.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

// The URDF fixtures of tests/model (DMBD_TEST_DATA is tests/diagrams/data).
std::string urdf_data(const std::string& rel) {
  return (fs::path(DMBD_TEST_DATA).parent_path().parent_path() / "model" / "data" / "urdf" / rel).lexically_normal().string();
}
// DRACO's description (robots/draco/draco.urdf at the top of the source tree).
std::string draco_urdf() {
  return (fs::path(DMBD_TEST_DATA).parent_path().parent_path().parent_path() / "robots" / "draco" / "draco.urdf")
      .lexically_normal()
      .string();
}

int line_of(const std::string& text, const std::string& needle) {
  const auto at = text.find(needle);
  if (at == std::string::npos) return 0;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

double sum_of_mass_elements(const std::string& text) {
  static const std::regex re(R"re(<mass\s+value\s*=\s*"([^"]*)")re");
  double sum = 0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator(); ++it)
    sum += std::stod((*it)[1].str());
  return sum;
}

using dmbd::cli_testing::quote;
using dmbd::cli_testing::Result;
using dmbd::cli_testing::slurp;

class ModelCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("dmbd_model_cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "work");
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Runs dmbd in an empty working folder (dir_/work), so that any file it wrote would show.
  Result run(const std::vector<std::string>& args) { return dmbd::cli_testing::run_dmbd(args, dir_, dir_ / "work"); }

  nlohmann::json info_json(const std::vector<std::string>& args) {
    std::vector<std::string> full = {"model", "info"};
    full.insert(full.end(), args.begin(), args.end());
    full.push_back("--json");
    const Result r = run(full);
    EXPECT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    // Each warning once on stderr (never on stdout), as the JSON lists them.
    std::string expected;
    for (const auto& w : j["warnings"]) expected += "warning: " + w.get<std::string>() + "\n";
    EXPECT_EQ(r.err, expected);
    return j;
  }

  // Exit 2, exactly one line on stderr starting "dmbd: error: FILE:LINE: " and holding
  // every fragment, nothing on stdout, nothing written.
  void expect_bad(const std::vector<std::string>& args, const std::string& at, const std::vector<std::string>& fragments) {
    std::vector<std::string> full = {"model", "info"};
    full.insert(full.end(), args.begin(), args.end());
    for (const bool json : {false, true}) {
      std::vector<std::string> a = full;
      if (json) a.push_back("--json");
      const Result r = run(a);
      EXPECT_EQ(r.code, 2) << r.err;
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
      EXPECT_EQ(r.err.rfind("dmbd: error: " + at, 0), 0u) << r.err;
      for (const auto& f : fragments) EXPECT_NE(r.err.find(f), std::string::npos) << "missing '" << f << "' in: " << r.err;
      EXPECT_EQ(r.out, "");
      EXPECT_TRUE(fs::is_empty(dir_ / "work"));
    }
  }

  fs::path dir_;
};

TEST_F(ModelCli, JsonOfTheArmMatchesTheFile) {
  const std::string path = urdf_data("ws/arm_description/urdf/arm.urdf");
  const nlohmann::json j = info_json({path});
  EXPECT_EQ(j["name"], "small_arm");
  EXPECT_EQ(j["links"], 6);
  EXPECT_EQ(j["dof"], 3);
  EXPECT_EQ(j["joint_counts"],
            (nlohmann::json{{"fixed", 2}, {"revolute", 2}, {"continuous", 1}, {"prismatic", 0}, {"floating", 0}, {"planar", 0}}));
  EXPECT_NEAR(j["total_mass_kg"].get<double>(), sum_of_mass_elements(slurp(path)), 1e-12);
  EXPECT_NEAR(j["height_m"].get<double>(), 1.1, 1e-7);
  EXPECT_EQ(j["meshes_loaded"], 2);
  EXPECT_EQ(j["meshes_missing"], nlohmann::json::array());
  EXPECT_EQ(j["warnings"], nlohmann::json::array());
  ASSERT_EQ(j["joints"].size(), 5u);
  // Parent before child, in the order of the tree.
  const std::vector<std::string> names = {"base_link_to_base", "shoulder_yaw", "shoulder_pitch", "elbow", "tool_joint"};
  for (std::size_t k = 0; k < names.size(); ++k) EXPECT_EQ(j["joints"][k]["name"], names[k]);
  const auto& sp = j["joints"][2];
  EXPECT_EQ(sp["type"], "revolute");
  EXPECT_EQ(sp["parent"], "shoulder");
  EXPECT_EQ(sp["child"], "upper_arm");
  EXPECT_EQ(sp["lower"], -1.57);
  EXPECT_EQ(sp["upper"], 1.57);
  EXPECT_EQ(sp["axis"], (nlohmann::json{0.0, 1.0, 0.0}));  // "0 2 0" normalised
  const auto& sy = j["joints"][1];
  EXPECT_EQ(sy["type"], "continuous");
  EXPECT_TRUE(sy["lower"].is_null());
  EXPECT_TRUE(sy["upper"].is_null());
  EXPECT_EQ(sy["axis"], (nlohmann::json{0.0, 0.0, 1.0}));
  EXPECT_EQ(j["joints"][0]["type"], "fixed");
}

TEST_F(ModelCli, JsonOfTheQuadrupedCountsAndWarnings) {
  const std::string path = urdf_data("quadruped/quadruped.urdf");
  const nlohmann::json j = info_json({path});
  EXPECT_EQ(j["name"], "quad");
  EXPECT_EQ(j["links"], 30);
  EXPECT_EQ(j["dof"], 15);
  EXPECT_EQ(j["joint_counts"]["floating"], 1);
  EXPECT_EQ(j["joint_counts"]["prismatic"], 2);
  EXPECT_EQ(j["joint_counts"]["revolute"], 13);
  EXPECT_EQ(j["joint_counts"]["fixed"], 13);
  EXPECT_NEAR(j["total_mass_kg"].get<double>(), sum_of_mass_elements(slurp(path)), 1e-12);
  EXPECT_NEAR(j["height_m"].get<double>(), 0.52, 1e-12);
  ASSERT_EQ(j["warnings"].size(), 3u);
  const std::string w = j["warnings"][0];
  EXPECT_EQ(w.rfind(path + ":" + std::to_string(line_of(slurp(path), "<gazebo reference=")) + ": <gazebo> ignored", 0), 0u) << w;
  EXPECT_EQ(j["joints"][0]["type"], "floating");
  EXPECT_TRUE(j["joints"][0]["axis"].is_null());
}

TEST_F(ModelCli, TableOfTheArm) {
  const Result r = run({"model", "info", urdf_data("ws/arm_description/urdf/arm.urdf")});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  for (const char* s : {"robot 'small_arm'", "links    6 (root base_link)", "dof      3",
                        "fixed 2, revolute 2, continuous 1, prismatic 0, floating 0, planar 0", "mass     4.95 kg",
                        "height   1.1 m", "meshes   2 loaded, 0 missing"})
    EXPECT_NE(r.out.find(s), std::string::npos) << "missing '" << s << "' in:\n" << r.out;
  // One row per joint with its type, limits and axis.
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(shoulder_pitch +revolute +shoulder -> upper_arm +-1\.57 rad +1\.57 rad +40 N m +3 rad/s +0 1 0\n)")))
      << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(tool_joint +fixed +forearm -> tool_frame +- +- +- +- +-\n)"))) << r.out;
}

TEST_F(ModelCli, MissingMeshesAreWarningsAndStrictMakesThemErrors) {
  const std::string path = urdf_data("partial/missing_meshes.urdf");
  const nlohmann::json j = info_json({path});
  EXPECT_EQ(j["meshes_missing"], (nlohmann::json{"package://nowhere_description/meshes/ghost.stl", "garbage.stl"}));
  EXPECT_EQ(j["meshes_loaded"], 1);
  ASSERT_EQ(j["warnings"].size(), 3u);  // the two meshes, then the massless moving link 'arm'
  EXPECT_NE(j["warnings"][0].get<std::string>().find("ghost.stl' not found"), std::string::npos);
  EXPECT_EQ(j["repairs"].size(), 1u);
  const Result table = run({"model", "info", path});
  EXPECT_EQ(table.code, 0);
  EXPECT_NE(table.out.find("missing: package://nowhere_description/meshes/ghost.stl"), std::string::npos) << table.out;
  EXPECT_NE(table.err.find("warning: " + path + ":"), std::string::npos) << table.err;
  EXPECT_EQ(table.out.find("warning:"), std::string::npos) << table.out;
  expect_bad({path, "--strict"}, path + ":" + std::to_string(line_of(slurp(path), "ghost.stl")) + ": ",
             {"link 'base'", "ghost.stl' not found", "strict"});
}

TEST_F(ModelCli, PackagePath) {
  // The arm's URDF alone in another folder: its package:// meshes are found only
  // through --package-path.
  const fs::path copy = dir_ / "arm.urdf";
  fs::copy_file(urdf_data("ws/arm_description/urdf/arm.urdf"), copy);
  const nlohmann::json without = info_json({copy.string()});
  EXPECT_EQ(without["meshes_loaded"], 0);
  EXPECT_EQ(without["meshes_missing"].size(), 2u);
  const nlohmann::json with = info_json({copy.string(), "--package-path", urdf_data("ws")});
  EXPECT_EQ(with["meshes_loaded"], 2);
  EXPECT_EQ(with["meshes_missing"].size(), 0u);
  EXPECT_NEAR(with["height_m"].get<double>(), 1.1, 1e-7);
  // Repeatable: the first folder has nothing, the second has the package.
  const nlohmann::json two = info_json({"--package-path", dir_.string(), "--package-path", urdf_data("ws"), copy.string()});
  EXPECT_EQ(two["meshes_loaded"], 2);
}

// No robot is built in: a robot folder by name (--robot), found on the search path,
// else one of the two must be given (exit 2, one line).
TEST_F(ModelCli, RobotByNameAndNoDefault) {
  const Result r = run({"model", "info", "--json", "--robot", "draco"});
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["source"], draco_urdf());
  EXPECT_EQ(j["links"].get<int>(), static_cast<int>(j["joints"].size()) + 1);
  EXPECT_NEAR(j["total_mass_kg"].get<double>(), sum_of_mass_elements(slurp(draco_urdf())), 1e-9);
  const Result none = run({"model", "info"});
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.err.find("give a URDF file or --robot NAME"), std::string::npos) << none.err;
  const Result unknown = run({"model", "info", "--robot", "no_such_robot"});
  EXPECT_EQ(unknown.code, 2);
  EXPECT_NE(unknown.err.find("--robot: robot 'no_such_robot' not found (searched: "), std::string::npos) << unknown.err;
}

TEST_F(ModelCli, BadFiles) {
  auto bad = [&](const std::string& file, const std::string& marker, const std::vector<std::string>& fragments) {
    SCOPED_TRACE(file);
    const std::string path = urdf_data("bad/" + file);
    expect_bad({path}, path + ":" + std::to_string(line_of(slurp(path), marker)) + ": ", fragments);
  };
  bad("malformed.urdf", "</inertia>", {"malformed XML"});
  bad("two_parents.urdf", "<joint name=\"knee_linkage\"", {"joint 'knee_linkage'", "already has the parent joint 'knee'"});
  bad("loop.urdf", "<joint name=\"c_to_a\"", {"loop in the kinematic tree"});
  bad("negative_mass.urdf", "<mass", {"link 'thigh'", "negative"});
  bad("not_positive_definite.urdf", "<inertia ", {"link 'thigh'", "not positive definite"});
  bad("revolute_without_limit.urdf", "<joint name=\"hip_pitch\"", {"joint 'hip_pitch'", "<limit"});
  bad("nan_origin.urdf", "xyz=\"0 nan", {"joint 'hip'", "not a finite number"});
}

TEST_F(ModelCli, MissingFileAndUsage) {
  const std::string path = (dir_ / "nothing.urdf").string();
  expect_bad({path}, path + ": ", {"cannot open the file"});
  const Result no_sub = run({"model"});
  EXPECT_EQ(no_sub.code, 2);
  EXPECT_EQ(std::count(no_sub.err.begin(), no_sub.err.end(), '\n'), 1) << no_sub.err;
  const Result extra = run({"model", "info", "a.urdf", "b.urdf"});
  EXPECT_EQ(extra.code, 2);
  EXPECT_EQ(std::count(extra.err.begin(), extra.err.end(), '\n'), 1) << extra.err;
}

// Repairs (docs/model.md): an inertia breaking the triangle inequality and a moving link
// without mass load with one warning line each and a `repairs` entry; --strict refuses.
TEST_F(ModelCli, RepairsAreWarnedListedAndRefusedByStrict) {
  const fs::path path = dir_ / "bad.urdf";
  std::ofstream(path) << R"(<robot name="bad">
  <link name="base">
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/>
  </joint>
  <link name="arm">
    <inertial><mass value="1"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.004"/></inertial>
  </link>
  <joint name="tilt" type="continuous"><parent link="arm"/><child link="sensor"/><axis xyz="0 1 0"/></joint>
  <link name="sensor"/>
</robot>
)";
  const std::string p = path.string();
  const Result text = run({"model", "info", p});
  EXPECT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.err.find("warning: " + p + ":10: link 'arm': inertia violates the triangle inequality " +
                          "(principal moments 0.001 + 0.002 < 0.004 kg m^2, by 33.3 %): repaired by balanceinertia"),
            std::string::npos)
      << text.err;
  EXPECT_NE(text.err.find("warning: " + p + ":12: link 'sensor': moved by continuous joint 'tilt'"), std::string::npos)
      << text.err;
  EXPECT_NE(text.out.find("mass     2 kg"), std::string::npos) << text.out;
  const nlohmann::json j = info_json({p});
  ASSERT_EQ(j["repairs"].size(), 2u);
  EXPECT_EQ(j["repairs"][0]["link"], "arm");
  EXPECT_EQ(j["repairs"][0]["kind"], "balanceinertia");
  ASSERT_EQ(j["repairs"][0]["before"].size(), 3u);
  EXPECT_NEAR(j["repairs"][0]["before"][2].get<double>(), 0.004, 1e-15);
  for (const auto& a : j["repairs"][0]["after"]) EXPECT_NEAR(a.get<double>(), 0.007 / 3, 1e-15);
  EXPECT_EQ(j["repairs"][1]["link"], "sensor");
  EXPECT_EQ(j["repairs"][1]["kind"], "massless_moving_link");
  EXPECT_EQ(j["repairs"][1]["before"], (nlohmann::json{0.0}));
  EXPECT_EQ(j["warnings"].size(), 2u);
  expect_bad({p, "--strict"}, p + ":10: ", {"link 'arm'", "triangle inequality", "strict"});
  // DRACO needs no repair.
  EXPECT_EQ(info_json({draco_urdf()})["repairs"], nlohmann::json::array());
}

// Simbody's Atlas example as Debian ships it: loads with the head's inertia balanced.
TEST_F(ModelCli, SimbodysAtlasLoadsWithWarningsAndStrictRefusesIt) {
  const std::string gz =
      "/usr/share/doc/simbody/examples/src/TaskSpaceControl-Atlas/models/atlas_v4_free_pelvis.urdf.gz";
  if (!fs::exists(gz)) GTEST_SKIP() << gz << " is absent (Simbody's examples, Debian's simbody docs)";
  const std::string p = (dir_ / "atlas_v4_free_pelvis.urdf").string();
  ASSERT_EQ(std::system(("gzip -dc " + quote(gz) + " > " + quote(p)).c_str()), 0);
  const Result text = run({"model", "info", p});
  EXPECT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.err.find("link 'head': inertia violates the triangle inequality"), std::string::npos) << text.err;
  const nlohmann::json j = info_json({p});
  EXPECT_EQ(j["dof"], 29);
  EXPECT_NEAR(j["total_mass_kg"].get<double>(), 159.854574, 1e-6);
  ASSERT_EQ(j["repairs"].size(), 1u);
  EXPECT_EQ(j["repairs"][0]["link"], "head");
  expect_bad({p, "--strict"}, p + ":" + std::to_string(line_of(slurp(p), "<inertia ixx=\"0.0036053766\"")) + ": ",
             {"link 'head'", "triangle inequality"});
}

}  // namespace
