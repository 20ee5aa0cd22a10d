// DRACO frames against reference images (tests/report/data/render_*.png, drawn by the
// renderer of commit 14a6c05, before its speed-ups of issue 29 item 6): the image, and
// the body seen at each pixel, of a fixed pose from two cameras, with every overlay.
// The speed-ups skip work whose result is known (ground no grid line reaches, off the
// shadow map, nearer than the fade; the background of a camera kept between frames),
// they do not change what is drawn: the images are the same, byte for byte, today. The
// bounds below leave room for a later change of the arithmetic's order (a rounding of
// a colour level here and there):
//   * the body seen at each pixel is the same at all but 0.01% of the pixels (the
//     rasteriser's fixed-point coverage is unchanged);
//   * per colour channel, the mean absolute difference is at most 0.25 levels, 99.5%
//     of the pixels differ by at most 2 levels in every channel, and none by more than
//     48 (a pixel on a grid line's edge may take the line's colour or the ground's).
// The same frame drawn again by one renderer (from the background it keeps for a
// camera seen twice in a row) is the same image, byte for byte, and so is another pose
// drawn from the kept background and by a new renderer.
//
// DMBD_WRITE_RENDER_REFERENCE=1 writes the reference images instead of checking them.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <ostream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "dmbd/base/file.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/report/robot_scene.hpp"
#include "dmbd/viz/plot.hpp"
#include "dmbd/viz/primitives.hpp"
#include "dmbd/viz/renderer.hpp"

namespace dmbd::viz {
namespace {

const std::string kData = std::string(DMBD_SOURCE_DIR) + "/tests/report/data/";

struct Case {
  const char* name;
  int w, h;
  Eigen::Vector3d position, look_at;
  double near_m;
};
// The test's name in ctest's listing (GoogleTest prints a struct as its raw bytes).
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }


// A walking pose (left leg forward, right knee bent), placed on the ground, and the
// overlays a balancing run draws: text, CoM, two contact forces, a path and a marker.
struct Frame {
  std::vector<Eigen::Isometry3d> X;
  Overlays ov;
};

Frame draco_frame(const model::RobotDescription& robot, const Scene& scene) {
  Frame f;
  std::vector<double> q(robot.joints.size(), 0.0);
  q[robot.joint_index("l_hip_pitch")] = -0.7;
  q[robot.joint_index("r_hip_pitch")] = -0.1;
  q[robot.joint_index("l_knee")] = 0.9;
  q[robot.joint_index("r_knee")] = 1.2;
  q[robot.joint_index("l_ankle")] = -0.3;
  q[robot.joint_index("r_ankle")] = -0.5;
  f.X = model::link_frames(robot, q);
  place_on_ground(scene, f.X);
  f.ov.text_lines = {"balance  |  actuated", "t = 12.345 s", "phase: left swing"};
  f.ov.com_W = Eigen::Vector3d(0.01, 0.02, 0.88);
  f.ov.forces.push_back({Eigen::Vector3d(0.02, 0.167, 0.0), Eigen::Vector3d(10, -5, 250), {230, 50, 40}});
  f.ov.forces.push_back({Eigen::Vector3d(0.02, -0.167, 0.0), Eigen::Vector3d(-8, 4, 120), {230, 50, 40}});
  PathOverlay path;
  for (int i = 0; i <= 200; ++i) {
    const double s = i / 200.0;
    path.points_W.emplace_back(-0.3 + 0.6 * s, 0.1 * std::sin(6.0 * s), 0.9 + 0.02 * std::cos(9.0 * s));
  }
  path.label = "CoM";
  f.ov.paths.push_back(path);
  f.ov.markers.push_back({Eigen::Vector3d(0.25, 0.18, 0.0), {255, 140, 0}, 0.06, "foothold"});
  return f;
}

cv::Mat ids_as_bytes(const cv::Mat& ids) {  // -1 (ground, sky) -> 0, body b -> b + 1
  cv::Mat out;
  ids.convertTo(out, CV_8U, 1.0, 1.0);
  return out;
}

class RenderReference : public ::testing::TestWithParam<Case> {
 protected:
  static void SetUpTestSuite() {
    robot_ = new model::RobotDescription(model::load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf"));
    scene_ = new Scene(report::scene_from_robot(*robot_));
  }
  static void TearDownTestSuite() {
    delete scene_;
    delete robot_;
  }
  static model::RobotDescription* robot_;
  static Scene* scene_;
};
model::RobotDescription* RenderReference::robot_ = nullptr;
Scene* RenderReference::scene_ = nullptr;

TEST_P(RenderReference, SameImageAsTheReference) {
  const Case& c = GetParam();
  Camera cam;
  cam.position = c.position;
  cam.look_at = c.look_at;
  cam.width_px = c.w;
  cam.height_px = c.h;
  cam.near_m = c.near_m;
  Renderer renderer(c.w, c.h);
  renderer.set_scene(*scene_);
  const Frame f = draco_frame(*robot_, *scene_);
  const cv::Mat img = renderer.render(f.X, cam, f.ov).clone();
  const cv::Mat ids = ids_as_bytes(renderer.body_ids());
  const std::string img_path = kData + "render_" + c.name + ".png", ids_path = kData + "render_" + c.name + "_ids.png";
  if (const char* w = std::getenv("DMBD_WRITE_RENDER_REFERENCE"); w && std::string(w) == "1") {
    write_file_atomic(img_path, encode_png(img));
    write_file_atomic(ids_path, encode_png(ids));
    GTEST_SKIP() << "wrote " << img_path << " and " << ids_path;
  }
  const cv::Mat ref = cv::imread(img_path, cv::IMREAD_COLOR);
  const cv::Mat ref_ids = cv::imread(ids_path, cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(ref.empty()) << img_path;
  ASSERT_FALSE(ref_ids.empty()) << ids_path;
  ASSERT_EQ(ref.size(), img.size());
  ASSERT_EQ(ref_ids.size(), ids.size());

  const double n = static_cast<double>(c.w) * c.h;
  EXPECT_LE(cv::countNonZero(ids != ref_ids), 1e-4 * n);
  cv::Mat diff;
  cv::absdiff(img, ref, diff);
  const cv::Scalar mean = cv::mean(diff);
  for (int ch = 0; ch < 3; ++ch) EXPECT_LE(mean[ch], 0.25) << "channel " << ch;
  cv::Mat max_diff(diff.size(), CV_8U);
  for (int r = 0; r < diff.rows; ++r)
    for (int col = 0; col < diff.cols; ++col) {
      const cv::Vec3b d = diff.at<cv::Vec3b>(r, col);
      max_diff.at<std::uint8_t>(r, col) = std::max({d[0], d[1], d[2]});
    }
  EXPECT_LE(cv::countNonZero(max_diff > 2), 0.005 * n);
  double worst = 0;
  cv::minMaxLoc(max_diff, nullptr, &worst);
  EXPECT_LE(worst, 48);
  std::printf("%s: %d pixels of another body, mean difference (B, G, R) %.4f %.4f %.4f levels, %d pixels off by more "
              "than 2, at most %.0f\n",
              c.name, cv::countNonZero(ids != ref_ids), mean[0], mean[1], mean[2], cv::countNonZero(max_diff > 2), worst);

  // Drawn again: the second time the renderer keeps the background of the camera seen
  // twice, the third time it starts from it; the same bytes each time.
  for (int k = 0; k < 2; ++k) {
    const cv::Mat again = renderer.render(f.X, cam, f.ov);
    EXPECT_EQ(cv::norm(again, img, cv::NORM_INF), 0.0) << k;
  }
  // Another pose (its shadow elsewhere) from the kept background: the same bytes as a
  // new renderer's.
  std::vector<Eigen::Isometry3d> X2 = f.X;
  for (auto& X : X2) X.translation() += Eigen::Vector3d(0.15, -0.1, 0.0);
  const cv::Mat moved = renderer.render(X2, cam, f.ov).clone();
  Renderer fresh(c.w, c.h);
  fresh.set_scene(*scene_);
  EXPECT_EQ(cv::norm(fresh.render(X2, cam, f.ov), moved, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::countNonZero(fresh.body_ids() != renderer.body_ids()), 0);
}

// The default three-quarter view at 960x540 (ground, grid, axes, shadow, sky at the
// top), and a low camera close to the robot at 480x270 whose near plane cuts a foot
// (clipped triangles) with the horizon across the frame.
INSTANTIATE_TEST_SUITE_P(Draco, RenderReference,
                         ::testing::Values(Case{"three_quarter_960x540", 960, 540, Eigen::Vector3d(1.65, -1.75, 1.25),
                                                Eigen::Vector3d(0.0, 0.0, 0.62), 0.05},
                                           Case{"low_close_480x270", 480, 270, Eigen::Vector3d(0.55, -0.25, 0.25),
                                                Eigen::Vector3d(-0.3, 0.2, 0.5), 0.25}),
                         [](const ::testing::TestParamInfo<Case>& i) { return std::string(i.param.name); });

}  // namespace
}  // namespace dmbd::viz
