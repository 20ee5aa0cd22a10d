// Robots that are not DRACO, and DRACO renamed (issue 26): operational space control on a
// robot with ideal joints (its torques drive the joints, no pass-through diagrams), a
// hopper standing on a box, a cylinder and a mesh foot under joint PD diagrams, a copy of
// DRACO with every link and joint renamed that balances with a log bit-identical to
// DRACO's, balancing refused on a robot without the named feet, and a bus controller and
// an experiment registered at run time and run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <regex>
#include <set>
#include <tuple>

#include "contact_fixtures.hpp"
#include "dmbd/base/error.hpp"
#include "dmbd/control/registry.hpp"
#include "dmbd/experiments/registry.hpp"
#include "dmbd/scenario/run_directory.hpp"
#include "dmbd/report/report.hpp"
#include "dmbd/scenario/evaluate.hpp"
#include "dmbd/scenario/scenario.hpp"
#include "sim_test_support.hpp"

namespace {

namespace fs = std::filesystem;
using dmbd::InputError;
using dmbd::sim::test::read_text;
using dmbd::sim::test::TempDir;
using dmbd::sim::test::write_text;
namespace sc = dmbd::scenario;

const std::string kSource = DMBD_SOURCE_DIR;
const std::string kArm = kSource + "/tests/scenario/data/arm3.urdf";
const std::string kPd = kSource + "/examples/diagrams/joint_pd_torque.yaml";

dmbd::sim::VariantResult run_only(const std::string& path, std::optional<double> duration = std::nullopt) {
  const sc::Scenario s = sc::load_scenario(path);
  sc::RunOptions o;
  o.duration_s = duration;
  return sc::run_variant(s, s.variants.front(), o);
}

double largest(const std::vector<double>& x) { return *std::max_element(x.begin(), x.end()); }
double smallest(const std::vector<double>& x) { return *std::min_element(x.begin(), x.end()); }

// ---------------------------------------------------------------- operational space control

// The arm's hand follows a 3-D path (0.1 m, 0.1 m, 0.05 m at 0.5 Hz) on ideal joints: the
// controller's torques drive them (J.torque = J.tau_d), within 1 cm after the ramp.
TEST(RobotsOsc, IdealJointsFollowTheirTorquesAndTheHandItsPath) {
  TempDir dir;
  const std::string path = dir.file("arm_osc.yaml");
  write_text(path, "name: arm_osc\nrobot: {urdf: " + kArm + ", base: fixed, initial: {shoulder: -0.4, elbow: 1.2}}\n"
                   "integration: {mode: fixed, step_s: 0.0005}\nduration_s: 3\nlog_rate_hz: 500\n"
                   "bus_controllers:\n  - {type: osc, link: hand, kp: (2*pi*5)^2, kd: 2*(2*pi*5),\n"
                   "     trajectory: {amplitude_m: [0.1, 0.1, 0.05], frequency_hz: 0.5, ramp_s: 0.5}}\n");
  const dmbd::sim::VariantResult r = run_only(path);
  const auto& t = r.log.time();
  double worst = 0, travel = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (t[k] < 1.0) continue;
    double e2 = 0;
    for (const char* a : {"x", "y", "z"}) e2 += std::pow(r.log.column(std::string("osc.") + a + "_d")[k] - r.log.column(std::string("osc.") + a)[k], 2);
    worst = std::max(worst, std::sqrt(e2));
    travel = std::max(travel, std::abs(r.log.column("osc.x_d")[k] - r.log.column("osc.x_d")[0]));
  }
  std::printf("arm OSC on ideal joints: largest error %.3g m over t >= 1 s (path travels %.3g m)\n", worst, travel);
  EXPECT_GT(travel, 0.09);  // the path moved
  EXPECT_LT(worst, 0.01);
  // A command output: the torque the controller computed is what drives each joint.
  for (const char* j : {"yaw", "shoulder", "elbow"}) {
    const auto& cmd = r.log.column(std::string(j) + ".torque");
    EXPECT_EQ(cmd, r.log.column(std::string(j) + ".tau_d")) << j;
    EXPECT_GT(largest(cmd) - smallest(cmd), 0.1) << j;
  }
}

// ---------------------------------------------------------------- a user's actuator file

// The arm given as a URDF alone with an actuator file of its user's (robot.actuators:
// {file, joints}): the shoulder on a rotary geared motor, the elbow on a rotary
// series-elastic actuator, the yaw an ideal joint (listed as such). Each joint's current
// comes from a PD on its angle (joint_pd_current.yaml): the actuator signals are logged
// in their units, the elbow's spring torque is K_s times its twist, the windings warm,
// and the report names the user's robot (the URDF's robot name).
TEST(RobotsActuators, AUsersUrdfWithItsOwnActuatorFileOfBothRotaryKinds) {
  TempDir dir;
  write_text(dir.file("arm_actuators.yaml"), R"(format: 1
actuators:
  - joint: shoulder
    kind: rotary
    J_m_kgm2: 2.0e-5
    gear_ratio: 80
    k_tau_Nm_per_A: 0.06
    current_limit_A: 20
    torque_limit_Nm: 60
    efficiency: 0.8
    viscous_friction_Nms: 0.05
    coulomb_friction_Nm: 0.2
    thermal: &t {R_winding_ohm: 0.4, alpha_per_K: 0.00393, C_winding_J_per_K: 15, C_housing_J_per_K: 100,
                 R_wh_K_per_W: 1.5, R_ha_air_K_per_W: 5.0, R_ha_liquid_K_per_W: 5.0, T_ambient_C: 25, T_winding_max_C: 120}
    motor_encoder: &e {counts_per_unit: 2607.59}
  - joint: elbow
    kind: rotary_sea
    J_m_kgm2: 2.0e-5
    gear_ratio: 80
    K_s_Nm_per_rad: 400
    B_s_Nms_per_rad: 2
    k_tau_Nm_per_A: 0.06
    current_limit_A: 20
    torque_limit_Nm: 40
    efficiency: 0.8
    viscous_friction_Nms: 0.05
    coulomb_friction_Nm: 0.2
    thermal: *t
    motor_encoder: *e
    spring_encoder: {counts_per_unit: 20860.76}
)");
  const std::string pdc = kSource + "/examples/diagrams/joint_pd_current.yaml";
  std::string yaml = "name: arm_rotary\nrobot: {urdf: " + kArm + ", base: fixed, initial: {shoulder: -0.4, elbow: 1.2},\n"
                     "        actuators: {file: arm_actuators.yaml, joints: all}}\n"
                     "integration: {mode: fixed, step_s: 0.0005}\nsensors: {noise: true, seed: 3}\nduration_s: 1\nlog_rate_hz: 500\n"
                     "references: {shoulder_d: -0.4, elbow_d: 1.2, zero: 0, yaw_d: 0}\ncontrollers:\n";
  // The shoulder's loop at 5 Hz: a PD has a static error of its gravity load over Kp
  // (about 10 N m over 444 N m/rad = 0.023 rad here; at 3 Hz it would be 0.064 rad). The
  // elbow's stays at 3 Hz, well below its spring mode (sqrt(K_s / J_m N^2) = 8.9 Hz).
  for (const auto& [j, inertia, f_c] : {std::tuple<const char*, double, int>{"shoulder", 0.45, 5}, {"elbow", 0.15, 3}})
    yaml += std::string("  - {name: ") + j + ", diagram: " + pdc + ", rate_hz: 1000, implementation: generated,\n" +
            "     parameters: {I_j: " + std::to_string(inertia) + ", f_c: " + std::to_string(f_c) +
            ", N: 80, k_tau: 0.06, eta: 0.8, tau_max: 40},\n" +
            "     inputs: {q_d: " + j + "_d, qd_d: zero, tau_ff: zero, q: " + j + ".q, qd: " + j + ".qd}, outputs: {i: " + j + ".current}}\n";
  yaml += "  - {name: yaw, diagram: " + kPd + ", rate_hz: 1000, parameters: {Kp: 50, Kd: 5},\n"
          "     inputs: {q_d: yaw_d, qd_d: zero, tau_ff: zero, q: yaw.q, qd: yaw.qd}, outputs: {torque: yaw.torque}}\n";
  write_text(dir.file("arm_rotary.yaml"), yaml);
  const sc::Scenario s = sc::load_scenario(dir.file("arm_rotary.yaml"));
  const std::vector<std::string> notes = sc::scenario_notes(s);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("1 joint(s) without an entry in " + dir.file("arm_actuators.yaml") + ", driven by ideal joint torques: yaw"),
            std::string::npos)
      << notes[0];
  const sc::ScenarioRun run = sc::run_scenario(s, dir.file("out"));
  const dmbd::sim::Log& log = run.runs.front().log;
  EXPECT_EQ(log.unit(log.find("shoulder.force")), "N m");  // the rigid motor's current-based estimate
  EXPECT_EQ(log.unit(log.find("elbow.force")), "N m");     // the spring's torque
  EXPECT_EQ(log.unit(log.find("elbow.spring_deflection")), "rad");
  EXPECT_LT(log.find("shoulder.spring_deflection"), 0);  // a rigid gear has no spring
  EXPECT_LT(log.find("shoulder.q_pot"), 0);              // no potentiometer given
  const auto& twist = log.column("elbow.force_true");
  EXPECT_GT(std::abs(twist.back()), 1.0);  // the spring carries the forearm
  for (const char* j : {"shoulder", "elbow"}) {
    EXPECT_GT(largest(log.column(std::string(j) + ".T_winding")), 25.0) << j;  // the currents warm the windings
    EXPECT_GT(std::abs(log.column(std::string(j) + ".current_applied").back()), 0.1) << j;
  }
  std::printf("rotary shoulder: static error %.4f rad; elbow spring torque %.3f N m\n", log.column("shoulder.q").back() + 0.4, twist.back());
  EXPECT_LT(std::abs(log.column("shoulder.q").back() + 0.4), 0.035);
  EXPECT_TRUE(run.runs.front().sil.has_value());  // the two PDs ran as their generated code
  const std::string page = dmbd::report::write_report(run, dir.file("out"), [] {
                             dmbd::report::ReportOptions o;
                             o.frames = false;
                             return o;
                           }())
                               .page;
  EXPECT_NE(read_text(page).find("arm3 (" + kArm + ")"), std::string::npos);  // the URDF's robot name
}

// ---------------------------------------------------------------- feet of every shape

// The hopper (floating torso, thigh, shank, a foot of the given collision geometry)
// under a 1 kHz joint PD from a diagram, 2 s: its torso height stays within 1 cm and its
// foot's contact force carries its weight.
void stands(const std::string& foot, const std::string& dir, const std::string& what) {
  SCOPED_TRACE(what);
  write_text(dir + "/hopper.urdf", dmbd::model::testing::hopper_urdf(foot));
  std::string yaml = "name: hopper\nrobot: {urdf: hopper.urdf, base: floating, contact: true, initial: {hip: 0.2, knee: -0.4, ankle: 0.2}}\n"
                     "integration: {mode: fixed, step_s: 0.0005}\nduration_s: 2\nlog_rate_hz: 200\n"
                     "references: {hip_d: 0.2, knee_d: -0.4, ankle_d: 0.2, zero: 0}\ncontrollers:\n";
  for (const auto& [j, kp, kd] : {std::tuple<const char*, int, int>{"hip", 400, 8}, {"knee", 400, 8}, {"ankle", 200, 2}})
    yaml += std::string("  - {name: ") + j + ", diagram: " + kPd + ", rate_hz: 1000, parameters: {Kp: " + std::to_string(kp) +
            ", Kd: " + std::to_string(kd) + "},\n     inputs: {q_d: " + j + "_d, qd_d: zero, tau_ff: zero, q: " + j + ".q, qd: " + j +
            ".qd}, outputs: {torque: " + j + ".torque}}\n";
  write_text(dir + "/hopper.yaml", yaml);
  const dmbd::sim::VariantResult r = run_only(dir + "/hopper.yaml");
  ASSERT_FALSE(r.log.time().empty());
  EXPECT_DOUBLE_EQ(r.log.time().back(), 2.0);
  const auto& z = r.log.column("base.z");
  const double mass = 6.0 + 1.5 + 1.0 + 0.5;
  // Contact signals per collision shape: the torso's box (0), thigh (1), shank (2), foot (3).
  ASSERT_GE(r.log.find("contact.3.fz"), 0);
  ASSERT_LT(r.log.find("contact.4.fz"), 0);
  std::printf("hopper on a %s foot: torso height %.4f .. %.4f m over 2 s, foot force %.2f N (weight %.2f N)\n", what.c_str(), smallest(z),
              largest(z), r.log.column("contact.3.fz").back(), mass * 9.81);
  EXPECT_LT(largest(z) - smallest(z), 0.01);
  EXPECT_NEAR(r.log.column("contact.3.fz").back(), mass * 9.81, 0.05 * mass * 9.81);  // the foot carries the weight
  for (int k = 0; k < 3; ++k) EXPECT_EQ(largest(r.log.column("contact." + std::to_string(k) + ".fz")), 0.0) << k;
}

TEST(RobotsFeet, AHopperStandsOnABoxACylinderAndAMeshFoot) {
  TempDir dir;
  stands(dmbd::model::testing::box_xml({0.24, 0.12, 0.06}), dir.file(""), "box");
  stands(dmbd::model::testing::cylinder_xml(0.08, 0.06), dir.file(""), "cylinder");
  dmbd::model::testing::write_box_obj(dir.file("foot.obj"), {0.24, 0.12, 0.06});
  stands("<mesh filename=\"foot.obj\"/>", dir.file(""), "mesh");
}

// A box on a slope (robot.ground_normal tilted by theta about y): held by friction
// (mu = 0.8) at 20 degrees, sliding down at 45 degrees (tan 45 = 1 > mu) with the
// sliding acceleration g (sin - mu cos) along the slope.
TEST(RobotsFeet, ABoxHoldsOnAGentleSlopeAndSlidesDownASteepOne) {
  TempDir dir;
  write_text(dir.file("box.urdf"), "<robot name=\"box\"><link name=\"box\">" +
                                       dmbd::model::testing::inertial(2.0, dmbd::model::testing::box_inertia(2.0, {0.2, 0.2, 0.1})) +
                                       "<collision><geometry>" + dmbd::model::testing::box_xml({0.2, 0.2, 0.1}) +
                                       "</geometry></collision></link></robot>\n");
  for (const double deg : {20.0, 45.0}) {
    const double th = deg * M_PI / 180;
    write_text(dir.file("slope.yaml"), "name: slope\nrobot: {urdf: box.urdf, base: floating, contact: true, base_pose: {rpy: [0, " +
                                           std::to_string(-th) + ", 0]},\n        ground_normal: [" + std::to_string(-std::sin(th)) + ", 0, " +
                                           std::to_string(std::cos(th)) + "]}\nintegration: {mode: fixed, step_s: 0.0005}\nduration_s: 1\n"
                                           "log_rate_hz: 100\n");
    const dmbd::sim::VariantResult r = run_only(dir.file("slope.yaml"));
    const auto& x = r.log.column("base.x");
    const double moved = x.back() - x[50];  // over the last 0.5 s, along world x (down-slope is -x here)
    std::printf("box on a %.0f degree slope: moved %.4g m along x over 0.5 s\n", deg, moved);
    if (deg < 30) {
      EXPECT_LT(std::abs(moved), 1e-3);
    } else {
      const double a = 9.81 * (std::sin(th) - 0.8 * std::cos(th));  // along the slope
      const double expected = -0.5 * a * std::cos(th) * (1.0 - 0.25);  // s(1) - s(0.5) from rest at t = 0, its horizontal part (down: -x)
      EXPECT_NEAR(moved, expected, 0.05 * std::abs(expected));
    }
  }
}

// ---------------------------------------------------------------- DRACO renamed

// Every link and joint name of the URDF, longest first.
std::vector<std::string> urdf_names(const std::string& urdf) {
  std::set<std::string> names;
  const std::regex tag("<(link|joint) name=\"([^\"]+)\"");
  for (std::sregex_iterator it(urdf.begin(), urdf.end(), tag), end; it != end; ++it) names.insert((*it)[2]);
  std::vector<std::string> v(names.begin(), names.end());
  std::sort(v.begin(), v.end(), [](const std::string& a, const std::string& b) { return a.size() > b.size(); });
  return v;
}

// Each whole name (not part of a longer word) prefixed with "renamed_".
std::string renamed(std::string text, const std::vector<std::string>& names) {
  std::string alternatives;
  for (const auto& n : names) alternatives += (alternatives.empty() ? "" : "|") + n;
  return std::regex_replace(text, std::regex("\\b(" + alternatives + ")\\b"), "renamed_$1");
}

// A copy of robots/draco with every link and joint renamed (URDF names and references,
// the actuator file's joints, robot.yaml's controller options) balances with the same
// log, value for value, as DRACO: no name is built into the controllers.
TEST(RobotsRenamed, ACopyOfDracoWithEveryNameChangedBalancesBitForBit) {
  TempDir dir;
  const fs::path from = kSource + "/robots/draco", to = fs::path(dir.file("renamed_draco"));
  fs::copy(from, to, fs::copy_options::recursive);
  const std::string urdf = read_text((from / "draco.urdf").string());
  const std::vector<std::string> names = urdf_names(urdf);
  write_text((to / "draco.urdf").string(),
             std::regex_replace(urdf, std::regex("(name|link)=\"(" + [&] {
                                                   std::string a;
                                                   for (const auto& n : names) a += (a.empty() ? "" : "|") + n;
                                                   return a;
                                                 }() + ")\""),
                                "$1=\"renamed_$2\""));
  for (const char* f : {"actuators.yaml", "robot.yaml"}) write_text((to / f).string(), renamed(read_text((from / f).string()), names));
  const std::string shipped = std::regex_replace(read_text(kSource + "/examples/scenarios/balance.yaml"), std::regex("\\.\\./diagrams/"),
                                                 kSource + "/examples/diagrams/");
  write_text(dir.file("draco.yaml"), shipped);
  std::string copy = renamed(shipped, names);
  copy = std::regex_replace(copy, std::regex("name: draco\\b"), "name: renamed_draco");
  copy = std::regex_replace(copy, std::regex("leg: l_"), "leg: renamed_l_");
  copy = std::regex_replace(copy, std::regex("task_gains: \\{renamed_torso:"), "task_gains: {torso:");  // an option, not the link
  write_text(dir.file("renamed.yaml"), copy);
  const sc::Scenario a = sc::load_scenario(dir.file("draco.yaml")), b = sc::load_scenario(dir.file("renamed.yaml"));
  ASSERT_EQ(b.variants.front().robot.folder->dir, to.string());
  sc::RunOptions o;
  o.duration_s = 5.0;  // the start-up and the first steps
  const dmbd::sim::VariantResult ra = sc::run_variant(a, a.variants.front(), o), rb = sc::run_variant(b, b.variants.front(), o);
  ASSERT_EQ(ra.log.columns(), rb.log.columns());
  ASSERT_GT(ra.log.rows(), 900u);
  for (std::size_t c = 0; c < ra.log.columns(); ++c) {
    const std::string na = ra.log.name(static_cast<int>(c));
    const std::string nb = c == 0 ? na : renamed(na, names);
    ASSERT_EQ(rb.log.name(static_cast<int>(c)), nb);
    EXPECT_EQ(ra.log.column(static_cast<int>(c)), rb.log.column(static_cast<int>(c))) << na;  // bit for bit
  }
  EXPECT_GT(ra.log.column("balance.touch_downs").back(), 0.0);  // it stepped
  // The balance experiment's metrics of both, equal (wall-clock figures aside; the joints
  // they name, renamed).
  auto metrics = [](const sc::Scenario& s, const dmbd::sim::VariantResult& r) {
    nlohmann::json m = sc::evaluate_experiment(s, {r}).metrics["balance"];
    for (auto& [name, v] : m.items()) {
      v.erase("wbc_tick_us");
      v.erase("real_time_factor");
    }
    return m;
  };
  EXPECT_EQ(renamed(metrics(a, ra).dump(), names), metrics(b, rb).dump());
}

// Balancing names the robot's torso, feet and joints: on a robot whose folder gives none
// (a URDF alone) the first option it lacks is named; a foot it does not have, too.
TEST(RobotsRenamed, BalancingARobotWithoutTheNamedFeetIsRefusedNamingTheOption) {
  TempDir dir;
  const std::string path = dir.file("b.yaml");
  const std::string head = "name: b\nrobot: {urdf: " + kArm + ", base: floating, contact: true}\nduration_s: 0.01\n";
  write_text(path, head + "bus_controllers: [{type: balance}]\n");
  try {
    run_only(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("balance: option 'foot_links' is not set"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind(path + ":4:", 0), 0u) << e.what();
  }
  write_text(path, head + "bus_controllers: [{type: balance, foot_links: [left_foot, right_foot], torso_link: stand}]\n");
  try {
    run_only(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("balance: the robot has no link '"), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------- registered at run time

// A bus controller of the test's own: holds every joint at its initial angle by a PD on
// ideal torques (options kp, kd).
struct HoldOptions : dmbd::control::BusControllerOptions {
  double kp = 0, kd = 0;
};

class Hold : public dmbd::control::BusController {
 public:
  Hold(const HoldOptions& o, const dmbd::control::BusControllerContext& c) : BusController(o, 1 << 20), o_(o) {
    for (const auto& [joint, q] : c.q0) {
      const int j = c.robot.joint_index(joint);
      if (c.robot.joints[static_cast<std::size_t>(j)].type == dmbd::model::JointType::Fixed) continue;
      add_input(joint + ".q");
      add_input(joint + ".qd");
      add_output(joint + ".torque", "N m");
      q0_.push_back(q);
    }
  }
  std::string timing_name() const override { return "hold"; }

 protected:
  void tick(const double* u, double* y) override {
    for (std::size_t j = 0; j < q0_.size(); ++j) y[j] = o_.kp * (q0_[j] - u[2 * j]) - o_.kd * u[2 * j + 1];
  }

 private:
  HoldOptions o_;
  std::vector<double> q0_;
};

class HoldType : public dmbd::control::BusControllerType {
 public:
  std::shared_ptr<dmbd::control::BusControllerOptions> read(const dmbd::yaml::Fields& f, const YAML::Node& n,
                                                           const dmbd::control::BusControllerOptions* base) const override {
    f.keys(n, "hold", {"type", "name", "rate_hz", "delay_s", "kp", "kd"});
    auto o = std::make_shared<HoldOptions>();
    if (const auto* b = dynamic_cast<const HoldOptions*>(base)) *o = *b;
    o->type = o->name = "hold";
    o->where = f.at(n);
    dmbd::control::read_common_options(f, n, *o);
    f.optional(n, "kp", [&](const YAML::Node& x) { o->kp = f.positive(x, "hold.kp"); });
    f.optional(n, "kd", [&](const YAML::Node& x) { o->kd = f.positive(x, "hold.kd"); });
    return o;
  }
  std::shared_ptr<dmbd::control::BusController> make(const dmbd::control::BusControllerOptions& o,
                                                     const dmbd::control::BusControllerContext& c) const override {
    return std::make_shared<Hold>(dynamic_cast<const HoldOptions&>(o), c);
  }
};

// An experiment of the test's own: the largest |torque| of the experiment's joint.
class PeakTorque : public dmbd::experiments::Experiment {
 public:
  std::map<std::string, dmbd::experiments::KeyKind> keys() const override { return {}; }
  bool needs_joint() const override { return true; }
  dmbd::experiments::ExperimentResult evaluate(const dmbd::experiments::ExperimentSetup& e, const std::vector<dmbd::sim::VariantResult>& runs,
                                               const std::vector<dmbd::experiments::VariantFacts>&) const override {
    dmbd::experiments::ExperimentResult res;
    for (const auto& r : runs) {
      double peak = 0;
      for (double x : r.log.column(e.joint + ".torque")) peak = std::max(peak, std::abs(x));
      res.metrics["peak_torque_Nm"][r.name] = peak;
    }
    return res;
  }
};

TEST(RobotsRegistry, ABusControllerAndAnExperimentRegisteredAtRunTimeRun) {
  dmbd::control::register_bus_controller("hold", std::make_shared<HoldType>());
  dmbd::experiments::register_experiment("peak_torque", std::make_shared<PeakTorque>());
  const std::vector<std::string> types = dmbd::control::bus_controller_types();
  EXPECT_EQ(types, (std::vector<std::string>{"balance", "hold", "osc"}));
  TempDir dir;
  const std::string path = dir.file("hold.yaml");
  write_text(path, "name: hold\nrobot: {urdf: " + kArm + ", base: fixed, initial: {shoulder: -0.4, elbow: 1.2}}\n"
                   "integration: {mode: fixed, step_s: 0.0005}\nduration_s: 1\nlog_rate_hz: 500\n"
                   "bus_controllers: [{type: hold, kp: 400, kd: 40, rate_hz: 500}]\nexperiment: {type: peak_torque, joint: shoulder}\n");
  const sc::Scenario s = sc::load_scenario(path);
  const sc::ScenarioRun run = sc::run_scenario(s, dir.file("out"));
  const dmbd::sim::VariantResult& r = run.runs.front();
  EXPECT_EQ(r.controller_steps, (std::vector<long long>{501}));  // 500 Hz from t = 0 to 1 s
  // Held against gravity: the shoulder stays within a few mrad of its start, its torque
  // what the experiment reports.
  const auto& q = r.log.column("shoulder.q");
  EXPECT_LT(std::abs(q.back() + 0.4), 0.05);
  double peak = 0;
  for (double x : r.log.column("shoulder.torque")) peak = std::max(peak, std::abs(x));
  EXPECT_GT(peak, 1.0);
  EXPECT_EQ(run.metrics["peak_torque_Nm"]["base"].get<double>(), peak);
  // An unknown type is named with the known ones.
  write_text(path, "name: x\nrobot: {urdf: " + kArm + "}\nbus_controllers: [{type: hodl}]\n");
  try {
    sc::load_scenario(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":3:26: bus_controllers: unknown type 'hodl' (one of: balance, hold, osc)"), std::string::npos)
        << e.what();
  }
}

}  // namespace
