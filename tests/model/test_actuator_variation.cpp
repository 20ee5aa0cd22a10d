// Variations of an actuator table (docs/actuator-format.md, "Load sets" and "Scaling"):
// the file's named `load_sets:` read and located, one put in place of the entries'
// `load:` terms, and a parameter of every entry scaled.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "actuator_fixtures.hpp"
#include "dmbd/model/actuator.hpp"
#include "dmbd/model/error.hpp"

namespace dm = dmbd::model;
using dmbd::model::testing::replaced;
using dmbd::model::testing::text_of;
namespace {
std::string fixture(const std::string& name) { return dmbd::model::testing::actuator_fixture(name); }
}  // namespace

namespace {

// good.yaml with a `robot` load set on both entries (knee 4000, ankle 480) and an `other`
// set on the knee alone, written to a temporary file.
struct Table {
  std::string path = (std::filesystem::temp_directory_path() / ("dmbd_actuator_variation_" + std::to_string(::getpid()) + ".yaml")).string();
  explicit Table(const std::string& text) { std::ofstream(path) << text; }
  ~Table() { std::filesystem::remove(path); }
};

std::string with_sets() {
  std::string t = text_of(fixture("good.yaml"));
  t = replaced(t, "    load: {B_l_Ns_per_m: 2.0e4}\n", "    load: {B_l_Ns_per_m: 2.0e4}\n    load_sets: {robot: {B_l_Ns_per_m: 4000}, other: {B_l_Ns_per_m: 1}}\n");
  return replaced(t, "    load: {B_l_Ns_per_m: 2.4e3}\n", "    load: {B_l_Ns_per_m: 2.4e3}\n    load_sets:\n      robot: {B_l_Ns_per_m: 480}\n");
}

std::string error_of(const std::string& text, std::string* path = nullptr) {
  Table t(text);
  if (path) *path = t.path;
  try {
    dm::load_actuators(t.path);
  } catch (const dm::ModelError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(ActuatorLoadSets, AreReadWithTheirPlacesAndLeaveTheLoadTermsAlone) {
  Table t(with_sets());
  const auto acts = dm::load_actuators(t.path);
  ASSERT_EQ(acts.size(), 2u);
  EXPECT_EQ(acts[0].B_l_Ns_per_m, 2.0e4);  // `load:` until a set is selected
  ASSERT_EQ(acts[0].load_sets.size(), 2u);
  EXPECT_EQ(acts[0].load_sets[0].name, "robot");
  EXPECT_EQ(acts[0].load_sets[0].B_l_Ns_per_m, 4000);
  EXPECT_EQ(acts[0].load_sets[0].where, t.path + ":12:17");
  EXPECT_EQ(acts[0].load_sets[1].name, "other");
  ASSERT_EQ(acts[1].load_sets.size(), 1u);
  EXPECT_EQ(acts[1].load_sets[0].where, t.path + ":34:7");
}

TEST(ActuatorLoadSets, SelectingOnePutsItsTermsInPlace) {
  Table t(with_sets());
  auto acts = dm::load_actuators(t.path);
  dm::select_load_set(acts, "robot");
  EXPECT_EQ(acts[0].B_l_Ns_per_m, 4000);
  EXPECT_EQ(acts[1].B_l_Ns_per_m, 480);
  EXPECT_EQ(acts[0].K_s_N_per_m, 9.5e6);  // nothing else changes
}

TEST(ActuatorLoadSets, ASetSomeEntriesLackIsRefusedNamingThem) {
  Table t(with_sets());
  auto acts = dm::load_actuators(t.path);
  try {
    dm::select_load_set(acts, "other");
    ADD_FAILURE() << "no error";
  } catch (const dm::ModelError& e) {
    EXPECT_EQ(std::string(e.what()), t.path + ":25:5: actuator 'l_ankle' has no load set 'other' (the table's load sets: robot, other)");
  }
  try {
    dm::select_load_set(acts, "robt");
    ADD_FAILURE() << "no error";
  } catch (const dm::ModelError& e) {
    EXPECT_EQ(std::string(e.what()), t.path + ":3:5: actuators 'l_knee', 'l_ankle' have no load set 'robt' (the table's load sets: robot, other)");
  }
}

TEST(ActuatorLoadSets, MistakesAreLocated) {
  std::string path;
  const std::string base = text_of(fixture("good.yaml"));
  auto located = [&](const std::string& text, int line, const std::string& what) {
    const std::string msg = error_of(text, &path);
    EXPECT_EQ(msg.rfind(path + ":" + std::to_string(line) + ":", 0), 0u) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  };
  const std::string at = "    load: {B_l_Ns_per_m: 2.0e4}\n";
  located(replaced(base, at, at + "    load_sets: {robot: {B_l_Nms_per_rad: 4000}}\n"), 12,
          "actuator 'l_knee' load_sets 'robot': unknown key 'B_l_Nms_per_rad' (expected one of: B_l_Ns_per_m)");
  located(replaced(base, at, at + "    load_sets: {robot: {B_l_Ns_per_m: -1}}\n"), 12, "'B_l_Ns_per_m' must be >= 0 (N s/m), got -1");
  located(replaced(base, at, at + "    load_sets: {robot: 4000}\n"), 12, "load_sets: 'robot' must be a map with the key B_l_Ns_per_m");
  located(replaced(base, at, at + "    load_sets: [robot]\n"), 12, "'load_sets' must be a map of named load terms");
  located(replaced(base, at, at + "    load_sets: {robot: {B_l_Ns_per_m: 1}, robot: {B_l_Ns_per_m: 2}}\n"), 12,
          "load_sets: 'robot' is given twice (first at ");
}

TEST(ActuatorScale, MultipliesTheParameterOfEveryEntry) {
  auto acts = dm::load_actuators(fixture("good.yaml"));
  const auto before = acts;
  dm::scale_parameter(acts, "B_l", 0.25);
  EXPECT_EQ(acts[0].B_l_Ns_per_m, 5000);
  EXPECT_EQ(acts[1].B_l_Ns_per_m, 600);
  dm::scale_parameter(acts, "J_m", 2);
  EXPECT_EQ(acts[0].J_m_kgm2, 2 * before[0].J_m_kgm2);
  EXPECT_EQ(acts[1].B_m_Nms, before[1].B_m_Nms);
  dm::scale_parameter(acts, "B_l", 0);  // a damping may vanish
  EXPECT_EQ(acts[0].B_l_Ns_per_m, 0);
}

TEST(ActuatorScale, UnknownSymbolsAndBadFactorsAreRefused) {
  auto acts = dm::load_actuators(fixture("good.yaml"));
  auto message = [&](const std::string& symbol, double f) {
    try {
      dm::scale_parameter(acts, symbol, f);
    } catch (const dm::ModelError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(message("B_x", 2), "unknown actuator parameter 'B_x' to scale (expected one of: J_m, B_m, K_s, B_s, M_r, B_l, k_tau, "
                               "viscous_friction, coulomb_friction)");
  EXPECT_EQ(message("K_s", 0), "the scale of actuator parameter 'K_s' must be > 0, got 0");
  EXPECT_EQ(message("B_l", -1), "the scale of actuator parameter 'B_l' must be >= 0, got -1");
  EXPECT_EQ(message("B_l", NAN), "the scale of actuator parameter 'B_l' must be >= 0, got nan");
  EXPECT_EQ(acts[0].K_s_N_per_m, 9.5e6);  // a refused scale changes nothing
}
