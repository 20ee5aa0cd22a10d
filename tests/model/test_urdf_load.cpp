// Loading real-world-style URDFs: masses, joint counts and order, inertia rotation,
// joint fields, default-pose kinematics, heights, unknown-tag warnings, summaries.
// Fixtures: tests/model/data/urdf/{ws/arm_description,quadruped,mixed,partial}.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>

#include "test_urdf_support.hpp"

namespace dmbd::model {
namespace {

using test::expect_tree_order;
using test::line_of;
using test::slurp;
using test::sum_of_mass_elements;
using test::urdf_data;

const std::string kArm = "ws/arm_description/urdf/arm.urdf";
const std::string kQuad = "quadruped/quadruped.urdf";

const Link& link_named(const RobotDescription& r, const std::string& name) {
  const int i = r.link_index(name);
  EXPECT_GE(i, 0) << name;
  return r.links.at(static_cast<std::size_t>(std::max(i, 0)));
}
const Joint& joint_named(const RobotDescription& r, const std::string& name) {
  const int i = r.joint_index(name);
  EXPECT_GE(i, 0) << name;
  return r.joints.at(static_cast<std::size_t>(std::max(i, 0)));
}

TEST(UrdfLoad, ArmMassIsTheSumOfTheMassElements) {
  const std::string path = urdf_data(kArm);
  int n = 0;
  const double expected = sum_of_mass_elements(slurp(path), &n);
  EXPECT_EQ(n, 4);
  const RobotDescription r = load_urdf(path);
  // Four parsed doubles summed in another order: a few ulps at most.
  EXPECT_NEAR(r.total_mass_kg(), expected, 1e-12);
  EXPECT_NEAR(summarize(r).total_mass_kg, expected, 1e-12);
  EXPECT_EQ(link_named(r, "base_link").mass_kg, 0.0);   // dummy, no <inertial>
  EXPECT_EQ(link_named(r, "tool_frame").mass_kg, 0.0);  // massless leaf
  EXPECT_EQ(link_named(r, "base").mass_kg, 2.5);
}

TEST(UrdfLoad, ArmTreeOrderAndCounts) {
  const RobotDescription r = load_urdf(urdf_data(kArm));
  EXPECT_EQ(r.name, "small_arm");
  EXPECT_EQ(r.source, urdf_data(kArm));
  expect_tree_order(r);
  const std::vector<std::string> links = {"base_link", "base", "shoulder", "upper_arm", "forearm", "tool_frame"};
  ASSERT_EQ(r.links.size(), links.size());
  for (std::size_t i = 0; i < links.size(); ++i) EXPECT_EQ(r.links[i].name, links[i]);
  // joints[i] is the parent joint of links[i + 1].
  for (std::size_t i = 0; i < r.joints.size(); ++i) EXPECT_EQ(r.joints[i].child, r.links[i + 1].name);
  const ModelSummary s = summarize(r);
  EXPECT_EQ(s.links, 6u);
  EXPECT_EQ(s.fixed, 2u);
  EXPECT_EQ(s.revolute, 2u);
  EXPECT_EQ(s.continuous, 1u);
  EXPECT_EQ(s.prismatic + s.floating + s.planar, 0u);
  EXPECT_EQ(s.dof, 3u);
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
}

TEST(UrdfLoad, InertiaIsRotatedByTheInertialRpy) {
  // shoulder: <origin xyz="0.01 0.02 0.05" rpy="0 0 pi/2">, I = [[.004 .0005 0] [.0005 .006 0] [0 0 .008]].
  // Rz(90 deg) maps x -> y and y -> -x, so R I R^T = [[.006 -.0005 0] [-.0005 .004 0] [0 0 .008]] (by hand).
  const RobotDescription r = load_urdf(urdf_data(kArm));
  const Link& l = link_named(r, "shoulder");
  Eigen::Matrix3d expected;
  expected << 0.006, -0.0005, 0, -0.0005, 0.004, 0, 0, 0, 0.008;
  EXPECT_LT((l.inertia_kgm2 - expected).cwiseAbs().maxCoeff(), 1e-15);  // cos(pi/2) ~ 6e-17 leaks in
  EXPECT_LT((l.com_m - Eigen::Vector3d(0.01, 0.02, 0.05)).norm(), 1e-15);
  EXPECT_EQ(l.mass_kg, 1.2);
}

TEST(UrdfLoad, InertiaRotationMatchesTheUrdfRpyConvention) {
  // URDF rpy: fixed-axis roll (x), then pitch (y), then yaw (z): R = Rz(y) Ry(p) Rx(r),
  // built here with Eigen's AngleAxis, independently of urdfdom's quaternion.
  const std::string xml = R"(<robot name="rot">
  <link name="body">
    <inertial>
      <origin xyz="0.1 -0.2 0.3" rpy="0.3 -0.2 0.5"/>
      <mass value="2"/>
      <inertia ixx="0.05" ixy="0.004" ixz="-0.003" iyy="0.06" iyz="0.002" izz="0.07"/>
    </inertial>
  </link>
  <joint name="j" type="fixed">
    <parent link="body"/>
    <child link="tip"/>
    <origin xyz="1 2 3" rpy="0.3 -0.2 0.5"/>
  </joint>
  <link name="tip"/>
</robot>)";
  const RobotDescription r = parse_urdf(xml, ".", "rot.urdf");
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  Eigen::Matrix3d I;
  I << 0.05, 0.004, -0.003, 0.004, 0.06, 0.002, -0.003, 0.002, 0.07;
  const Eigen::Matrix3d expected = R * I * R.transpose();
  EXPECT_LT((r.links[0].inertia_kgm2 - expected).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((r.links[0].com_m - Eigen::Vector3d(0.1, -0.2, 0.3)).norm(), 1e-15);
  EXPECT_LT((r.joints[0].X_PJ.linear() - R).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LT((r.joints[0].X_PJ.translation() - Eigen::Vector3d(1, 2, 3)).norm(), 1e-15);
  EXPECT_EQ(r.source, "");
}

TEST(UrdfLoad, ArmJointFields) {
  const RobotDescription r = load_urdf(urdf_data(kArm));
  const Joint& sp = joint_named(r, "shoulder_pitch");
  EXPECT_EQ(sp.type, JointType::Revolute);
  EXPECT_EQ(sp.parent, "shoulder");
  EXPECT_EQ(sp.child, "upper_arm");
  EXPECT_LT((sp.axis - Eigen::Vector3d(0, 1, 0)).norm(), 1e-15);  // written "0 2 0": normalised
  EXPECT_TRUE(sp.has_limits);
  EXPECT_EQ(sp.lower, -1.57);
  EXPECT_EQ(sp.upper, 1.57);
  EXPECT_EQ(sp.effort, 40.0);
  EXPECT_EQ(sp.velocity, 3.0);
  EXPECT_EQ(sp.damping, 0.5);
  EXPECT_EQ(sp.friction, 0.1);
  EXPECT_LT((sp.X_PJ.translation() - Eigen::Vector3d(0, 0, 0.1)).norm(), 1e-15);
  const Joint& sy = joint_named(r, "shoulder_yaw");
  EXPECT_EQ(sy.type, JointType::Continuous);
  EXPECT_FALSE(sy.has_limits);  // <limit effort velocity> only
  EXPECT_EQ(sy.effort, 60.0);
  EXPECT_EQ(sy.velocity, 4.0);
  EXPECT_EQ(sy.damping, 0.0);
  EXPECT_EQ(joint_named(r, "tool_joint").type, JointType::Fixed);
  EXPECT_FALSE(joint_named(r, "tool_joint").has_limits);
}

TEST(UrdfLoad, ArmMaterialsFromGlobalAndInlineDefinitions) {
  const RobotDescription r = load_urdf(urdf_data(kArm));
  ASSERT_EQ(link_named(r, "base").visuals.size(), 1u);
  EXPECT_EQ(link_named(r, "base").visuals[0].rgba, Eigen::Vector4d(0.5, 0.5, 0.5, 1));  // <material name="grey"/>
  EXPECT_EQ(link_named(r, "shoulder").visuals[0].rgba, Eigen::Vector4d(0.1, 0.2, 0.8, 1));
  EXPECT_EQ(link_named(r, "upper_arm").visuals[0].rgba, Eigen::Vector4d(0.7, 0.7, 0.7, 1));  // default
  ASSERT_EQ(link_named(r, "base").collisions.size(), 1u);
  EXPECT_EQ(link_named(r, "base").collisions[0].geometry.kind, Geometry::Kind::Box);
  EXPECT_EQ(link_named(r, "base").collisions[0].geometry.box_size_m, Eigen::Vector3d(0.5, 0.5, 0.5));
  const Geometry& cyl = link_named(r, "shoulder").visuals[0].geometry;
  EXPECT_EQ(cyl.kind, Geometry::Kind::Cylinder);
  EXPECT_EQ(cyl.radius_m, 0.06);
  EXPECT_EQ(cyl.length_m, 0.1);
}

TEST(UrdfLoad, ArmDefaultPoseAndHeightByHand) {
  const RobotDescription r = load_urdf(urdf_data(kArm));
  const auto X = default_pose_link_frames(r);
  ASSERT_EQ(X.size(), r.links.size());
  // Joint origins along z: 0.25 + 0.25 + 0.1 + 0.3 + 0.2 to the tool frame.
  EXPECT_NEAR(X[static_cast<std::size_t>(r.link_index("tool_frame"))].translation().z(), 1.1, 1e-15);
  EXPECT_NEAR(X[static_cast<std::size_t>(r.link_index("upper_arm"))].translation().z(), 0.6, 1e-15);
  // Lowest point: the base cube (edge 1 m scaled 0.5) centred at z = 0.25 -> z = 0.
  // Highest: the forearm cylinder, centre 0.9 + 0.1, half length 0.1 -> z = 1.1.
  // Mesh vertices are floats: 1e-7 m.
  EXPECT_NEAR(summarize(r).height_m, 1.1, 1e-7);
}

TEST(UrdfLoad, SimpleRobotHeightByHand) {
  const std::string xml = R"(<robot name="simple">
  <link name="base">
    <visual><geometry><box size="0.4 0.3 0.2"/></geometry></visual>
  </link>
  <joint name="neck" type="revolute">
    <parent link="base"/>
    <child link="head"/>
    <origin xyz="0 0 0.1"/>
    <axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="5" velocity="2"/>
  </joint>
  <link name="head">
    <visual><origin xyz="0 0 0.3"/><geometry><sphere radius="0.05"/></geometry></visual>
    <visual><origin xyz="0 0 0.4" rpy="0.5235987755982988 0 0"/><geometry><box size="0.1 0.1 0.02"/></geometry></visual>
  </link>
  <joint name="leg_mount" type="fixed">
    <parent link="base"/>
    <child link="leg"/>
    <origin xyz="0 0 -0.1" rpy="0 0.7853981633974483 0"/>
  </joint>
  <link name="leg">
    <visual><origin xyz="0 0 -0.3"/><geometry><cylinder radius="0.02" length="0.6"/></geometry></visual>
  </link>
</robot>)";
  const RobotDescription r = parse_urdf(xml, ".", "simple.urdf");
  // Top: the hat, a 0.1 x 0.1 x 0.02 box at z = 0.1 + 0.4 turned 30 deg about x:
  // half extent in z = (0.1 sin 30 + 0.02 cos 30) / 2.
  const double top = 0.5 + 0.5 * (0.1 * std::sin(M_PI / 6) + 0.02 * std::cos(M_PI / 6));
  // Bottom: the leg, pitched 45 deg at z = -0.1, its centre 0.3 down its axis, its far
  // rim another 0.3 down the axis and 0.02 across: -0.1 - (0.3 + 0.3 + 0.02) cos 45.
  const double bottom = -0.1 - 0.62 * std::cos(M_PI / 4);
  EXPECT_NEAR(summarize(r).height_m, top - bottom, 1e-12);

  // Cross-check of the cylinder: its two rim circles sampled every 0.01 deg.
  const auto X = default_pose_link_frames(r);
  const Link& leg = link_named(r, "leg");
  const Eigen::Isometry3d X_WG = X[static_cast<std::size_t>(r.link_index("leg"))] * leg.visuals[0].X_LG;
  double zmin = INFINITY;
  for (int k = 0; k < 36000; ++k) {
    const double th = 2 * M_PI * k / 36000;
    for (double h : {-0.3, 0.3}) zmin = std::min(zmin, (X_WG * Eigen::Vector3d(0.02 * std::cos(th), 0.02 * std::sin(th), h)).z());
  }
  EXPECT_NEAR(zmin, bottom, 1e-9);  // sampling error 0.02 (1 - cos(pi/36000)) ~ 8e-11
}

TEST(UrdfLoad, QuadrupedFloatingBaseVirtualChainsAndSensorFrames) {
  const std::string path = urdf_data(kQuad);
  const std::string text = slurp(path);
  const RobotDescription r = load_urdf(path);
  expect_tree_order(r);
  EXPECT_EQ(r.links[0].name, "world");
  EXPECT_EQ(r.joints[0].name, "floating_base");
  EXPECT_EQ(r.joints[0].type, JointType::Floating);
  const ModelSummary s = summarize(r);
  EXPECT_EQ(s.links, 30u);
  EXPECT_EQ(s.floating, 1u);
  EXPECT_EQ(s.fixed, 13u);      // imu, and per leg hip, thigh offset and foot
  EXPECT_EQ(s.revolute, 13u);   // payload pitch and three per leg
  EXPECT_EQ(s.prismatic, 2u);   // payload x and z
  EXPECT_EQ(s.continuous + s.planar, 0u);
  EXPECT_EQ(s.dof, 15u);
  int n = 0;
  EXPECT_NEAR(s.total_mass_kg, sum_of_mass_elements(text, &n), 1e-12);
  EXPECT_EQ(n, 14);  // trunk, payload, and hip, thigh, calf per leg
  // Massless links are kept as they are: virtual links of the chains, sensor frames.
  for (const char* l : {"imu_link", "payload_virtual_x", "payload_virtual_z", "FL_hip_virtual", "RR_thigh_virtual", "FR_foot"})
    EXPECT_EQ(link_named(r, l).mass_kg, 0.0) << l;
  // The virtual chain trunk -> x -> z -> pitch -> payload, in that order.
  const int px = r.joint_index("payload_x"), pz = r.joint_index("payload_z"), pp = r.joint_index("payload_pitch");
  EXPECT_LT(px, pz);
  EXPECT_LT(pz, pp);
  EXPECT_EQ(r.joints[static_cast<std::size_t>(px)].type, JointType::Prismatic);
  EXPECT_EQ(r.joints[static_cast<std::size_t>(pz)].lower, 0.0);
  EXPECT_EQ(r.joints[static_cast<std::size_t>(pz)].upper, 0.02);
  // A leg is contiguous, in file order (depth-first).
  const int fl = r.link_index("FL_hip_virtual");
  const std::vector<std::string> leg = {"FL_hip_virtual", "FL_hip", "FL_thigh_virtual", "FL_thigh", "FL_calf", "FL_foot"};
  for (std::size_t k = 0; k < leg.size(); ++k) EXPECT_EQ(r.links[static_cast<std::size_t>(fl) + k].name, leg[k]);
}

TEST(UrdfLoad, QuadrupedDefaultPoseAndHeight) {
  const RobotDescription r = load_urdf(urdf_data(kQuad));
  const auto X = default_pose_link_frames(r);
  // FL foot: hip at (0.19, 0.05, 0), thigh offset 0.083 in y, thigh 0.2 and calf 0.2 down.
  EXPECT_LT((X[static_cast<std::size_t>(r.link_index("FL_foot"))].translation() - Eigen::Vector3d(0.19, 0.133, -0.4)).norm(), 1e-15);
  EXPECT_LT((X[static_cast<std::size_t>(r.link_index("RR_foot"))].translation() - Eigen::Vector3d(-0.19, -0.133, -0.4)).norm(), 1e-15);
  // Top: payload box (0.06 + 0.02 + 0.04 / 2 = 0.1); bottom: foot spheres (-0.4 - 0.02).
  EXPECT_NEAR(summarize(r).height_m, 0.52, 1e-12);
}

TEST(UrdfLoad, UnknownTagsWarnOncePerNameWithTheFirstLine) {
  const std::string path = urdf_data(kQuad);
  const std::string text = slurp(path);
  const RobotDescription r = load_urdf(path);
  ASSERT_EQ(r.warnings.size(), 3u);  // gazebo, contact, transmission; not their children
  auto warning_for = [&](const std::string& tag) {
    std::vector<std::string> hits;
    for (const auto& w : r.warnings)
      if (w.find("<" + tag + ">") != std::string::npos) hits.push_back(w);
    EXPECT_EQ(hits.size(), 1u) << tag;
    return hits.empty() ? std::string() : hits[0];
  };
  const std::string gz = warning_for("gazebo");
  EXPECT_EQ(gz.rfind(path + ":" + std::to_string(line_of(text, "<gazebo reference=")) + ": ", 0), 0u) << gz;
  EXPECT_NE(gz.find("6 elements"), std::string::npos) << gz;
  const std::string tr = warning_for("transmission");
  EXPECT_EQ(tr.rfind(path + ":" + std::to_string(line_of(text, "<transmission name=")) + ": ", 0), 0u) << tr;
  EXPECT_NE(tr.find("12 elements"), std::string::npos) << tr;
  const std::string ct = warning_for("contact");
  EXPECT_EQ(ct.rfind(path + ":" + std::to_string(line_of(text, "<contact>\n")) + ": ", 0), 0u) << ct;
  for (const auto& w : r.warnings) EXPECT_EQ(w.find("hardwareInterface"), std::string::npos) << w;
}

TEST(UrdfLoad, PlanarJoint) {
  const RobotDescription r = load_urdf(urdf_data("mixed/mixed.urdf"));
  expect_tree_order(r);
  const Joint& j = joint_named(r, "puck_plane");
  EXPECT_EQ(j.type, JointType::Planar);
  EXPECT_EQ(j.axis, Eigen::Vector3d(0, 0, 1));
  const ModelSummary s = summarize(r);
  EXPECT_EQ(s.planar, 1u);
  EXPECT_EQ(s.dof, 0u);
  EXPECT_NEAR(s.total_mass_kg, sum_of_mass_elements(slurp(urdf_data("mixed/mixed.urdf"))), 1e-12);
}

TEST(UrdfLoad, MasslessLinkWithInertiaLoadsWithAWarning) {
  const std::string path = urdf_data("partial/massless_with_inertia.urdf");
  const RobotDescription r = load_urdf(path);
  ASSERT_EQ(r.links.size(), 1u);
  EXPECT_EQ(r.links[0].mass_kg, 0.0);
  EXPECT_EQ(r.links[0].inertia_kgm2, Eigen::Matrix3d::Identity() * 0.001);  // kept as written
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0].rfind(path + ":" + std::to_string(line_of(slurp(path), "<inertia ")) + ": link 'base_link': ", 0), 0u)
      << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("mass 0 with a nonzero inertia"), std::string::npos);
}

TEST(UrdfLoad, UrdfdomWarningsAreCollectedNotPrinted) {
  const std::string xml = R"(<robot name="r">
  <link name="a">
    <visual><geometry><box size="1 1 1"/></geometry><material name="undefined_red"/></visual>
  </link>
</robot>)";
  testing::internal::CaptureStderr();
  testing::internal::CaptureStdout();
  const RobotDescription r = parse_urdf(xml, ".", "mat.urdf");
  const std::string err = testing::internal::GetCapturedStderr();
  const std::string out = testing::internal::GetCapturedStdout();
  EXPECT_EQ(err, "");
  EXPECT_EQ(out, "");
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0].rfind("mat.urdf:2: urdfdom: ", 0), 0u) << r.warnings[0];  // the line of link 'a'
  EXPECT_NE(r.warnings[0].find("undefined_red"), std::string::npos);
  EXPECT_EQ(r.links[0].visuals[0].rgba, Eigen::Vector4d(0.7, 0.7, 0.7, 1));
}

}  // namespace
}  // namespace dmbd::model
