// The actuator file as a versioned contract (docs/actuator-format.md): `format: 1`
// required, the rotary kinds' keys and defaults, keys of another kind, the transmission
// methods of ActuatorParams, the table checked against a robot, and a rotary actuator's
// thermal parameters read and used.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "actuator_fixtures.hpp"
#include "robot_files.hpp"
#include "dmbd/model/actuator.hpp"
#include "dmbd/model/error.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/model/thermal.hpp"

namespace dm = dmbd::model;
using dmbd::model::testing::replaced;
using dmbd::model::testing::text_of;
namespace {
std::string fixture(const std::string& name) { return dmbd::model::testing::actuator_fixture(name); }
}  // namespace

namespace {

std::string write_table(const std::string& text) {
  const std::string path =
      (std::filesystem::temp_directory_path() / ("dmbd_actuator_format_" + std::to_string(::getpid()) + ".yaml")).string();
  std::ofstream(path) << text;
  return path;
}

// The ModelError of loading `text` (written to a file), "" if it loads.
std::string error_of_text(const std::string& text, std::string* path_out = nullptr) {
  const std::string path = write_table(text);
  if (path_out) *path_out = path;
  std::string msg;
  try {
    dm::load_actuators(path);
  } catch (const dm::ModelError& e) {
    msg = e.what();
  }
  std::filesystem::remove(path);
  return msg;
}

// The single-line message starts with "PATH:LINE:" followed by a column, and contains `what`.
void expect_located(const std::string& text, int line, const std::string& what) {
  std::string path;
  const std::string msg = error_of_text(text, &path);
  const std::string prefix = path + ":" + std::to_string(line) + ":";
  EXPECT_EQ(msg.rfind(prefix, 0), 0u) << "expected prefix '" << prefix << "', got: " << msg;
  EXPECT_TRUE(prefix.size() < msg.size() && std::isdigit(static_cast<unsigned char>(msg[prefix.size()]))) << msg;
  EXPECT_NE(msg.find(what), std::string::npos) << "expected '" << what << "' in: " << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
}

const std::string& rotary_text() {
  static const std::string t = text_of(fixture("rotary.yaml"));
  return t;
}

}  // namespace

TEST(ActuatorFormat, ReadsRotaryAndRotarySeaWithTheirDefaults) {
  const auto acts = dm::load_actuators(fixture("rotary.yaml"));
  ASSERT_EQ(acts.size(), 2u);
  const dm::ActuatorParams& r = acts[0];
  EXPECT_EQ(r.joint, "shoulder");
  EXPECT_EQ(r.kind, dm::ActuatorKind::ROTARY);
  EXPECT_TRUE(r.is_rotary());
  EXPECT_FALSE(r.has_spring());
  EXPECT_EQ(r.where, fixture("rotary.yaml") + ":3:5");
  EXPECT_DOUBLE_EQ(r.J_m_kgm2, 3.3e-5);
  EXPECT_DOUBLE_EQ(r.N_m_rad_per_m, 50);  // gear_ratio
  EXPECT_DOUBLE_EQ(r.k_tau_Nm_per_A, 0.12);
  EXPECT_DOUBLE_EQ(r.current_limit_A, 10);
  EXPECT_DOUBLE_EQ(r.torque_limit_Nm, 40);
  EXPECT_DOUBLE_EQ(r.efficiency, 0.85);
  EXPECT_DOUBLE_EQ(r.viscous_friction_Nms, 0.3);
  EXPECT_DOUBLE_EQ(r.coulomb_friction_Nm, 1.5);
  EXPECT_EQ(r.coulomb_velocity_rad_s, 1e-3);  // default
  EXPECT_EQ(r.B_m_Nms, 0.0);                  // default
  EXPECT_EQ(r.B_l_Ns_per_m, 0.0);             // no load: map
  EXPECT_EQ(r.K_s_N_per_m, 0.0);              // no spring
  EXPECT_EQ(r.M_r_kg, 0.0);
  EXPECT_FALSE(r.has_potentiometer);          // optional for rotary kinds
  EXPECT_DOUBLE_EQ(r.thermal.R_winding_ohm, 0.6);
  EXPECT_DOUBLE_EQ(r.motor_encoder.counts_per_unit, 651.8986469044033);
  EXPECT_DOUBLE_EQ(r.force_limit(), 40);

  const dm::ActuatorParams& s = acts[1];
  EXPECT_EQ(s.joint, "elbow");
  EXPECT_EQ(s.kind, dm::ActuatorKind::ROTARY_SEA);
  EXPECT_TRUE(s.is_rotary());
  EXPECT_TRUE(s.has_spring());
  EXPECT_EQ(s.where, fixture("rotary.yaml") + ":18:5");
  EXPECT_DOUBLE_EQ(s.B_m_Nms, 1.0e-5);
  EXPECT_DOUBLE_EQ(s.N_m_rad_per_m, 100);
  EXPECT_DOUBLE_EQ(s.K_s_N_per_m, 350);   // K_s_Nm_per_rad
  EXPECT_DOUBLE_EQ(s.B_s_Ns_per_m, 0.8);  // B_s_Nms_per_rad
  EXPECT_DOUBLE_EQ(s.coulomb_velocity_rad_s, 2.0e-3);
  EXPECT_DOUBLE_EQ(s.B_l_Ns_per_m, 0.05);  // load: B_l_Nms_per_rad
  EXPECT_DOUBLE_EQ(s.spring_encoder.counts_per_unit, 2.0e5);
  EXPECT_TRUE(s.has_potentiometer);
  EXPECT_EQ(s.potentiometer.cutoff_hz, 50);
  EXPECT_DOUBLE_EQ(s.thermal.C_housing_J_per_K, 80);  // through the alias
}

// Both spellings of the VLCA kinds: DRACO's file writes rfsea/fsea, good.yaml RFSEA/FSEA.
TEST(ActuatorFormat, VlcaKindsInEitherCase) {
  const auto draco = dmbd::test::draco_actuators();
  const auto good = dm::load_actuators(fixture("good.yaml"));
  EXPECT_EQ(draco[3].kind, dm::ActuatorKind::RFSEA);
  EXPECT_EQ(draco[4].kind, dm::ActuatorKind::FSEA);
  EXPECT_EQ(good[0].kind, dm::ActuatorKind::RFSEA);
  EXPECT_EQ(good[1].kind, dm::ActuatorKind::FSEA);
  EXPECT_EQ(std::string(dm::kind_name(dm::ActuatorKind::ROTARY_SEA)), "rotary_sea");
  EXPECT_EQ(good[0].where, fixture("good.yaml") + ":3:5");
}

// The transmission: a gear's r = 1, r' = 0, travel q; a linkage's the LinkageGeometry's,
// the same numbers (not recomputed: DRACO's results must not move).
TEST(ActuatorFormat, TransmissionMethodsPerKind) {
  const auto rot = dm::load_actuators(fixture("rotary.yaml"));
  for (const auto& p : rot) {
    for (double q : {-1.3, 0.0, 0.7}) {
      EXPECT_EQ(p.moment_arm(q), 1.0);
      EXPECT_EQ(p.dmoment_arm_dq(q), 0.0);
      EXPECT_EQ(p.N_l(q), 1.0);
      EXPECT_EQ(p.travel(q), q);
      EXPECT_EQ(p.angle_for_travel(q, 5.0), q);
    }
  }
  const dm::ActuatorParams knee = dm::load_actuators(fixture("good.yaml"))[0];
  for (double q : {0.1, 0.9, 2.0}) {
    EXPECT_EQ(knee.moment_arm(q), knee.linkage.moment_arm_m(q));
    EXPECT_EQ(knee.dmoment_arm_dq(q), knee.linkage.dmoment_arm_dq_m(q));
    EXPECT_EQ(knee.N_l(q), knee.linkage.N_l(q));
    EXPECT_EQ(knee.travel(q), knee.linkage.length_m(q) - knee.linkage.length_m(0.0));
    // Newton's inverse: back to q to 1e-12 rad from a guess 0.3 rad off.
    EXPECT_NEAR(knee.angle_for_travel(knee.travel(q), q + 0.3), q, 1e-12);
  }
}

// The current the plant applies at most: the torque limit through eta k_tau N, or the
// current limit, whichever is lower; a VLCA's is its current limit.
TEST(ActuatorFormat, AppliedCurrentLimitHonoursTheTorqueLimit) {
  const auto rot = dm::load_actuators(fixture("rotary.yaml"));
  // shoulder: 40 / (0.85 * 50 * 0.12) = 7.843 A < 10 A.
  EXPECT_NEAR(rot[0].applied_current_limit_A(), 40.0 / (0.85 * 50 * 0.12), 1e-14);
  EXPECT_NEAR(rot[0].efficiency * rot[0].force_per_amp_N_per_A() * rot[0].applied_current_limit_A(), 40.0, 1e-12);
  // elbow: 60 / (0.8 * 100 * 0.05) = 15 A > 12 A: the current limit.
  EXPECT_EQ(rot[1].applied_current_limit_A(), 12.0);
  const dm::ActuatorParams knee = dm::load_actuators(fixture("good.yaml"))[0];
  EXPECT_EQ(knee.applied_current_limit_A(), knee.current_limit_A);
}

// ---- errors, each one line at its place ----------------------------------------------

TEST(ActuatorFormat, FormatIsRequired) {
  expect_located(replaced(rotary_text(), "format: 1  #", "#"), 1, "missing 'format: 1'");
}

TEST(ActuatorFormat, UnknownFormatVersionIsNamed) {
  expect_located(replaced(rotary_text(), "format: 1", "format: 2"), 1,
                 "unknown format '2' (this version of dmbd reads format 1)");
}

TEST(ActuatorFormat, UnknownKindListsTheKinds) {
  expect_located(replaced(rotary_text(), "kind: rotary_sea", "kind: harmonic"), 19,
                 "actuator 'elbow': unknown kind 'harmonic' (expected rfsea, fsea, rotary or rotary_sea)");
}

TEST(ActuatorFormat, AJointListedTwiceNamesTheFirstsLine) {
  expect_located(replaced(rotary_text(), "joint: elbow", "joint: shoulder"), 18,
                 "joint 'shoulder' has a second actuator (the first is at line 3)");
}

TEST(ActuatorFormat, UnknownKeyListsTheKindsKeys) {
  expect_located(replaced(rotary_text(), "gear_ratio: 50 ", "gear_ration: 50"), 6,
                 "actuator 'shoulder': unknown key 'gear_ration' (expected one of: joint, kind, J_m_kgm2,");
}

TEST(ActuatorFormat, AKeyOfAnotherKindIsNamedAsSuch) {
  // A spring on a rigid rotary, a linkage on a gear.
  expect_located(replaced(rotary_text(), "    coulomb_friction_Nm: 1.5\n",
                          "    coulomb_friction_Nm: 1.5\n    K_s_Nm_per_rad: 300\n"),
                 13, "actuator 'shoulder': 'K_s_Nm_per_rad' applies to kind rotary_sea only, not rotary");
  expect_located(replaced(rotary_text(), "    coulomb_friction_Nm: 0.4\n",
                          "    coulomb_friction_Nm: 0.4\n    linkage: {a_m: 0.3, b_m: 0.05, gamma0_rad: 1, sign: 1}\n"),
                 31, "actuator 'elbow': 'linkage' applies to kind rfsea, fsea only, not rotary_sea");
}

TEST(ActuatorFormat, MissingRotaryKeyAtItsEntry) {
  expect_located(replaced(rotary_text(), "    torque_limit_Nm: 40           # below", "    # below"), 3,
                 "actuator 'shoulder': missing 'torque_limit_Nm'");
  expect_located(replaced(rotary_text(), "    K_s_Nm_per_rad: 350           # torsion spring\n", ""), 18,
                 "actuator 'elbow': missing 'K_s_Nm_per_rad'");
}

TEST(ActuatorFormat, LoadKeyInTheKindsUnit) {
  // A VLCA's load damping is along the actuator (N s/m), a rotary's at the joint.
  expect_located(replaced(rotary_text(), "B_l_Nms_per_rad: 0.05", "B_l_Ns_per_m: 0.05"), 32,
                 "actuator 'elbow': unknown load key 'B_l_Ns_per_m' (expected one of: B_l_Nms_per_rad)");
}

// ---- the table against the robot ------------------------------------------------------

namespace {

dm::Link link(const std::string& name) {
  dm::Link l;
  l.name = name;
  l.mass_kg = 1.0;
  l.inertia_kgm2 = 0.01 * Eigen::Matrix3d::Identity();
  return l;
}

dm::Joint joint(const std::string& name, dm::JointType t, const std::string& parent, const std::string& child) {
  dm::Joint j;
  j.name = name;
  j.type = t;
  j.parent = parent;
  j.child = child;
  j.axis = Eigen::Vector3d::UnitY();
  return j;
}

// base -shoulder (revolute)-> upper -elbow (fixed)-> lower -wrist (continuous)-> hand
//      -slide (prismatic)-> rail
dm::RobotDescription arm() {
  dm::RobotDescription r;
  r.name = "arm";
  for (const char* n : {"base", "upper", "lower", "hand", "rail"}) r.links.push_back(link(n));
  r.joints.push_back(joint("shoulder", dm::JointType::Revolute, "base", "upper"));
  r.joints.push_back(joint("elbow", dm::JointType::Fixed, "upper", "lower"));
  r.joints.push_back(joint("wrist", dm::JointType::Continuous, "lower", "hand"));
  r.joints.push_back(joint("slide", dm::JointType::Prismatic, "base", "rail"));
  return r;
}

std::string check_error(const std::vector<dm::ActuatorParams>& table, const dm::RobotDescription& robot) {
  try {
    dm::check_actuators_against(table, robot);
  } catch (const dm::ModelError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(ActuatorFormat, CheckedAgainstTheRobotAtTheEntrysLine) {
  const std::string path = fixture("rotary.yaml");
  auto table = dm::load_actuators(path);
  // shoulder is revolute; elbow is fixed in this robot.
  EXPECT_EQ(check_error(table, arm()),
            path + ":18:5: actuator 'elbow': joint 'elbow' of the robot 'arm' is fixed: it cannot move");
  table[1].joint = "wrist";  // continuous: fine
  EXPECT_EQ(check_error(table, arm()), "");
  table[0].joint = "knee";   // no such joint
  table[1].joint = "slide";  // prismatic
  EXPECT_EQ(check_error(table, arm()),
            path + ":3:5: actuator 'knee': the robot 'arm' has no joint 'knee'\n" + path +
                ":18:5: actuator 'slide': joint 'slide' of the robot 'arm' is prismatic; an actuator drives a revolute or "
                "continuous joint");
  // Built in code: no place in a file.
  dm::ActuatorParams p;
  p.joint = "hip";
  EXPECT_EQ(check_error({p}, arm()), "actuator table: actuator 'hip': the robot 'arm' has no joint 'hip'");
}

TEST(ActuatorFormat, MovingJointsWithoutAnEntryAreListed) {
  const auto table = dm::load_actuators(fixture("rotary.yaml"));  // shoulder, elbow
  EXPECT_EQ(dm::joints_without_actuator(table, arm()), (std::vector<std::string>{"wrist", "slide"}));
  EXPECT_EQ(dm::joints_without_actuator({}, arm()), (std::vector<std::string>{"shoulder", "wrist", "slide"}));
}

// ---- thermal: shared with the VLCAs --------------------------------------------------------

// The rotary entry's thermal block is read and drives the shared two-node model: at
// ambient, dT_w/dt = i^2 R_20 (1 + alpha (T_amb - 20)) / C_w, with the file's numbers
// (R_20 0.6 ohm, alpha 0.00393, T_amb 22 C, C_w 12 J/K), and a step of 10 s at 5 A
// warms the winding.
TEST(ActuatorFormat, RotaryThermalParametersAreReadAndUsed) {
  const dm::ActuatorParams p = dm::load_actuators(fixture("rotary.yaml"))[0];
  dm::ThermalModel m(p.thermal);
  m.reset();
  EXPECT_EQ(m.state().T_winding_C, 22.0);
  const double i = 5.0;
  const double expected = i * i * 0.6 * (1 + 0.00393 * (22 - 20)) / 12;  // K/s
  const double got = m.derivative(m.state(), i, false).T_winding_C;
  EXPECT_NEAR(got / expected, 1.0, 1e-12);
  m.step(i, 10.0, false);
  EXPECT_GT(m.state().T_winding_C, 22.0 + 10.0 * expected * 0.5);  // most of the initial slope over 10 s (tau_w ~ 14 s)
  EXPECT_LT(m.state().T_winding_C, 22.0 + 10.0 * expected);
}
