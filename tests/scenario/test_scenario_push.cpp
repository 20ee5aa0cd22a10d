// A variant's `push` (docs/scenario-format.md, "push"): its keys merged over the base and
// the matrix axes into one force (one axis the direction, one the force, one the moment),
// a zero force no push (its trigger still watched), the shipped push map, and the keys still missing after every axis named at the
// push's line.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "dmbd/base/error.hpp"
#include "dmbd/scenario/run_directory.hpp"
#include "dmbd/scenario/scenario.hpp"
#include "sim_test_support.hpp"

namespace {

namespace sc = dmbd::scenario;
using dmbd::sim::test::TempDir;
using dmbd::sim::test::write_text;

std::string scenario(const std::string& push, const std::string& matrix) {
  return "name: pushes\n"
         "robot: {name: draco, base: fixed, base_pose: {xyz: [0, 0, 1.3]}, moving: [l_knee]}\n"
         "duration_s: 0.01\n" + push + "matrix:\n" + matrix;
}

const std::string kAxes = "  direction:\n"
                          "    - {name: fwd, push: {direction_deg: 0}}\n"
                          "    - {name: left, push: {direction_deg: 90}}\n"
                          "  force:\n"
                          "    - {name: none, push: {force_N: 0}}\n"
                          "    - {name: 60N, push: {force_N: 60}}\n"
                          "  phase:\n"
                          "    - {name: early, push: {trigger: {signal: l_knee.q, occurrence: 3, after_s: 0.05}}}\n"
                          "    - {name: at1s, push: {start_s: 1.0}}\n";

}  // namespace

TEST(Push, TheAxesMergeIntoOneForce) {
  TempDir dir;
  write_text(dir.file("p.yaml"), scenario("push: {link: torso, point: [0, 0, 0.1], duration_s: 0.2}\n", kAxes));
  const sc::Scenario s = sc::load_scenario(dir.file("p.yaml"));
  ASSERT_EQ(s.variants.size(), 8u);
  for (const auto& v : s.variants) {
    SCOPED_TRACE(v.name);
    const bool none = v.name.find("/none/") != std::string::npos;
    ASSERT_EQ(v.forces.size(), 1u);
    const auto& f = v.forces[0];
    if (none) {  // the reference: no force, its trigger still watched
      EXPECT_EQ(f.direction_W, Eigen::Vector3d::Zero());
      EXPECT_EQ(f.trigger.has_value(), v.name.find("/early") != std::string::npos);
      continue;
    }
    EXPECT_EQ(f.link, "torso");
    EXPECT_EQ(f.point_L, Eigen::Vector3d(0, 0, 0.1));
    const bool left = v.name.rfind("left/", 0) == 0;
    EXPECT_NEAR(f.direction_W.x(), left ? 0.0 : 1.0, 1e-15);
    EXPECT_NEAR(f.direction_W.y(), left ? 1.0 : 0.0, 1e-15);
    EXPECT_EQ(f.direction_W.z(), 0.0);
    const bool early = v.name.find("/early") != std::string::npos;
    ASSERT_EQ(f.trigger.has_value(), early);
    if (early) {
      EXPECT_EQ(f.trigger->signal, "l_knee.q");
      EXPECT_EQ(f.trigger->occurrence, 3);
      EXPECT_EQ(f.trigger->after_s, 0.05);
    }
    const double t0 = early ? 0.0 : 1.0;  // a trigger's source runs from its start
    EXPECT_EQ(f.source.value(t0 - 1e-9), 0.0);
    EXPECT_EQ(f.source.value(t0), 60.0);
    EXPECT_EQ(f.source.value(t0 + 0.2 - 1e-9), 60.0);
    EXPECT_EQ(f.source.value(t0 + 0.2), 0.0);
  }
}

TEST(Push, KeysStillMissingAfterEveryAxisAreNamedAtThePush) {
  TempDir dir;
  const std::string path = dir.file("p.yaml");
  write_text(path, scenario("push: {link: torso}\n", kAxes));  // no duration anywhere
  try {
    sc::load_scenario(path);
    FAIL() << "no error";
  } catch (const dmbd::InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("variant 'fwd/60N/early': push: missing duration_s (after the base, the variant and the matrix axes)"), std::string::npos)
        << msg;
    EXPECT_NE(msg.find(path + ":"), std::string::npos) << msg;
  }
  write_text(path, scenario("push: {link: torso, duration_s: 0.2, force: 3}\n", kAxes));
  try {
    sc::load_scenario(path);
    FAIL() << "no error";
  } catch (const dmbd::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":4:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("unknown key 'force'"), std::string::npos) << e.what();
  }
}

// The shipped push map (examples/scenarios/push_map.yaml): 2 joint models x 8 directions
// x (the reference and 10 forces) x 4 phases on the sixth touch-down, the ideal-joint
// group with its ankles' armature, one force per run, the
// reference's force zero with its trigger kept; two of its runs, the reference and the
// 60 N forward push 0.1 s after the touch-down, reproduce the full map's figures
// (docs/experiments.md): the boundary 43.70 N there (to 0.01 N; 43.68 N before the heading
// hold) and the push survived.
TEST(Push, TheShippedMapIsDirectionsByForcesByPhasesOnTheSixthStep) {
  sc::Scenario s = sc::load_scenario(std::string(DMBD_SOURCE_DIR) + "/examples/scenarios/push_map.yaml");
  ASSERT_EQ(s.variants.size(), 2u * 8u * 11u * 4u);
  EXPECT_EQ(s.experiment.type, "push_map");
  int references = 0;
  for (const auto& v : s.variants) {
    SCOPED_TRACE(v.name);
    ASSERT_EQ(v.forces.size(), 1u);
    const auto& f = v.forces[0];
    ASSERT_TRUE(f.trigger.has_value());
    EXPECT_EQ(f.trigger->signal, "balance.touch_downs");
    EXPECT_EQ(f.trigger->occurrence, 6);
    references += f.direction_W.norm() == 0;
    EXPECT_GE(v.duration_s, 7.5 + 3.0);  // the latest push ends near 7.4 s; survival asks 3 s more
  }
  EXPECT_EQ(references, 2 * 8 * 4);
  for (const auto& v : s.variants)
    if (v.name.rfind("ideal/", 0) == 0) {
      EXPECT_EQ(v.robot.armature, (std::vector<std::pair<std::string, double>>{{"l_ankle", 0.55}, {"r_ankle", 0.55}})) << v.name;
    }
  std::vector<sc::VariantSetup> kept;
  for (const auto& v : s.variants)
    if (v.name == "actuated/d0/F0/p0.1" || v.name == "actuated/d0/F60/p0.1") kept.push_back(v);
  ASSERT_EQ(kept.size(), 2u);
  s.variants = kept;
  TempDir dir;
  const sc::ScenarioRun r = sc::run_scenario(s, dir.file("out"));
  const auto& m = r.metrics["push_map"]["actuated"];
  ASSERT_EQ(m["pushes"].size(), 1u);
  EXPECT_TRUE(m["pushes"][0]["survived"].get<bool>());
  EXPECT_NEAR(m["directions"]["0"]["by_phase"][0]["boundary_N"].get<double>(), 43.70, 0.01);
}
