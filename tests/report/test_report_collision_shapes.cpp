// Robots whose visual meshes are missing (report::scene_from_robot, the frames): a link
// with a missing visual mesh, or with no visual, is drawn from its collision shapes in
// the stand-in colour, a link whose visuals loaded as before; the frames say which links
// in one warning; a box resting on the ground gets its contact force arrow at its centre
// of pressure, under its centre of mass, drawn where nothing was without it.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "dmbd/model/robot_description.hpp"
#include "dmbd/report/report.hpp"
#include "dmbd/report/robot_scene.hpp"
#include "dmbd/scenario/run_directory.hpp"
#include "dmbd/viz/renderer.hpp"
#include "sim_test_support.hpp"

namespace {

using dmbd::sim::test::TempDir;
using dmbd::sim::test::write_text;

const char* const kInertial =
    "<inertial><mass value=\"1\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial>";

// body: a missing visual mesh, a collision box 0.2 x 0.1 x 0.05 m 0.1 m above its origin
// and a collision box of zero size (nothing to draw); lit: a red visual cylinder and a
// collision sphere (its visual is drawn); bare: no visual, a collision sphere; ghost: a
// missing visual mesh and no collision (nothing drawn).
std::string robot_urdf() {
  auto link = [](const std::string& name, const std::string& body) { return "<link name=\"" + name + "\">" + kInertial + body + "</link>\n"; };
  auto fixed = [](const std::string& child, const std::string& xyz) {
    return "<joint name=\"to_" + child + "\" type=\"fixed\"><parent link=\"body\"/><child link=\"" + child + "\"/><origin xyz=\"" + xyz +
           "\"/></joint>\n";
  };
  return "<?xml version=\"1.0\"?>\n<robot name=\"stand_ins\">\n" +
         link("body",
              "<visual><geometry><mesh filename=\"missing_body.stl\"/></geometry></visual>"
              "<collision><origin xyz=\"0 0 0.1\"/><geometry><box size=\"0.2 0.1 0.05\"/></geometry></collision>"
              "<collision><geometry><box size=\"0 0.1 0.1\"/></geometry></collision>") +
         fixed("lit", "0.4 0 0") +
         link("lit",
              "<visual><geometry><cylinder radius=\"0.05\" length=\"0.1\"/></geometry><material name=\"red\"><color rgba=\"1 0 0 1\"/></material></visual>"
              "<collision><geometry><sphere radius=\"0.2\"/></geometry></collision>") +
         fixed("bare", "0 0.4 0") + link("bare", "<collision><geometry><sphere radius=\"0.05\"/></geometry></collision>") +
         fixed("ghost", "0 -0.4 0") + link("ghost", "<visual><geometry><mesh filename=\"missing_ghost.stl\"/></geometry></visual>") +
         "</robot>\n";
}

TEST(CollisionStandIns, MissingVisualMeshesAreReplacedByTheCollisionShapes) {
  TempDir dir;
  const dmbd::model::RobotDescription robot = dmbd::model::parse_urdf(robot_urdf(), dir.path().string(), "stand_ins.urdf");
  ASSERT_EQ(robot.meshes_missing.size(), 2u);
  EXPECT_EQ(dmbd::report::links_drawn_from_collisions(robot), (std::vector<std::string>{"body", "bare"}));
  const dmbd::report::RobotSceneOptions options;
  const dmbd::viz::Scene scene = dmbd::report::scene_from_robot(robot, options);
  ASSERT_EQ(scene.bodies.size(), 4u);
  // body: the box alone (12 triangles), in the stand-in colour, centred 0.1 m up.
  const auto& body = scene.bodies[static_cast<std::size_t>(robot.link_index("body"))];
  ASSERT_EQ(body.meshes.size(), 1u);
  EXPECT_EQ(body.meshes[0].triangles.size(), 12u);
  EXPECT_EQ(body.meshes[0].rgba, options.collision_rgba);
  Eigen::AlignedBox3f box;
  for (const auto& v : body.meshes[0].vertices) box.extend(v);
  EXPECT_TRUE(box.min().isApprox(Eigen::Vector3f(-0.1f, -0.05f, 0.075f), 1e-6f)) << box.min().transpose();
  EXPECT_TRUE(box.max().isApprox(Eigen::Vector3f(0.1f, 0.05f, 0.125f), 1e-6f)) << box.max().transpose();
  // lit: its red cylinder, not the sphere; bare: its sphere; ghost: nothing.
  const auto& lit = scene.bodies[static_cast<std::size_t>(robot.link_index("lit"))];
  ASSERT_EQ(lit.meshes.size(), 1u);
  EXPECT_EQ(lit.meshes[0].rgba, Eigen::Vector4f(1, 0, 0, 1));
  const auto& bare = scene.bodies[static_cast<std::size_t>(robot.link_index("bare"))];
  ASSERT_EQ(bare.meshes.size(), 1u);
  EXPECT_EQ(bare.meshes[0].rgba, options.collision_rgba);
  EXPECT_TRUE(scene.bodies[static_cast<std::size_t>(robot.link_index("ghost"))].meshes.empty());

  // Drawn: the box covers pixels of its body id, in the stand-in colour (hue 169 deg +- 8,
  // saturated) as shaded, where the scene without stand-ins shows the ground.
  dmbd::viz::Camera cam;
  cam.position = {0.8, -0.9, 0.6};
  cam.look_at = {0.1, 0, 0.1};
  cam.width_px = 320;
  cam.height_px = 240;
  dmbd::viz::Renderer renderer(320, 240);
  renderer.set_scene(scene);
  const auto X = dmbd::model::link_frames(robot, std::vector<double>(robot.joints.size(), 0.0));
  const cv::Mat img = renderer.render(X, cam).clone();
  const cv::Mat on_body = renderer.body_ids() == robot.link_index("body");
  const int n = cv::countNonZero(on_body);
  cv::Mat hsv, teal;
  cv::cvtColor(img, hsv, cv::COLOR_BGR2HSV);
  cv::inRange(hsv, cv::Scalar(80, 70, 40), cv::Scalar(89, 255, 255), teal);
  std::printf("the box covers %d px, %d of them in the stand-in colour\n", n, cv::countNonZero(teal & on_body));
  EXPECT_GT(n, 1000);
  EXPECT_GT(cv::countNonZero(teal & on_body), 0.9 * n);
  dmbd::viz::Scene hidden = scene;
  for (auto& b : hidden.bodies)
    if (b.name == "body" || b.name == "bare") b.meshes.clear();
  renderer.set_scene(hidden);
  renderer.render(X, cam);
  EXPECT_EQ(cv::countNonZero(renderer.body_ids() == robot.link_index("body")), 0);
}

// A 50 kg block (a box 0.5 x 0.4 x 0.1 m, its visual mesh missing), its centre of mass
// 6 cm and 4 cm off the box's centre, resting on the ground for 1 s (it rocks on its
// corners for the first 0.5 s; at 1 s the contact force is m g to 0.1 %); frames at 0,
// 0.5 and 1 s, 640 x 360, from a fixed camera. The frames warn that it is drawn from its
// collision shape. Its arrow in the last frame: that frame minus the same frame with the
// contact force zeroed in the log (no arrow) differs only within 9 px of the projection
// of the force from the centre of mass's ground point (the centre of pressure in statics;
// the arrow's head is 10 px wide), and along it: near its middle and near its tip. An
// arrow at one of the box's lowest corners, the other place it could be drawn, would be
// more than 40 px off that line (the view is chosen so).
TEST(ContactArrows, ABoxFootsArrowStartsAtItsCentreOfPressure) {
  TempDir dir;
  write_text(dir.file("block.urdf"),
             "<?xml version=\"1.0\"?>\n<robot name=\"block\">\n<link name=\"block\">"
             "<inertial><origin xyz=\"0.06 0.04 0\"/><mass value=\"50\"/><inertia ixx=\"0.42\" ixy=\"0\" ixz=\"0\" iyy=\"0.71\" iyz=\"0\" izz=\"1.04\"/></inertial>"
             "<visual><geometry><mesh filename=\"block_visual.stl\"/></geometry></visual>"
             "<collision><geometry><box size=\"0.5 0.4 0.1\"/></geometry></collision></link>\n</robot>\n");
  write_text(dir.file("block.yaml"),
             "name: block\nrobot: {urdf: block.urdf, base: floating, contact: true, base_pose: {xyz: [0, 0.5, 0.3], rpy: [0, 0, 0.89]}}\n"
             "integration: {mode: fixed, step_s: 0.0005}\nduration_s: 1.0\nlog_rate_hz: 1000\n"
             "frames: {fps: 2, width: 640, height: 360, camera: {position: [1.0, -0.5, 0.8], look_at: [0, 0.5, 0.2]}}\n");
  auto run = dmbd::scenario::run_scenario(dmbd::scenario::load_scenario(dir.file("block.yaml")), dir.file("with"));
  const auto with = dmbd::report::write_report(run, dir.file("with"));
  ASSERT_EQ(with.frames, 3);
  EXPECT_EQ(std::count_if(with.warnings.begin(), with.warnings.end(),
                          [](const std::string& w) { return w.find("1 links drawn from their collision shapes") != std::string::npos &&
                                                            w.find(": block") != std::string::npos; }),
            1);
  for (const auto& w : with.warnings) EXPECT_EQ(w.find("block_visual.stl"), std::string::npos) << w;  // covered by that line
  const dmbd::sim::Log& log = run.runs[0].log;
  const std::size_t row = log.rows() - 1;  // t = 1 s: the last frame
  const auto at = [&](const char* name) { return log.column(name)[row]; };
  const Eigen::Vector3d f(at("contact.0.fx"), at("contact.0.fy"), at("contact.0.fz"));
  ASSERT_NEAR(f.z(), 50 * 9.81, 0.001 * 50 * 9.81);
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() << at("base.x"), at("base.y"), at("base.z");
  X.linear() = (Eigen::AngleAxisd(at("base.yaw"), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(at("base.pitch"), Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(at("base.roll"), Eigen::Vector3d::UnitX())).toRotationMatrix();
  const Eigen::Vector3d com = X * Eigen::Vector3d(0.06, 0.04, 0), tail(com.x(), com.y(), 0), tip = tail + 0.001 * f;

  // The same log with the contact force zeroed.
  dmbd::sim::Log bare;
  for (std::size_t c = 1; c < log.columns(); ++c) bare.add_column(log.name(int(c)), log.unit(int(c)));
  for (std::size_t r = 0; r < log.rows(); ++r) {
    bare.begin_row(log.time()[r]);
    for (std::size_t c = 1; c < log.columns(); ++c)
      bare.set(int(c), log.name(int(c)).rfind("contact.", 0) == 0 ? 0.0 : log.column(int(c))[r]);
  }
  run.runs[0].log = bare;
  ASSERT_EQ(dmbd::report::write_report(run, dir.file("without")).frames, 3);
  const cv::Mat a = cv::imread(dir.file("with") + "/frames/frame_00002.png", cv::IMREAD_COLOR);
  const cv::Mat b = cv::imread(dir.file("without") + "/frames/frame_00002.png", cv::IMREAD_COLOR);
  ASSERT_EQ(a.size(), cv::Size(640, 360));
  ASSERT_EQ(b.size(), a.size());

  dmbd::viz::Camera cam;
  cam.position = {1.0, -0.5, 0.8};
  cam.look_at = {0, 0.5, 0.2};
  cam.width_px = 640;
  cam.height_px = 360;
  const Eigen::Vector2d p0 = *dmbd::viz::project(cam, tail), p1 = *dmbd::viz::project(cam, tip);
  const auto distance = [&](const Eigen::Vector2d& q) {  // to the segment p0 p1, px
    const double s = std::clamp((q - p0).dot(p1 - p0) / (p1 - p0).squaredNorm(), 0.0, 1.0);
    return (q - (p0 + s * (p1 - p0))).norm();
  };
  cv::Mat d;
  cv::absdiff(a, b, d);
  int changed = 0, astray = 0, middle = 0, top = 0;
  for (int r = 0; r < d.rows; ++r)
    for (int c = 0; c < d.cols; ++c) {
      const cv::Vec3b v = d.at<cv::Vec3b>(r, c);
      if (std::max({v[0], v[1], v[2]}) == 0) continue;
      const Eigen::Vector2d q(c + 0.5, r + 0.5);
      ++changed;
      astray += distance(q) > 9;
      middle += (q - 0.5 * (p0 + p1)).norm() <= 2;
      top += (q - (p0 + 0.9 * (p1 - p0))).norm() <= 2;
    }
  double nearest_corner = 1e9;  // px from the arrow's line
  const Eigen::Vector2d along = (p1 - p0).normalized();
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d corner = X * Eigen::Vector3d(k & 1 ? 0.25 : -0.25, k & 2 ? 0.2 : -0.2, -0.05);
    const Eigen::Vector2d q = *dmbd::viz::project(cam, corner) - p0;
    nearest_corner = std::min(nearest_corner, (q - q.dot(along) * along).norm());
  }
  std::printf("arrow from (%.1f, %.1f) to (%.1f, %.1f) px: %d pixels changed, %d astray; nearest corner %.0f px away\n", p0.x(),
              p0.y(), p1.x(), p1.y(), changed, astray, nearest_corner);
  EXPECT_GT((p1 - p0).norm(), 80);  // 0.49 m of arrow
  EXPECT_GT(changed, 200);
  EXPECT_EQ(astray, 0);
  EXPECT_GT(middle, 0);
  EXPECT_GT(top, 0);
  EXPECT_GT(nearest_corner, 40);
}

}  // namespace
