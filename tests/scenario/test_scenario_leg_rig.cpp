// The second shipped robot (robots/leg_rig: a single leg on a vertical rail) in its
// shipped scenario examples/scenarios/leg_rig.yaml: dropped 2 cm, it lands on its box
// sole and stands in a crouch under two generated joint PDs (a rotary hip, a rotary_sea
// knee), then squats. Checked against closed forms and the rig's statics: the touch-down
// time of the free fall, the foot carrying the weight on the rail, the knee's spring
// torque and the hip's current-based estimate against the torques the contact force
// needs, the gains against their stated rule; and the report names the robot and draws
// frames.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "dmbd/model/actuator.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/report/report.hpp"
#include "dmbd/scenario/run_directory.hpp"
#include "dmbd/scenario/scenario.hpp"
#include "robot_files.hpp"
#include "sim_test_support.hpp"

namespace {

namespace fs = std::filesystem;
using dmbd::scenario::ScenarioRun;

const std::string kScenario = std::string(DMBD_SOURCE_DIR) + "/examples/scenarios/leg_rig.yaml";
constexpr double kDrop_m = 0.02;                      // the sole's height at t = 0 (the scenario's initial rail)
constexpr double kStandFrom_s = 1.0, kSquat_s = 2.0;  // the last second of standing: [1, 2) s

// The shipped scenario run once for every test here (its controllers as generated code,
// as the file says), with its report.
class LegRig : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<dmbd::sim::test::TempDir>();
    const dmbd::scenario::Scenario s = dmbd::scenario::load_scenario(kScenario);
    run_ = std::make_unique<ScenarioRun>(dmbd::scenario::run_scenario(s, dir_->file("out")));
    dmbd::report::ReportOptions o;
    o.width_px = 320;
    o.height_px = 240;
    report_ = std::make_unique<dmbd::report::ReportResult>(dmbd::report::write_report(*run_, dir_->file("out"), o));
  }
  static void TearDownTestSuite() {
    report_.reset();
    run_.reset();
    dir_.reset();
  }
  static const dmbd::sim::Log& log() { return run_->runs.front().log; }
  static const std::vector<double>& col(const std::string& name) {
    EXPECT_GE(log().find(name), 0) << name << " is not logged";
    return log().column(name);
  }
  // Rows of the last second of standing.
  static std::vector<std::size_t> standing_rows() {
    std::vector<std::size_t> rows;
    for (std::size_t r = 0; r < log().rows(); ++r)
      if (log().time()[r] >= kStandFrom_s && log().time()[r] < kSquat_s) rows.push_back(r);
    return rows;
  }
  static double mean(const std::vector<double>& v, const std::vector<std::size_t>& rows) {
    double s = 0;
    for (std::size_t r : rows) s += v[r];
    return s / static_cast<double>(rows.size());
  }
  static dmbd::model::RobotDescription urdf() { return dmbd::model::load_urdf(dmbd::test::robot_dir("leg_rig") + "/leg_rig.urdf"); }
  static dmbd::model::ActuatorParams actuator(const std::string& joint) {
    for (const auto& a : dmbd::model::load_actuators(dmbd::test::robot_dir("leg_rig") + "/actuators.yaml"))
      if (a.joint == joint) return a;
    ADD_FAILURE() << "no actuator for " << joint;
    return {};
  }

  static std::unique_ptr<dmbd::sim::test::TempDir> dir_;
  static std::unique_ptr<ScenarioRun> run_;
  static std::unique_ptr<dmbd::report::ReportResult> report_;
};
std::unique_ptr<dmbd::sim::test::TempDir> LegRig::dir_;
std::unique_ptr<ScenarioRun> LegRig::run_;
std::unique_ptr<dmbd::report::ReportResult> LegRig::report_;

// Index of a link or joint by name.
template <class T>
int index_of(const std::vector<T>& v, const std::string& name) {
  const auto it = std::find_if(v.begin(), v.end(), [&](const T& x) { return x.name == name; });
  return it == v.end() ? -1 : static_cast<int>(it - v.begin());
}

// The y component of r x f: a pitch moment (N m) about an axis along y through r's origin.
double moment_y(const Eigen::Vector3d& r, const Eigen::Vector3d& f) { return r.z() * f.x() - r.x() * f.z(); }

TEST_F(LegRig, RunsBothJointControllersAsGeneratedCode) {
  const auto& r = run_->runs.front();
  ASSERT_TRUE(r.sil.has_value());
  ASSERT_EQ(r.sil->controllers.size(), 2u);
  EXPECT_EQ(r.sil->controllers[0].controller, "hip");
  EXPECT_EQ(r.sil->controllers[1].controller, "knee");
  EXPECT_EQ(r.controller_steps, (std::vector<long long>{3501, 3501}));  // 3.5 s at 1 kHz, t = 0 included
  EXPECT_TRUE(r.effort_clamp_events.empty());
  EXPECT_TRUE(r.velocity_limit_exceeded.empty());
  std::printf("leg rig: %.1f s simulated at a real-time factor of %.1f\n", r.log.time().back(), r.real_time_factor);
}

// The actuator signals of both rotary kinds, with their units.
TEST_F(LegRig, LogsTheActuatorAndContactSignals) {
  const struct {
    const char* name;
    const char* unit;
  } want[] = {{"hip.current", "A"},          {"hip.current_applied", "A"}, {"hip.force", "N m"},
              {"hip.T_winding", "degC"},     {"knee.current", "A"},        {"knee.force", "N m"},
              {"knee.spring_deflection", "rad"}, {"knee.T_winding", "degC"}, {"contact.3.fz", "N"}};
  for (const auto& w : want) {
    const int c = log().find(w.name);
    ASSERT_GE(c, 0) << w.name;
    EXPECT_EQ(log().unit(c), w.unit) << w.name;
  }
  // A rigid geared motor has no spring: no spring signal, and no potentiometer on either.
  EXPECT_LT(log().find("hip.spring_deflection"), 0);
  EXPECT_LT(log().find("hip.q_pot"), 0);
  EXPECT_LT(log().find("knee.q_pot"), 0);
  // The windings warm (above the 25 degC ambient) but stay far below their 125 degC.
  for (const char* t : {"hip.T_winding", "knee.T_winding"}) {
    EXPECT_GT(col(t).back(), 25.0) << t;
    EXPECT_LT(col(t).back(), 35.0) << t;
  }
}

// Free fall from 2 cm: the sole touches after sqrt(2 h / g) = 63.9 ms, within 0.5 ms (the
// rail's 5 N s/m damper on 8.76 kg delays it by (c/m) t^2/6 = 0.39 ms; the fixed step's
// symplectic Euler, h v / 2 ahead in position, advances it by h/2 = 0.25 ms). The first
// log row with contact (rows 2 ms apart) is the first at or after it.
TEST_F(LegRig, TheSoleTouchesDownAfterTheFreeFallTime) {
  const auto& fz = col("contact.3.fz");
  std::size_t first = 0;
  while (first < fz.size() && fz[first] == 0.0) ++first;
  ASSERT_LT(first, fz.size()) << "the foot never touches";
  const double t_fall = std::sqrt(2 * kDrop_m / 9.81), t = log().time()[first];
  std::printf("touch-down: first contact row at %.4f s, free fall %.4f s\n", t, t_fall);
  EXPECT_GE(t, t_fall - 0.5e-3);
  EXPECT_LE(t, t_fall + 0.5e-3 + 2e-3);
}

// Standing, the foot's sole carries the weight of everything on the rail (the rail is
// passive: only gravity and the ground act along it), and nothing else touches.
TEST_F(LegRig, TheFootCarriesTheMovingMassOnTheRail) {
  const dmbd::model::RobotDescription robot = urdf();
  ASSERT_EQ(robot.links.front().name, "stand");
  double moving = 0;
  for (std::size_t l = 1; l < robot.links.size(); ++l) moving += robot.links[l].mass_kg;  // every link but the stand
  const double weight = moving * 9.81;
  const auto rows = standing_rows();
  ASSERT_GT(rows.size(), 400u);
  const auto& fz = col("contact.3.fz");
  const double f = mean(fz, rows);
  double worst = 0;
  for (std::size_t r : rows) worst = std::max(worst, std::abs(fz[r] - weight));
  std::printf("standing: foot carries %.4f N (mean), the weight on the rail %.4f N (%.3f kg); worst sample off by %.2e N\n", f, weight,
              moving, worst);
  EXPECT_NEAR(moving, 8.76, 1e-9);
  EXPECT_NEAR(f, weight, 1e-3 * weight);
  EXPECT_LT(worst, 1e-2 * weight);
  for (int k = 0; k < 3; ++k)
    for (std::size_t r : rows) ASSERT_EQ(col("contact." + std::to_string(k) + ".fz")[r], 0.0) << "shape " << k << " touches";
}

// The carriage holds its height: steady within 1 cm over the last second of standing,
// below the crouch's 0.5865 m by the PDs' sag.
TEST_F(LegRig, TheRailHeightIsSteadyWhileStanding) {
  const auto& z = col("rail.q");
  const auto rows = standing_rows();
  double lo = z[rows.front()], hi = lo;
  for (std::size_t r : rows) lo = std::min(lo, z[r]), hi = std::max(hi, z[r]);
  std::printf("standing: rail height %.4f .. %.4f m (range %.2e m)\n", lo, hi, hi - lo);
  EXPECT_LT(hi - lo, 0.01);
  EXPECT_LT(hi, 0.06 + 0.6 * std::cos(0.5));
  EXPECT_GT(lo, 0.06 + 0.6 * std::cos(0.5) - 0.05);
  // The squat lowers it: by 0.6 (cos 0.5 - cos 0.8) = 10.9 cm between the references.
  EXPECT_LT(z.back(), lo - 0.08);
}

// The knee's J.force is the spring's torque K_s s, exactly, on every row; standing it
// twists by many encoder counts.
TEST_F(LegRig, TheKneeSpringTorqueIsItsStiffnessTimesItsTwist) {
  const double K_s = actuator("knee").K_s_N_per_m;  // N m/rad for a rotary_sea
  ASSERT_EQ(K_s, 1000.0);
  const auto &F = col("knee.force"), &s = col("knee.spring_deflection");
  for (std::size_t r = 0; r < F.size(); ++r) ASSERT_EQ(F[r], K_s * s[r]) << "row " << r;
  const double twist = mean(s, standing_rows()), count = 1 / 20860.756700940907;
  std::printf("standing: knee spring twist %.5f rad (%.0f counts)\n", twist, twist / count);
  EXPECT_LT(twist, -100 * count);  // the weight flexes the knee: the spring holds it back
}

// The joint torques standing, from the rig's statics (the ankle is a free pin, so the
// foot passes the contact force and its own weight to the shank at the ankle):
//   knee: tau_k = -[(c_s - k) x m_s g]_y - [(a - k) x (F + m_f g)]_y
//   hip:  tau_h = -[(c_t - h) x m_t g]_y - [(c_s - h) x m_s g]_y - [(a - h) x (F + m_f g)]_y
// with F the sole's contact force and the positions from the logged joint angles. The
// knee's spring measures the link's torque (2 encoder counts: 0.1 N m); the hip's J.force
// is the drive's torque eta N k_tau i, off by the gear's Coulomb friction (0.4 N m) at
// most while the joint holds.
TEST_F(LegRig, TheMeasuredTorquesAreTheStaticsOfTheContactForce) {
  const dmbd::model::RobotDescription robot = urdf();
  const auto rows = standing_rows();
  std::vector<double> q;
  for (const auto& j : robot.joints) q.push_back(mean(col(j.name + ".q"), rows));
  const auto X = dmbd::model::link_frames(robot, q);
  const int thigh = index_of(robot.links, "thigh"), shank = index_of(robot.links, "shank"), foot = index_of(robot.links, "foot");
  ASSERT_TRUE(thigh > 0 && shank > 0 && foot > 0);
  const Eigen::Vector3d g(0, 0, -9.81);
  const Eigen::Vector3d F(mean(col("contact.3.fx"), rows), mean(col("contact.3.fy"), rows), mean(col("contact.3.fz"), rows));
  const auto com = [&](int l) -> Eigen::Vector3d { return X[static_cast<std::size_t>(l)] * robot.links[static_cast<std::size_t>(l)].com_m; };
  const auto m = [&](int l) { return robot.links[static_cast<std::size_t>(l)].mass_kg; };
  const Eigen::Vector3d h = X[static_cast<std::size_t>(thigh)].translation(), k = X[static_cast<std::size_t>(shank)].translation(),
                        a = X[static_cast<std::size_t>(foot)].translation();
  const Eigen::Vector3d at_ankle = F + m(foot) * g;
  const double tau_k = -moment_y(com(shank) - k, m(shank) * g) - moment_y(a - k, at_ankle);
  const double tau_h = -moment_y(com(thigh) - h, m(thigh) * g) - moment_y(com(shank) - h, m(shank) * g) - moment_y(a - h, at_ankle);
  const double knee = mean(col("knee.force"), rows), hip = mean(col("hip.force"), rows);
  std::printf("standing: knee %.4f N m (spring) vs %.4f N m (statics); hip %.4f N m (estimate) vs %.4f N m (statics); "
              "contact force (%.2f, %.2f) N\n", knee, tau_k, hip, tau_h, F.x(), F.z());
  EXPECT_NEAR(knee, tau_k, 0.1);
  EXPECT_NEAR(hip, tau_h, 0.4 + 0.05);
  // The hip's estimate is the drive's torque: eta N k_tau times the applied current (the
  // means of the two differ by 1e-4 N m: J.force is sampled at the controller's tick,
  // before that tick's command, the current at the log's).
  const auto hp = actuator("hip");
  EXPECT_NEAR(hip, hp.efficiency * hp.N_m_rad_per_m * hp.k_tau_Nm_per_A * mean(col("hip.current_applied"), rows), 1e-3);
  // Both hold well inside the friction cone (mu = 0.8): the sole does not slide.
  EXPECT_LT(std::abs(F.x()), 0.5 * 0.8 * F.z());
}

// The gains follow the scenario's rule: I_j is the joint's rotor J_m N^2 plus the links it
// moves about its axis in the crouch (hip -0.5, knee 1.0 rad), the foot a point mass at the
// free ankle; written to 4 digits.
TEST_F(LegRig, TheGainsFollowTheirRule) {
  const dmbd::model::RobotDescription robot = urdf();
  std::vector<double> q(robot.joints.size(), 0.0);
  q[static_cast<std::size_t>(index_of(robot.joints, "hip"))] = -0.5;
  q[static_cast<std::size_t>(index_of(robot.joints, "knee"))] = 1.0;
  q[static_cast<std::size_t>(index_of(robot.joints, "ankle"))] = -0.5;
  const auto X = dmbd::model::link_frames(robot, q);
  // Inertia about the y axis through p of link l (its own about its centre plus m d^2 in x-z).
  const auto about = [&](int l, const Eigen::Vector3d& p) {
    const auto& L = robot.links[static_cast<std::size_t>(l)];
    const Eigen::Matrix3d R = X[static_cast<std::size_t>(l)].linear();
    const Eigen::Vector3d d = X[static_cast<std::size_t>(l)] * L.com_m - p;
    return (R * L.inertia_kgm2 * R.transpose())(1, 1) + L.mass_kg * (d.x() * d.x() + d.z() * d.z());
  };
  const int thigh = index_of(robot.links, "thigh"), shank = index_of(robot.links, "shank"), foot = index_of(robot.links, "foot");
  const Eigen::Vector3d h = X[static_cast<std::size_t>(thigh)].translation(), k = X[static_cast<std::size_t>(shank)].translation(),
                        a = X[static_cast<std::size_t>(foot)].translation();
  const auto point = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d d = a - p;
    return robot.links[static_cast<std::size_t>(foot)].mass_kg * (d.x() * d.x() + d.z() * d.z());
  };
  const auto rotor = [&](const char* j) {
    const auto act = actuator(j);
    return act.J_m_kgm2 * act.N_m_rad_per_m * act.N_m_rad_per_m;
  };
  const double I_hip = rotor("hip") + about(thigh, h) + about(shank, h) + point(h);
  const double I_knee = rotor("knee") + about(shank, k) + point(k);
  const dmbd::scenario::Scenario s = dmbd::scenario::load_scenario(kScenario);
  for (const auto& c : s.variants.front().controllers) {
    const auto p = std::find_if(c.parameters.begin(), c.parameters.end(), [](const auto& x) { return x.first == "I_j"; });
    ASSERT_NE(p, c.parameters.end()) << c.name;
    const double want = c.name == "hip" ? I_hip : I_knee;
    std::printf("%s: I_j %.4f kg m^2 in the scenario, %.6f by the rule\n", c.name.c_str(), p->second, want);
    EXPECT_NEAR(p->second, want, 5e-5) << c.name;
  }
}

// The report: the robot's display name on the page, frames drawn from the log.
TEST_F(LegRig, TheReportNamesTheRobotAndDrawsFrames) {
  const std::string page = dmbd::sim::test::read_text(report_->page);
  EXPECT_NE(page.find("Leg rig"), std::string::npos);
  EXPECT_GT(report_->frames, 50);
  const fs::path png = fs::path(dir_->file("out")) / "frames" / "frame_00000.png";
  ASSERT_TRUE(fs::exists(png));
  EXPECT_GT(fs::file_size(png), 1000u);
  EXPECT_EQ(dmbd::sim::test::read_text(png.string()).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_TRUE(fs::exists(fs::path(dir_->file("out")) / "plots" / "foot_force.png"));
  EXPECT_TRUE(report_->warnings.empty());
}

}  // namespace
