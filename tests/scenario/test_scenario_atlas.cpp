// Simbody's Atlas example standing on its feet's boxes (the scenario:
// tests/support/atlas_scenario.hpp). The feet's boxes carry the weight, nothing else
// touches, the frames draw the robot from its collision shapes.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include <fmt/format.h>

#include "dmbd/model/plant.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/report/report.hpp"
#include "dmbd/scenario/scenario.hpp"
#include "atlas_scenario.hpp"
#include "sim_test_support.hpp"

namespace dmbd::scenario {
namespace {

namespace fs = std::filesystem;
using dmbd::sim::test::TempDir;
using dmbd::sim::test::write_text;

using test::atlas::initial;
using test::atlas::kAtlasGz;
using test::atlas::moving;
using test::atlas::scenario_text;

class Atlas : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(kAtlasGz)) GTEST_SKIP() << kAtlasGz << " is absent (Debian package simbody-doc / libsimbody-dev docs)";
    urdf_ = dir_.file("atlas_v4_free_pelvis.urdf");
    ASSERT_TRUE(test::atlas::decompress_atlas(urdf_)) << urdf_;
    model::UrdfOptions o;
    o.load_meshes = false;
    robot_ = model::load_urdf(urdf_, o);
  }
  Scenario scenario(double duration_s, const std::string& frames = "") const {
    const std::string path = dir_.file("atlas.yaml");
    write_text(path, scenario_text(robot_, urdf_, duration_s, frames));
    return load_scenario(path);
  }
  TempDir dir_;
  std::string urdf_;
  model::RobotDescription robot_;
};

// The mean of a logged signal over t >= t0.
double mean_from(const sim::Log& log, const std::string& signal, double t0) {
  double sum = 0;
  int n = 0;
  for (std::size_t k = 0; k < log.rows(); ++k)
    if (log.time()[k] >= t0 - 1e-9) sum += log.column(signal)[k], ++n;
  return sum / n;
}

// 1.5 s. Over its last 0.5 s: the pelvis height varies by less than 1 mm (measured
// 0.005 mm; it settles from 0.9397 m to 0.9374 m in the first 0.2 s); the two feet's
// boxes (contact.K numbered as model::Plant::contacts()) carry the weight, m g =
// 1568.2 N, within 0.5 % on average (measured 1568.2 N: the support is horizontal, so it
// carries none), half on each foot within 2 % of the weight (783.9 and 784.3 N); no other
// shape touches the ground at any logged instant (force exactly 0); every joint ends
// within 0.05 rad of its held angle (the largest: neck_ry, 0.030 rad under its head's
// weight; the knees 0.022 rad).
TEST_F(Atlas, StandsWithThePelvisHeldAndTheFeetCarryTheWeight) {
  const double T = 1.5, window = 0.5;
  const Scenario s = scenario(T);
  const VariantPlant vp = variant_plant(s, s.variants[0]);
  const model::Plant plant(vp.robot, vp.options);
  const sim::VariantResult r = run_variant(s, s.variants[0], {});
  const sim::Log& log = r.log;
  ASSERT_NEAR(log.time().back(), T, 1e-9);
  const auto& z = log.column("base.z");
  double z_min = 1e9, z_max = -1e9;
  for (std::size_t k = 0; k < log.rows(); ++k)
    if (log.time()[k] >= T - window - 1e-9) z_min = std::min(z_min, z[k]), z_max = std::max(z_max, z[k]);

  double feet[2] = {0, 0}, elsewhere = 0;
  int foot_shapes = 0;
  const auto contacts = plant.contacts();
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const std::string& link = vp.robot.links[static_cast<std::size_t>(contacts[k].link)].name;
    const std::string K = fmt::format("contact.{}.", k);
    if (link == "l_foot" || link == "r_foot") {
      EXPECT_EQ(contacts[k].kind, model::Geometry::Kind::Box) << link;
      feet[link == "r_foot"] += mean_from(log, K + "fz", T - window);
      ++foot_shapes;
      continue;
    }
    for (const char* axis : {"fx", "fy", "fz"})
      for (double f : log.column(K + axis)) elsewhere = std::max(elsewhere, std::abs(f));
  }
  const double weight = plant.total_mass_kg() * 9.81;
  std::printf("Atlas: pelvis at %.4f m (%.4f m at t = 0), varying %.4f mm over the last %.1f s; feet %.1f + %.1f N "
              "of %.1f N; largest force elsewhere %.3g N\n",
              z.back(), z.front(), 1e3 * (z_max - z_min), window, feet[0], feet[1], weight, elsewhere);
  EXPECT_EQ(foot_shapes, 2);
  EXPECT_LT(z_max - z_min, 1e-3);
  EXPECT_NEAR(feet[0] + feet[1], weight, 0.005 * weight);
  for (double f : feet) EXPECT_NEAR(f, 0.5 * weight, 0.02 * weight);
  EXPECT_EQ(elsewhere, 0.0);
  for (const auto& j : vp.robot.joints)
    if (moving(j)) {
      EXPECT_NEAR(log.column(j.name + ".q").back(), initial(j.name), 0.05) << j.name;
    }
}

// The frames of a 0.2 s run (at t = 0, 0.1, 0.2 s; 320 x 240, the default camera framing
// the robot) show Atlas, every one of its meshes missing, drawn from its collision shapes:
// at least 3 % of each frame in the stand-in colour (report::RobotSceneOptions's teal,
// hue 169 deg; measured 5.7 %); the report's warnings say so in one line naming the
// links.
TEST_F(Atlas, FramesDrawItFromItsCollisionShapes) {
  const Scenario s = scenario(0.2, "frames: {fps: 10, width: 320, height: 240}\n");
  const std::string out = dir_.file("out");
  const ScenarioRun run = run_scenario(s, out);
  const report::ReportResult rep = report::write_report(run, out);
  ASSERT_EQ(rep.frames, 3);
  const auto teal = [](const cv::Mat& bgr) {
    cv::Mat hsv, m;
    cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);  // H in [0, 180)
    cv::inRange(hsv, cv::Scalar(77, 70, 40), cv::Scalar(92, 255, 255), m);
    return cv::countNonZero(m);
  };
  for (int k = 0; k < 3; ++k) {
    const cv::Mat frame = cv::imread(fmt::format("{}/frames/frame_{:05d}.png", out, k), cv::IMREAD_COLOR);
    ASSERT_EQ(frame.size(), cv::Size(320, 240)) << k;
    const double share = static_cast<double>(teal(frame)) / static_cast<double>(frame.total());
    std::printf("frame %d: %.1f %% of its pixels in the stand-in colour\n", k, 100 * share);
    EXPECT_GT(share, 0.03) << "frame " << k;
  }
  int lines = 0;
  for (const auto& w : rep.warnings)
    if (w.find("links drawn from their collision shapes") != std::string::npos) {
      ++lines;
      EXPECT_NE(w.find("l_foot"), std::string::npos) << w;
      EXPECT_NE(w.find("utorso"), std::string::npos) << w;
      EXPECT_EQ(w.find("ltorso"), std::string::npos) << w;  // it has no collision shape
    }
  EXPECT_EQ(lines, 1);
  // Of its missing meshes the robot is drawn without two, each on a line of its own:
  // ltorso's visual (the link has no collision shape to stand in) and utorso's collision
  // mesh utorso_pack.stl; the 29 stand-in links' visual meshes are in the stand-ins' line.
  std::string meshes;
  for (const auto& w : rep.warnings)
    if (w.find("could not be read") != std::string::npos) meshes += w.substr(w.find("mesh '")) + "\n";
  EXPECT_EQ(meshes,
            "mesh 'package://atlas_description/meshes_v3/ltorso.dae' could not be read: the frames draw the robot without it\n"
            "mesh 'package://atlas_description/meshes_v3/utorso_pack.stl' could not be read: the frames draw the robot without it\n");
}

}  // namespace
}  // namespace dmbd::scenario
