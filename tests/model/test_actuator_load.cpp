// load_actuators: a valid table, and every kind of mistake reported as
// "FILE:LINE: what was expected" (ModelError).
#include <gtest/gtest.h>

#include <string>

#include "dmbd/model/actuator.hpp"
#include "dmbd/model/error.hpp"

namespace dm = dmbd::model;

namespace {

std::string fixture(const std::string& name) { return std::string(DMBD_MODEL_TEST_DATA) + "/actuators/" + name; }

// The ModelError message of loading a fixture ("" if it loads).
std::string error_of(const std::string& name) {
  try {
    dm::load_actuators(fixture(name));
  } catch (const dm::ModelError& e) {
    return e.what();
  }
  return "";
}

// The message starts with "PATH:LINE: " and contains `what`.
void expect_error(const std::string& name, int line, const std::string& what) {
  const std::string msg = error_of(name);
  const std::string prefix = fixture(name) + ":" + std::to_string(line) + ": ";
  EXPECT_EQ(msg.rfind(prefix, 0), 0u) << "expected prefix '" << prefix << "', got: " << msg;
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
    // No line to name: the message is "PATH: cannot open the file (...)".
    EXPECT_EQ(std::string(e.what()), path + ": cannot open the file (expected a YAML actuator table)");
  }
}

TEST(LoadActuators, MalformedYaml) { expect_error("malformed.yaml", 8, "malformed YAML: end of map flow not found"); }
TEST(LoadActuators, EmptyFile) { expect_error("empty.yaml", 1, "expected a map with the key 'actuators'"); }
TEST(LoadActuators, NotAMap) { expect_error("not_a_map.yaml", 2, "expected a map with the key 'actuators'"); }
TEST(LoadActuators, UnknownTopLevelKey) {
  expect_error("unknown_top_key.yaml", 2, "unknown top-level key 'actuator' (expected one of: actuators)");
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
  expect_error("not_a_number.yaml", 8, "actuator 'l_knee': 'K_s_N_per_m' must be a finite number (N/m)");
}
TEST(LoadActuators, UnknownKind) {
  expect_error("unknown_kind.yaml", 4, "actuator 'l_knee': unknown kind 'SEA' (expected RFSEA or FSEA)");
}
TEST(LoadActuators, FseaHasNoReactionMass) {
  expect_error("fsea_reaction_mass.yaml", 10, "'M_r_kg' applies to an RFSEA only");
}
TEST(LoadActuators, DuplicateJoint) {
  expect_error("duplicate_joint.yaml", 24, "joint 'l_knee' has a second actuator");
}
TEST(LoadActuators, BadLinkageSign) {
  expect_error("bad_sign.yaml", 16, "actuator 'l_knee' linkage: 'sign' must be +1 or -1, got 0.5");
}
TEST(LoadActuators, NonPositiveLiquidResistance) {
  expect_error("bad_liquid_resistance.yaml", 19, "thermal: 'R_ha_liquid_K_per_W' must be > 0 (K/W), got -0.1");
}
