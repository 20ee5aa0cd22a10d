// Repairs of published robot files (docs/model.md, Repairs): the balanceinertia rule on
// a hand-made inertia, a small URDF with a bad inertia and a massless moving link
// (warnings and repairs; strict refuses naming the link), DRACO untouched, and
// Simbody's Atlas example as Debian ships it.
#include "robot_files.hpp"
#include "dmbd/model/error.hpp"
#include "dmbd/model/inertia_repair.hpp"
#include "dmbd/model/robot_description.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <Eigen/Geometry>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace dmbd::model {
namespace {

namespace fs = std::filesystem;

TEST(BalanceInertia, HandMadeInertiaGetsTheMeanOfItsPrincipalMomentsOnTheSameAxes) {
  // Principal moments 1, 2, 4 (1 + 2 < 4: C exceeds A + B by a third) on rotated axes.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Matrix3d I = R * Eigen::Vector3d(1, 2, 4).asDiagonal() * R.transpose();
  EXPECT_NEAR(triangle_excess(principal_moments(I)), 1.0 / 3.0, 1e-12);
  EXPECT_DOUBLE_EQ(triangle_excess(Eigen::Vector3d(1, 2, 4)), 1.0 / 3.0);
  const Eigen::Matrix3d B = balance_inertia(I);
  // Exactly (trace / 3) times the identity: the mean of the principal moments, 7/3.
  EXPECT_EQ(B, (I.trace() / 3.0) * Eigen::Matrix3d::Identity());
  EXPECT_NEAR(B(0, 0), 7.0 / 3.0, 1e-12);
  // The original principal axes are principal axes of the result (R^T B R is diagonal).
  const Eigen::Matrix3d D = R.transpose() * B * R;
  EXPECT_LT((D - Eigen::Matrix3d(D.diagonal().asDiagonal())).norm(), 1e-12);
  // Physically valid: positive definite, the triangle inequality holds.
  const Eigen::Vector3d m = principal_moments(B);
  EXPECT_GT(m[0], 0.0);
  EXPECT_LE(triangle_excess(m), -0.5 + 1e-12);
  EXPECT_NEAR(m.sum(), 7.0, 1e-12);  // the trace is kept
}

TEST(BalanceInertia, ValidInertiaHasNoExcess) {
  EXPECT_DOUBLE_EQ(triangle_excess(Eigen::Vector3d(1, 1, 2)), 0.0);  // flat plate
  EXPECT_LT(triangle_excess(Eigen::Vector3d(1, 2, 2.5)), 0.0);
}

// base (1 kg) -> revolute -> arm (1 kg, moments 1e-3, 2e-3, 4e-3) -> revolute -> sensor (no mass).
const char* const kBad = R"(<robot name="bad">
  <link name="base">
    <inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/>
  </joint>
  <link name="arm">
    <inertial><origin xyz="0 0 0.1" rpy="0.3 0 0"/><mass value="1"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.004"/></inertial>
  </link>
  <joint name="tilt" type="continuous">
    <parent link="arm"/><child link="sensor"/><axis xyz="0 1 0"/>
  </joint>
  <link name="sensor"/>
</robot>
)";

TEST(UrdfRepairs, BadInertiaAndMasslessMovingLinkLoadWithWarningsAndRepairs) {
  const RobotDescription r = parse_urdf(kBad, ".", "bad.urdf");
  ASSERT_EQ(r.repairs.size(), 2u);
  const Repair& in = r.repairs[0];
  EXPECT_EQ(in.link, "arm");
  EXPECT_EQ(in.kind, "balanceinertia");
  ASSERT_EQ(in.before.size(), 3u);
  ASSERT_EQ(in.after.size(), 3u);
  EXPECT_NEAR(in.before[0], 0.001, 1e-15);
  EXPECT_NEAR(in.before[1], 0.002, 1e-15);
  EXPECT_NEAR(in.before[2], 0.004, 1e-15);
  for (double a : in.after) EXPECT_NEAR(a, 0.007 / 3, 1e-15);
  const Link& arm = r.links[static_cast<std::size_t>(r.link_index("arm"))];
  EXPECT_LT((arm.inertia_kgm2 - (0.007 / 3) * Eigen::Matrix3d::Identity()).norm(), 1e-15);
  EXPECT_EQ(arm.mass_kg, 1.0);
  const Repair& ml = r.repairs[1];
  EXPECT_EQ(ml.link, "sensor");
  EXPECT_EQ(ml.kind, "massless_moving_link");
  EXPECT_EQ(ml.before, std::vector<double>{0.0});
  EXPECT_EQ(ml.after, std::vector<double>{0.0});
  EXPECT_EQ(r.total_mass_kg(), 2.0);  // a repair changes no mass
  // One warning line each, naming the file, the line, the link and what was wrong.
  ASSERT_EQ(r.warnings.size(), 2u);
  EXPECT_EQ(r.warnings[0].rfind("bad.urdf:11: link 'arm': inertia violates the triangle inequality", 0), 0u)
      << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("by 33.3 %"), std::string::npos) << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("repaired by balanceinertia"), std::string::npos) << r.warnings[0];
  EXPECT_EQ(r.warnings[1].rfind("bad.urdf:13: link 'sensor': moved by continuous joint 'tilt'", 0), 0u)
      << r.warnings[1];
  for (const auto& w : r.warnings) EXPECT_EQ(w.find('\n'), std::string::npos);
}

std::string strict_error(const std::string& xml) {
  UrdfOptions o;
  o.strict = true;
  try {
    parse_urdf(xml, ".", "bad.urdf", o);
  } catch (const ModelError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(UrdfRepairs, StrictRefusesNamingTheLink) {
  const std::string e = strict_error(kBad);
  EXPECT_EQ(e.rfind("bad.urdf:11: link 'arm': inertia violates the triangle inequality", 0), 0u) << e;
  EXPECT_NE(e.find("strict"), std::string::npos) << e;
  // With the inertia fixed, the massless moving link is the one refused.
  std::string good = kBad;
  good.replace(good.find("izz=\"0.004\""), 11, "izz=\"0.003\"");
  const std::string m = strict_error(good);
  EXPECT_EQ(m.rfind("bad.urdf:13: link 'sensor': moved by continuous joint 'tilt'", 0), 0u) << m;
  EXPECT_TRUE(parse_urdf(good, ".", "good.urdf").repairs.size() == 1u);
}

TEST(UrdfRepairs, DracoNeedsNoRepair) {
  UrdfOptions o;
  o.strict = true;
  const RobotDescription r = load_urdf(dmbd::test::draco_dir() + "/draco.urdf", o);
  EXPECT_TRUE(r.repairs.empty());
}

TEST(UrdfRepairs, AJointFromAnUndeclaredWorldIsDroppedWithAWarning) {
  const std::string xml = R"(<robot name="w">
  <link name="pelvis"><inertial><mass value="2"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
  <joint name="attach" type="floating"><origin xyz="0 0 0.7"/><parent link="world"/><child link="pelvis"/></joint>
</robot>
)";
  const RobotDescription r = parse_urdf(xml, ".", "w.urdf");
  ASSERT_EQ(r.links.size(), 1u);
  EXPECT_EQ(r.links[0].name, "pelvis");
  EXPECT_TRUE(r.joints.empty());
  EXPECT_TRUE(r.repairs.empty());
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0].rfind("w.urdf:3: joint 'attach': attaches link 'pelvis' to the undeclared link 'world'", 0),
            0u)
      << r.warnings[0];
  std::string revolute = xml;
  revolute.replace(revolute.find("floating"), 8, "continuous");
  const std::string e = strict_error(revolute);
  EXPECT_EQ(e.rfind("bad.urdf:3: joint 'attach': a continuous joint from the undeclared link 'world'", 0), 0u) << e;
}

// Simbody's Atlas example as Debian's simbody docs ship it (gzip-compressed).
const char* const kAtlasGz =
    "/usr/share/doc/simbody/examples/src/TaskSpaceControl-Atlas/models/atlas_v4_free_pelvis.urdf.gz";

TEST(UrdfRepairs, SimbodysAtlasLoadsWithItsHeadInertiaBalanced) {
  if (!fs::exists(kAtlasGz)) GTEST_SKIP() << kAtlasGz << " is absent (Debian package simbody-doc / libsimbody-dev docs)";
  const fs::path dir = fs::temp_directory_path() / ("dmbd_atlas_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path urdf = dir / "atlas_v4_free_pelvis.urdf";
  ASSERT_EQ(std::system(("gzip -dc '" + std::string(kAtlasGz) + "' > '" + urdf.string() + "'").c_str()), 0);
  UrdfOptions o;
  o.load_meshes = false;
  const RobotDescription r = load_urdf(urdf.string(), o);
  const ModelSummary s = summarize(r);
  EXPECT_EQ(s.dof, 29u);
  EXPECT_NEAR(s.total_mass_kg, 159.854574, 1e-6);
  EXPECT_EQ(r.links.front().name, "pelvis");  // the floating joint from 'world' is not kept
  ASSERT_EQ(r.repairs.size(), 1u);
  EXPECT_EQ(r.repairs[0].link, "head");
  EXPECT_EQ(r.repairs[0].kind, "balanceinertia");
  const auto& b = r.repairs[0].before;
  EXPECT_NEAR(b[2] / (b[0] + b[1]) - 1, 0.135, 0.001);  // the issue's 13 %
  o.strict = true;
  try {
    load_urdf(urdf.string(), o);
    ADD_FAILURE() << "strict loaded the Atlas";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("link 'head': inertia violates the triangle inequality"), std::string::npos)
        << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace dmbd::model
