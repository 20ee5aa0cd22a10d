// robot.actuators' `load` (a named load set of the actuator file) and `scale` (a parameter
// of every entry times a factor), per variant: what the plant is built with, and the
// mistakes located at their scenario lines. The table: tests/model/data/actuators/good.yaml
// (DRACO's l_knee and l_ankle, B_l 2.0e4 and 2.4e3 N s/m) with a `robot` load set added.
#include <gtest/gtest.h>

#include <string>

#include "dmbd/base/error.hpp"
#include "dmbd/scenario/scenario.hpp"
#include "sim_test_support.hpp"

namespace {

namespace sc = dmbd::scenario;
using dmbd::sim::test::read_text;
using dmbd::sim::test::TempDir;
using dmbd::sim::test::write_text;

const std::string kTable = std::string(DMBD_SOURCE_DIR) + "/tests/model/data/actuators/good.yaml";

// The table with `load_sets: {robot: ...}` on both entries (knee 4000, ankle 480).
std::string table_with_sets() {
  std::string t = read_text(kTable);
  auto add = [&](const std::string& after, const std::string& set) {
    const auto at = t.find(after);
    if (at == std::string::npos) throw std::logic_error("no '" + after + "'");
    t.insert(at + after.size(), "    load_sets: {robot: {B_l_Ns_per_m: " + set + "}}\n");
  };
  add("    load: {B_l_Ns_per_m: 2.0e4}\n", "4000");
  add("    load: {B_l_Ns_per_m: 2.4e3}\n", "480");
  return t;
}

// The knee of the table robot, held by nothing for a few milliseconds; `actuators` is
// the robot.actuators map, `extra` more top-level keys.
std::string scenario(const std::string& actuators, const std::string& extra = "") {
  return "name: variation\n"
         "robot:\n"
         "  name: draco\n"
         "  base: fixed\n"
         "  base_pose: {xyz: [0, 0, 1.3]}\n"
         "  moving: [l_knee, l_ankle]\n"
         "  actuators: " + actuators + "\n"
         "  initial: {l_knee: 1.0}\n"
         "duration_s: 0.005\n" + extra;
}

double b_l(const sc::Scenario& s, std::size_t variant, const std::string& joint) {
  for (const auto& a : sc::variant_plant(s, s.variants.at(variant)).options.actuators)
    if (a.joint == joint) return a.B_l_Ns_per_m;
  throw std::logic_error("no actuator " + joint);
}

std::string load_error(const std::string& path, const std::string& yaml) {
  write_text(path, yaml);
  try {
    const sc::Scenario s = sc::load_scenario(path);
    for (const auto& v : s.variants) (void)sc::variant_plant(s, v);
  } catch (const dmbd::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(ActuatorVariation, ALoadSetAndAScaleReachThePlant) {
  TempDir dir;
  write_text(dir.file("table.yaml"), table_with_sets());
  write_text(dir.file("a.yaml"), scenario("{file: table.yaml, joints: all}"));
  EXPECT_EQ(b_l(sc::load_scenario(dir.file("a.yaml")), 0, "l_knee"), 2.0e4);  // the entries' `load:`
  write_text(dir.file("b.yaml"), scenario("{file: table.yaml, joints: all, load: robot}"));
  const sc::Scenario b = sc::load_scenario(dir.file("b.yaml"));
  EXPECT_EQ(b_l(b, 0, "l_knee"), 4000);
  EXPECT_EQ(b_l(b, 0, "l_ankle"), 480);
  // The set first, then the scale: 0.5 of the robot's values.
  write_text(dir.file("c.yaml"), scenario("{file: table.yaml, joints: all, load: robot, scale: {B_l: 0.5}}"));
  EXPECT_EQ(b_l(sc::load_scenario(dir.file("c.yaml")), 0, "l_knee"), 2000);
}

TEST(ActuatorVariation, AMatrixSweepsTheScale) {
  TempDir dir;
  write_text(dir.file("table.yaml"), table_with_sets());
  const std::string axis = "matrix:\n  s:\n"
                           "    - {name: s0.1, robot: {actuators: {file: table.yaml, joints: all, scale: {B_l: 0.1}}}}\n"
                           "    - {name: s1, robot: {actuators: {file: table.yaml, joints: all, scale: {B_l: 1}}}}\n"
                           "    - {name: robot_s2, robot: {actuators: {file: table.yaml, joints: all, load: robot, scale: {B_l: 2}}}}\n";
  write_text(dir.file("m.yaml"), scenario("all", axis));
  const sc::Scenario s = sc::load_scenario(dir.file("m.yaml"));
  ASSERT_EQ(s.variants.size(), 3u);
  EXPECT_DOUBLE_EQ(b_l(s, 0, "l_knee"), 2000);
  EXPECT_DOUBLE_EQ(b_l(s, 0, "l_ankle"), 240);
  EXPECT_DOUBLE_EQ(b_l(s, 1, "l_knee"), 2.0e4);
  EXPECT_DOUBLE_EQ(b_l(s, 2, "l_knee"), 8000);
  EXPECT_DOUBLE_EQ(b_l(s, 2, "l_ankle"), 960);
}

// A matrix entry's `actuators` replaces the base's whole (docs/scenario-format.md, "What a
// variant replaces"): 0.5 of the file's value, not 0.2 x 0.5; an entry scaling another
// parameter drops the base's B_l factor.
TEST(ActuatorVariation, AnEntrysActuatorsReplaceTheBasesWhole) {
  TempDir dir;
  write_text(dir.file("table.yaml"), table_with_sets());
  const std::string axis = "matrix:\n  s:\n"
                           "    - {name: s0.5, robot: {actuators: {file: table.yaml, joints: all, scale: {B_l: 0.5}}}}\n"
                           "    - {name: base, robot: {actuators: {file: table.yaml, joints: all, scale: {J_m: 2}}}}\n";
  write_text(dir.file("m.yaml"), scenario("{file: table.yaml, joints: all, scale: {B_l: 0.2}}", axis));
  const sc::Scenario s = sc::load_scenario(dir.file("m.yaml"));
  ASSERT_EQ(s.variants.size(), 2u);
  EXPECT_DOUBLE_EQ(b_l(s, 0, "l_knee"), 1.0e4);
  EXPECT_DOUBLE_EQ(b_l(s, 1, "l_knee"), 2.0e4);
}

TEST(ActuatorVariation, MistakesAreLocatedAtTheirLines) {
  TempDir dir;
  write_text(dir.file("table.yaml"), table_with_sets());
  const std::string path = dir.file("e.yaml");
  const std::string at7 = path + ":7:";
  std::string msg = load_error(path, scenario("{file: table.yaml, joints: all, scale: {B_x: 2}}"));
  EXPECT_EQ(msg.rfind(at7, 0), 0u) << msg;
  EXPECT_NE(msg.find("unknown actuator parameter 'B_x' (expected one of: J_m, B_m, K_s, B_s, M_r, B_l, k_tau"), std::string::npos) << msg;
  msg = load_error(path, scenario("{file: table.yaml, joints: all, scale: {B_l: -0.5}}"));
  EXPECT_EQ(msg.rfind(at7, 0), 0u) << msg;
  EXPECT_NE(msg.find("robot.actuators.scale.B_l: expected a factor >= 0, got -0.5"), std::string::npos) << msg;
  msg = load_error(path, scenario("{file: table.yaml, joints: all, scale: {K_s: 0}}"));
  EXPECT_EQ(msg.rfind(at7, 0), 0u) << msg;
  EXPECT_NE(msg.find("robot.actuators.scale: the scale of actuator parameter 'K_s' must be > 0, got 0"), std::string::npos) << msg;
  msg = load_error(path, scenario("{file: table.yaml, joints: all, load: robt}"));
  EXPECT_EQ(msg.rfind(at7, 0), 0u) << msg;
  EXPECT_NE(msg.find("robot.actuators.load: " + dir.file("table.yaml") + ":3:5: actuators 'l_knee', 'l_ankle' have no load set 'robt' "
                     "(the table's load sets: robot)"),
            std::string::npos)
      << msg;
  // DRACO's own file without a `robot` set at all names its sets as none.
  msg = load_error(path, scenario("{file: " + kTable + ", joints: all, load: robot}"));
  EXPECT_NE(msg.find("(the table's load sets: none)"), std::string::npos) << msg;
  for (const std::string& m : {msg}) EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}
