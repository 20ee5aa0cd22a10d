// The report's 3-D replay (report/src/replay.cpp) against the run it replays: every
// sampled link pose is the frames' forward kinematics (model::link_frames) of the logged
// angles and base pose at that row, the centre of mass the description's, the contact
// forces the logged ones where the frames draw them; the frames' times are among the
// samples; robots sharing a scene share its file; a table under a fixed base is one more
// body; at most twelve variants, the frames' variant always among them; and every
// shipped scenario logs what the replay draws (and a log that keeps no angle gives a warning).
#include <gtest/gtest.h>

#include <fnmatch.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "../../report/src/contact_sites.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/report/report.hpp"
#include "dmbd/scenario/run_directory.hpp"
#include "replay_script.hpp"
#include "sim_test_support.hpp"

namespace {

namespace fs = std::filesystem;
namespace rs = dmbd::test::replay;
using dmbd::scenario::load_scenario;
using dmbd::sim::test::read_text;
using dmbd::sim::test::TempDir;
using dmbd::sim::test::write_text;

const std::string kSourceDir = DMBD_SOURCE_DIR;
constexpr double kFloat32 = 2e-6;  // m or rotation-matrix entries: float32 of values below ~4

// DRACO falling free from a tilted pose with its left knee driven (0.3 s, 1 kHz log):
// "falling", "falling_straight" (other knee angles: the same robot, so the same scene)
// and "held" (a fixed base without contact: on a table, one more scene body).
const char* const kFallScenario = R"(name: fall
robot: {name: draco, base: floating, base_pose: {xyz: [0, 0, 1.4], rpy: [0.2, 0.1, 0.4]}, moving: [l_knee, r_knee],
        actuators: [l_knee], initial: {l_knee: 1.0, r_knee: 0.5}}
duration_s: 0.3
references:
  l_knee.current: {type: constant, value: 6.0}
variants:
  - name: falling
  - name: held
    robot: {base: fixed, base_pose: {xyz: [0, 0, 1.3]}}
  - name: falling_straight
    robot: {initial: {l_knee: 0.3, r_knee: 0.2}}
frames: {fps: 10, width: 480, height: 360, camera: {position: [2.2, -2.0, 1.2], look_at: [0, 0, 0.8]}}
)";

rs::Script script(const std::string& path) { return rs::parse(read_text(path)); }

// The row whose time is the sample's (float32).
std::size_t row_at(const dmbd::sim::Log& log, float t) {
  const auto& time = log.time();
  const auto it = std::min_element(time.begin(), time.end(), [&](double a, double b) { return std::abs(a - t) < std::abs(b - t); });
  return static_cast<std::size_t>(it - time.begin());
}

// The links' poses at a row, read from the log by the test: the angles by joint name, the
// base's pose from base.x .. base.yaw with its rotation as a product of quaternions.
std::vector<Eigen::Isometry3d> logged_link_poses(const dmbd::model::RobotDescription& robot, const dmbd::sim::Log& log,
                                                 const dmbd::scenario::VariantSetup& v, std::size_t row) {
  std::vector<double> q(robot.joints.size(), 0.0);
  for (std::size_t j = 0; j < q.size(); ++j)
    if (log.find(robot.joints[j].name + ".q") >= 0) q[j] = log.column(robot.joints[j].name + ".q")[row];
  Eigen::Isometry3d X = v.robot.X_WB;
  if (v.robot.base == dmbd::model::BaseMode::Floating) {
    const auto c = [&](const char* name) { return log.column(std::string("base.") + name)[row]; };
    const Eigen::Quaterniond r = Eigen::Quaterniond(Eigen::AngleAxisd(c("yaw"), Eigen::Vector3d::UnitZ())) *
                                 Eigen::Quaterniond(Eigen::AngleAxisd(c("pitch"), Eigen::Vector3d::UnitY())) *
                                 Eigen::Quaterniond(Eigen::AngleAxisd(c("roll"), Eigen::Vector3d::UnitX()));
    X = Eigen::Isometry3d::Identity();
    X.linear() = r.toRotationMatrix();
    X.translation() << c("x"), c("y"), c("z");
  }
  return dmbd::model::link_frames(robot, q, X);
}

// Every sample of a track against the run: its time a logged row's, every link's pose
// the forward kinematics of that row (the table's, when there is one, constant), the
// centre of mass the description's. Returns the sample times.
std::vector<float> expect_track_is_the_log(const nlohmann::json& track, const dmbd::model::RobotDescription& robot,
                                           const dmbd::sim::VariantResult& r, const dmbd::scenario::VariantSetup& v, bool table) {
  const std::vector<float> times = rs::floats(track.at("times")), P = rs::floats(track.at("poses")), com = rs::floats(track.at("com"));
  const std::size_t n = times.size(), bodies = robot.links.size() + (table ? 1 : 0);
  EXPECT_EQ(track.at("samples"), n);
  EXPECT_EQ(track.at("bodies"), bodies);
  EXPECT_EQ(P.size(), 7 * bodies * n);
  EXPECT_EQ(com.size(), 3 * n);
  double worst = 0;
  for (std::size_t k = 0; k < n && P.size() == 7 * bodies * n; ++k) {
    const std::size_t row = row_at(r.log, times[k]);
    EXPECT_NEAR(r.log.time()[row], times[k], 1e-6) << "sample " << k << ": no logged row at its time";
    const auto X = logged_link_poses(robot, r.log, v, row);
    for (std::size_t b = 0; b < robot.links.size(); ++b) {
      const float* p = &P[7 * (k * bodies + b)];
      const Eigen::Quaterniond qt(p[6], p[3], p[4], p[5]);
      worst = std::max({worst, (Eigen::Vector3d(p[0], p[1], p[2]) - X[b].translation()).norm(),
                        (qt.normalized().toRotationMatrix() - X[b].linear()).cwiseAbs().maxCoeff()});
    }
    if (table && k > 0) {
      for (int i = 0; i < 7; ++i) EXPECT_EQ(P[7 * (k * bodies + bodies - 1) + i], P[7 * (bodies - 1) + i]) << "the table moved";
    }
    const Eigen::Vector3d c = dmbd::model::center_of_mass(robot, X);
    worst = std::max(worst, (Eigen::Vector3d(com[3 * k], com[3 * k + 1], com[3 * k + 2]) - c).norm());
  }
  EXPECT_LT(worst, kFloat32) << r.name << ": largest difference from the log's forward kinematics";
  return times;
}

TEST(ReportReplay, PosesAreTheFramesForwardKinematics) {
  TempDir dir;
  write_text(dir.file("fall.yaml"), kFallScenario);
  const std::string out = dir.file("out");
  const auto run = dmbd::scenario::run_scenario(load_scenario(dir.file("fall.yaml")), out);
  const auto rep = dmbd::report::write_report(run, out);
  EXPECT_EQ(rep.replay_variants, 3);
  // falling and falling_straight share scene_0.js; held (its table) has scene_1.js.
  for (const char* f : {"three.min.js", "OrbitControls.js", "three.js-LICENSE.txt", "scene_0.js", "scene_1.js", "variant_0.js",
                        "variant_1.js", "variant_2.js"})
    EXPECT_TRUE(fs::exists(fs::path(out) / "replay" / f)) << f;
  EXPECT_FALSE(fs::exists(fs::path(out) / "replay/scene_2.js"));
  const std::string html = read_text(out + "/report.html");
  EXPECT_NE(html.find("data-track=\"replay/variant_2.js\" data-scene=\"replay/scene_0.js\""), std::string::npos);
  EXPECT_NE(html.find("data-track=\"replay/variant_1.js\" data-scene=\"replay/scene_1.js\""), std::string::npos);
  for (std::size_t k = 0; k < run.runs.size(); ++k) {
    SCOPED_TRACE(run.runs[k].name);
    const auto& v = run.scenario.variants[k];
    const auto robot = dmbd::scenario::variant_plant(run.scenario, v).robot;
    const bool table = v.robot.base == dmbd::model::BaseMode::Fixed;
    const rs::Script s = script(fmt::format("{}/replay/variant_{}.js", out, k));
    EXPECT_EQ(s.key, fmt::format("replay/variant_{}.js", k));
    EXPECT_EQ(s.value.at("name"), run.runs[k].name);
    const std::vector<float> times = expect_track_is_the_log(s.value, robot, run.runs[k], v, table);
    // 50 Hz from a 1 kHz log: every 20th row, and the last: 0, 0.02, ..., 0.3 s.
    ASSERT_EQ(times.size(), 16u);
    for (std::size_t i = 0; i < times.size(); ++i) EXPECT_NEAR(times[i], 0.02 * static_cast<double>(i), 1e-6);
    // The scene: one body per link (names in order), the table after them.
    const rs::Script sc = script(fmt::format("{}/replay/scene_{}.js", out, table ? 1 : 0));
    ASSERT_EQ(sc.value.at("bodies").size(), robot.links.size() + (table ? 1 : 0));
    for (std::size_t b = 0; b < robot.links.size(); ++b) EXPECT_EQ(sc.value["bodies"][b]["name"], robot.links[b].name);
    if (table) {
      EXPECT_EQ(sc.value["bodies"][robot.links.size()]["name"], "table");
    }
  }
  // Every frame's time is a sample's: the frames at 0, 0.1, 0.2, 0.3 s.
  ASSERT_EQ(rep.frames, 4);
  // The view starts at the frames' camera, on the frames' variant (the first).
  const std::string open = "<script type=\"application/json\" id=\"replay-setup\">";
  const std::size_t a = html.find(open) + open.size();
  const auto setup = nlohmann::json::parse(html.substr(a, html.find("</script>", a) - a));
  EXPECT_EQ(setup["camera"]["position"], nlohmann::json::array({2.2, -2.0, 1.2}));
  EXPECT_EQ(setup["camera"]["look_at"], nlohmann::json::array({0, 0, 0.8}));
  EXPECT_EQ(setup["camera"]["width"], 480);
  EXPECT_EQ(setup["camera"]["height"], 360);
  EXPECT_EQ(setup["camera"]["fov_y_deg"], 40);
  EXPECT_EQ(setup["initial"], 0);
}

// The leg rig dropped onto the ground (its rail, fixed base with contact): every sample's
// contact forces are the logged contact.K.f* at the point the frames draw them at.
TEST(ReportReplay, ContactForcesWhereTheFramesDrawThem) {
  TempDir dir;
  write_text(dir.file("drop.yaml"), "name: drop\n"
                                    "robot: {name: leg_rig, base: fixed, contact: true, initial: {rail: 0.68, hip: -0.5, knee: 1.0, ankle: -0.5}}\n"
                                    "integration: {mode: fixed, step_s: 0.0005}\nduration_s: 0.2\nlog_rate_hz: 500\nframes: false\n");
  const std::string out = dir.file("out");
  const auto run = dmbd::scenario::run_scenario(load_scenario(dir.file("drop.yaml")), out);
  const auto rep = dmbd::report::write_report(run, out);
  EXPECT_EQ(rep.frames, 0);
  EXPECT_EQ(rep.replay_variants, 1) << "written without frames";
  const auto& v = run.scenario.variants[0];
  const auto robot = dmbd::scenario::variant_plant(run.scenario, v).robot;
  const auto& log = run.runs[0].log;
  const rs::Script s = script(out + "/replay/variant_0.js");
  const std::vector<float> times = expect_track_is_the_log(s.value, robot, run.runs[0], v, false);
  const auto sites = dmbd::report::detail::contact_sites(robot);
  ASSERT_GT(sites.size(), 0u);
  ASSERT_EQ(s.value.at("sites"), sites.size());
  const std::vector<float> F = rs::floats(s.value.at("forces"));
  ASSERT_EQ(F.size(), 6 * sites.size() * times.size());
  double largest = 0, worst = 0;
  for (std::size_t k = 0; k < times.size(); ++k) {
    const std::size_t row = row_at(log, times[k]);
    const auto X = logged_link_poses(robot, log, v, row);
    for (std::size_t i = 0; i < sites.size(); ++i) {
      const float* f = &F[6 * (k * sites.size() + i)];
      const Eigen::Vector3d logged(log.column(fmt::format("contact.{}.fx", i))[row], log.column(fmt::format("contact.{}.fy", i))[row],
                                   log.column(fmt::format("contact.{}.fz", i))[row]);
      const Eigen::Vector3d point = dmbd::report::detail::contact_point(sites[i], X[static_cast<std::size_t>(sites[i].link)]);
      largest = std::max(largest, logged.norm());
      worst = std::max({worst, (Eigen::Vector3d(f[3], f[4], f[5]) - logged).norm() / std::max(1.0, logged.norm()),
                        (Eigen::Vector3d(f[0], f[1], f[2]) - point).norm()});
    }
  }
  EXPECT_GT(largest, 10.0) << "the foot never landed: nothing compared";
  EXPECT_LT(worst, 1e-6);
}

// Fourteen variants, the frames' the last: twelve replayed, the frames' among them, the
// caption saying so.
TEST(ReportReplay, AtMostTwelveVariantsTheFramesVariantAmongThem) {
  TempDir dir;
  std::string text = "name: many\nrobot: {name: leg_rig, base: fixed, contact: true, initial: {rail: 0.6, hip: -0.5, knee: 1.0, ankle: -0.5}}\n"
                     "integration: {mode: fixed, step_s: 0.0005}\nduration_s: 0.02\nlog_rate_hz: 500\nvariants:\n";
  for (int k = 1; k <= 14; ++k) text += fmt::format("  - name: v{}\n", k);
  text += "frames: {enabled: false, variant: v14}\n";
  write_text(dir.file("many.yaml"), text);
  const std::string out = dir.file("out");
  const auto run = dmbd::scenario::run_scenario(load_scenario(dir.file("many.yaml")), out);
  const auto rep = dmbd::report::write_report(run, out);
  EXPECT_EQ(rep.replay_variants, 12);
  const std::string html = read_text(out + "/report.html");
  for (int k = 1; k <= 11; ++k) EXPECT_NE(html.find(fmt::format(">v{}</option>", k)), std::string::npos) << k;
  EXPECT_EQ(html.find(">v12</option>"), std::string::npos);
  EXPECT_EQ(html.find(">v13</option>"), std::string::npos);
  EXPECT_NE(html.find("selected>v14</option>"), std::string::npos) << "the frames' variant, shown first";
  EXPECT_NE(html.find("12 of the run&#39;s 14 variants"), std::string::npos);
  EXPECT_EQ(script(out + "/replay/variant_11.js").value.at("name"), "v14");
  EXPECT_FALSE(fs::exists(out + "/replay/variant_12.js"));
  EXPECT_FALSE(fs::exists(out + "/replay/scene_1.js")) << "one robot, one scene file";
}

// A log that keeps no joint angle (log_only) has no replay: one warning for all its
// variants, no replay/ folder, no replay section, the rest of the report as before.
TEST(ReportReplay, NoJointAnglesLoggedNoReplayOneWarning) {
  TempDir dir;
  write_text(dir.file("blind.yaml"),
             "name: blind\nrobot: {name: leg_rig, base: fixed, contact: true, initial: {rail: 0.6, hip: -0.5, knee: 1.0, ankle: -0.5}}\n"
             "integration: {mode: fixed, step_s: 0.0005}\nduration_s: 0.02\nlog_rate_hz: 500\nlog_only: [rail.q]\n"
             "variants:\n  - name: a\n  - name: b\n  - name: c\nframes: false\n");
  const std::string out = dir.file("out");
  const auto run = dmbd::scenario::run_scenario(load_scenario(dir.file("blind.yaml")), out);
  const auto rep = dmbd::report::write_report(run, out);
  EXPECT_EQ(rep.replay_variants, 0);
  ASSERT_EQ(rep.warnings.size(), 1u);
  EXPECT_NE(rep.warnings[0].find("no 3-D replay: "), std::string::npos) << rep.warnings[0];
  EXPECT_NE(rep.warnings[0].find("logged no 'hip.q'"), std::string::npos) << rep.warnings[0];
  EXPECT_NE(rep.warnings[0].find("2 more variants have no replay either"), std::string::npos) << rep.warnings[0];
  EXPECT_FALSE(fs::exists(out + "/replay"));
  const std::string html = read_text(out + "/report.html");
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_NE(html.find("no 3-D replay"), std::string::npos) << "the warning is on the page";
}

// Every shipped scenario keeps in its log what the replay draws for the variants it
// replays: each moving joint's J.q and, on a floating base, base.x .. base.yaw. Checked
// on the scenario files (log_only), without running them.
TEST(ReportReplay, EveryShippedScenarioLogsWhatTheReplayDraws) {
  int checked = 0;
  for (const auto& e : fs::directory_iterator(kSourceDir + "/examples/scenarios")) {
    if (e.path().extension() != ".yaml") continue;
    SCOPED_TRACE(e.path().filename().string());
    const auto s = load_scenario(e.path().string());
    const auto kept = [&](const std::string& signal) {
      return s.log_only.empty() || std::any_of(s.log_only.begin(), s.log_only.end(), [&](const auto& p) {
               return fnmatch(p.pattern.c_str(), signal.c_str(), 0) == 0;
             });
    };
    for (std::size_t k = 0; k < std::min<std::size_t>(s.variants.size(), 12); ++k) {
      const auto& v = s.variants[k];
      const auto robot = dmbd::scenario::variant_plant(s, v).robot;
      for (const auto& j : robot.joints) {
        const bool one_dof = j.type == dmbd::model::JointType::Revolute || j.type == dmbd::model::JointType::Continuous ||
                             j.type == dmbd::model::JointType::Prismatic;
        EXPECT_TRUE(!one_dof || kept(j.name + ".q")) << v.name << ": " << j.name << ".q";
      }
      const bool floating = v.robot.base == dmbd::model::BaseMode::Floating;
      for (const char* b : {"base.x", "base.y", "base.z", "base.roll", "base.pitch", "base.yaw"}) EXPECT_TRUE(!floating || kept(b)) << v.name << ": " << b;
    }
    ++checked;
  }
  EXPECT_GE(checked, 13);
}

}  // namespace
