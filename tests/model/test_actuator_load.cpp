// load_actuators: a valid table, and every kind of mistake reported as
// "FILE:LINE:COLUMN: what was expected" (ModelError), every one of them; numbers
// through the parser a caller supplies (expressions from blocks).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "dmbd/blocks/expression_numbers.hpp"
#include "actuator_fixtures.hpp"
#include "dmbd/model/actuator.hpp"
#include "dmbd/model/error.hpp"

namespace dm = dmbd::model;
using dmbd::model::testing::replaced;
namespace {
std::string fixture(const std::string& name) { return dmbd::model::testing::actuator_fixture(name); }
}  // namespace

namespace {


// The ModelError message of loading a fixture ("" if it loads).
std::string error_of(const std::string& name) {
  try {
    dm::load_actuators(fixture(name));
  } catch (const dm::ModelError& e) {
    return e.what();
  }
  return "";
}

// The message starts with "PATH:LINE:COLUMN: " and contains `what`.
void expect_error(const std::string& name, int line, const std::string& what) {
  const std::string msg = error_of(name);
  const std::string prefix = fixture(name) + ":" + std::to_string(line) + ":";
  EXPECT_EQ(msg.rfind(prefix, 0), 0u) << "expected prefix '" << prefix << "', got: " << msg;
  const std::size_t column = prefix.size();
  EXPECT_TRUE(column < msg.size() && std::isdigit(static_cast<unsigned char>(msg[column]))) << "no column: " << msg;
  EXPECT_NE(msg.find(what), std::string::npos) << "expected '" << what << "' in: " << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
}

}  // namespace

TEST(LoadActuators, ReadsAValidTableWithSharedBlocks) {
  const auto acts = dm::load_actuators(fixture("good.yaml"));
  ASSERT_EQ(acts.size(), 2u);
  const dm::ActuatorParams& k = acts[0];
  EXPECT_EQ(k.joint, "l_knee");
  EXPECT_EQ(k.kind, dm::ActuatorKind::RFSEA);
  EXPECT_DOUBLE_EQ(k.J_m_kgm2, 1.6e-5);
  EXPECT_DOUBLE_EQ(k.B_m_Nms, 2.0e-4);
  EXPECT_DOUBLE_EQ(k.N_m_rad_per_m, 6632);
  EXPECT_DOUBLE_EQ(k.K_s_N_per_m, 9.5e6);
  EXPECT_DOUBLE_EQ(k.B_s_Ns_per_m, 1.6e4);
  EXPECT_DOUBLE_EQ(k.M_r_kg, 1.3);
  EXPECT_DOUBLE_EQ(k.B_l_Ns_per_m, 2.0e4);
  EXPECT_DOUBLE_EQ(k.k_tau_Nm_per_A, 0.0448);
  EXPECT_DOUBLE_EQ(k.current_limit_A, 22);
  EXPECT_DOUBLE_EQ(k.force_limit_N, 8000);
  EXPECT_DOUBLE_EQ(k.efficiency, 0.9);
  EXPECT_DOUBLE_EQ(k.linkage.a_m, 0.30);
  EXPECT_DOUBLE_EQ(k.linkage.b_m, 0.052);
  EXPECT_DOUBLE_EQ(k.linkage.gamma0_rad, 0.500796);
  EXPECT_DOUBLE_EQ(k.linkage.sign, 1);
  EXPECT_DOUBLE_EQ(k.thermal.R_winding_ohm, 1.03);
  EXPECT_DOUBLE_EQ(k.thermal.alpha_per_K, 0.00393);
  EXPECT_DOUBLE_EQ(k.thermal.C_winding_J_per_K, 30);
  EXPECT_DOUBLE_EQ(k.thermal.C_housing_J_per_K, 60);
  EXPECT_DOUBLE_EQ(k.thermal.R_wh_K_per_W, 1.0);
  EXPECT_DOUBLE_EQ(k.thermal.R_ha_air_K_per_W, 7.0);
  EXPECT_DOUBLE_EQ(k.thermal.R_ha_liquid_K_per_W, 0.28);
  EXPECT_DOUBLE_EQ(k.thermal.T_ambient_C, 25);
  EXPECT_DOUBLE_EQ(k.thermal.T_winding_max_C, 130);
  EXPECT_DOUBLE_EQ(k.motor_encoder.counts_per_unit, 1303.7972938088065);
  EXPECT_DOUBLE_EQ(k.spring_encoder.counts_per_unit, 1.0e6);
  EXPECT_DOUBLE_EQ(k.potentiometer.lo, -0.05);
  EXPECT_DOUBLE_EQ(k.potentiometer.hi, 2.19);
  EXPECT_EQ(k.potentiometer.adc_bits, 12);
  EXPECT_DOUBLE_EQ(k.potentiometer.noise_std, 2.0e-3);
  EXPECT_DOUBLE_EQ(k.potentiometer.cutoff_hz, 100);

  const dm::ActuatorParams& a = acts[1];
  EXPECT_EQ(a.joint, "l_ankle");
  EXPECT_EQ(a.kind, dm::ActuatorKind::FSEA);
  EXPECT_EQ(a.M_r_kg, 0.0);  // an FSEA has no reaction mass
  EXPECT_DOUBLE_EQ(a.linkage.sign, -1);
  EXPECT_DOUBLE_EQ(a.thermal.R_ha_liquid_K_per_W, 0.28);  // through the alias *thermal_30
  EXPECT_DOUBLE_EQ(a.motor_encoder.counts_per_unit, 1303.7972938088065);
  EXPECT_DOUBLE_EQ(a.spring_encoder.counts_per_unit, 2.0e6);
  EXPECT_EQ(a.potentiometer.adc_bits, 10);
  EXPECT_DOUBLE_EQ(a.potentiometer.cutoff_hz, 0);
}

TEST(LoadActuators, MissingFileNamesTheFile) {
  const std::string path = fixture("no_such_file.yaml");
  try {
    dm::load_actuators(path);
    FAIL() << "no error";
  } catch (const dm::ModelError& e) {
    // No line to name: the message is "PATH: cannot read: REASON (...)".
    EXPECT_EQ(std::string(e.what()), path + ": cannot read: No such file or directory (expected a YAML actuator file)");
  }
}

TEST(LoadActuators, MalformedYaml) { expect_error("malformed.yaml", 8, "malformed YAML: end of map flow not found"); }
TEST(LoadActuators, EmptyFile) {
  expect_error("empty.yaml", 1, "expected a map with the keys 'format' (1) and 'actuators'");
}
TEST(LoadActuators, NotAMap) { expect_error("not_a_map.yaml", 2, "expected a map with the keys 'format' (1) and 'actuators'"); }
TEST(LoadActuators, UnknownTopLevelKey) {
  expect_error("unknown_top_key.yaml", 2, "unknown top-level key 'actuator' (expected one of: format, actuators)");
}
TEST(LoadActuators, UnknownKey) {
  expect_error("unknown_key.yaml", 12, "actuator 'l_knee': unknown key 'B_s_Ns_per_mm' (expected one of: joint, kind,");
}
TEST(LoadActuators, UnknownNestedKey) {
  expect_error("unknown_nested_key.yaml", 16,
               "actuator 'l_knee': unknown linkage key 'c_m' (expected one of: a_m, b_m, gamma0_rad, sign)");
}
TEST(LoadActuators, MissingField) {
  expect_error("missing_field.yaml", 3, "actuator 'l_knee': missing 'k_tau_Nm_per_A'");
}
TEST(LoadActuators, MissingJoint) { expect_error("missing_joint.yaml", 3, "actuator: missing 'joint'"); }
TEST(LoadActuators, NegativeStiffness) {
  expect_error("negative_stiffness.yaml", 8, "actuator 'l_knee': 'K_s_N_per_m' must be > 0 (N/m), got -9.5e+06");
}
TEST(LoadActuators, ZeroStiffness) {
  expect_error("zero_stiffness.yaml", 8, "actuator 'l_knee': 'K_s_N_per_m' must be > 0 (N/m), got 0");
}
TEST(LoadActuators, NotANumber) {
  expect_error("not_a_number.yaml", 8, "actuator 'l_knee': 'K_s_N_per_m' (N/m): expected a number, got 'stiff'");
}
TEST(LoadActuators, UnknownKind) {
  expect_error("unknown_kind.yaml", 4, "actuator 'l_knee': unknown kind 'SEA' (expected rfsea, fsea, rotary or rotary_sea)");
}
TEST(LoadActuators, FseaHasNoReactionMass) {
  expect_error("fsea_reaction_mass.yaml", 10, "actuator 'l_knee': 'M_r_kg' applies to kind rfsea only, not fsea");
}
TEST(LoadActuators, DuplicateJoint) {
  expect_error("duplicate_joint.yaml", 24, "joint 'l_knee' has a second actuator (the first is at line 3)");
}
TEST(LoadActuators, BadLinkageSign) {
  expect_error("bad_sign.yaml", 16, "actuator 'l_knee' linkage: 'sign' must be +1 or -1, got 0.5");
}
TEST(LoadActuators, NonPositiveLiquidResistance) {
  expect_error("bad_liquid_resistance.yaml", 19, "thermal: 'R_ha_liquid_K_per_W' must be > 0 (K/W), got -0.1");
}

namespace {

std::string good_table() { return dmbd::model::testing::text_of(fixture("good.yaml")); }


std::string write_table(const std::string& text) {
  const std::string path = (std::filesystem::temp_directory_path() / ("dmbd_actuators_" + std::to_string(::getpid()) + ".yaml")).string();
  std::ofstream(path) << text;
  return path;
}

}  // namespace

TEST(LoadActuators, EveryProblemIsReportedEachAtItsLine) {
  std::string text = replaced(good_table(), "K_s_N_per_m: 9.5e6", "K_s_N_per_m: -1");
  text = replaced(text, "N_m_rad_per_m: 3142", "N_m_rad_per_m: lots");
  const std::string path = write_table(text);
  try {
    dm::load_actuators(path);
    ADD_FAILURE() << "no error";
  } catch (const dm::ModelError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg, path + ":8:18: actuator 'l_knee': 'K_s_N_per_m' must be > 0 (N/m), got -1\n" + path +
                       ":28:20: actuator 'l_ankle': 'N_m_rad_per_m' (rad/m): expected a number, got 'lots'");
  }
  std::filesystem::remove(path);
}

TEST(LoadActuators, ExpressionsWhenTheCallerSuppliesThem) {
  const std::string path = write_table(replaced(good_table(), "K_s_N_per_m: 9.5e6", "K_s_N_per_m: 9.5*10^6"));
  EXPECT_THROW(dm::load_actuators(path), dm::ModelError);  // plain numbers by default
  const auto acts = dm::load_actuators(path, dmbd::blocks::expression_numbers());
  EXPECT_DOUBLE_EQ(acts[0].K_s_N_per_m, 9.5e6);
  std::filesystem::remove(path);
}

TEST(LoadActuators, ATabInTheIndentationIsNamed) {
  const std::string path = write_table(replaced(good_table(), "    kind: RFSEA", "\tkind: RFSEA"));
  try {
    dm::load_actuators(path);
    ADD_FAILURE() << "no error";
  } catch (const dm::ModelError& e) {
    EXPECT_EQ(std::string(e.what()), path + ":4:1: tabs are not allowed in YAML indentation (indent with spaces)");
  }
  std::filesystem::remove(path);
}
