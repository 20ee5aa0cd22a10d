// The range-of-motion figure: per joint, the robot rendered at both limits and overlaid.
#include "dmbd/report/range_of_motion.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "dmbd/report/robot_scene.hpp"
#include "dmbd/viz/renderer.hpp"

namespace dmbd::report {

namespace {

constexpr double kPi = 3.14159265358979323846;

viz::Scene tinted(viz::Scene scene, const std::vector<bool>& moved, viz::Color c) {
  const Eigen::Vector4f rgba(c.r / 255.f, c.g / 255.f, c.b / 255.f, 1.f);
  for (std::size_t b = 0; b < scene.bodies.size(); ++b)
    if (moved[b])
      for (viz::SceneMesh& m : scene.bodies[b].meshes) m.rgba = rgba;
  return scene;
}

std::vector<Eigen::Isometry3d> pose(const model::RobotDescription& robot, std::vector<double> q, int joint,
                                    double value, double lift_m) {
  q[static_cast<std::size_t>(joint)] = value;
  std::vector<Eigen::Isometry3d> X = model::link_frames(robot, q);
  for (Eigen::Isometry3d& x : X) x.translation().z() += lift_m;
  return X;
}

// Looks along the joint's axis at both poses' bounds, from the side of the axis the
// joint is on (the front for an axis through the middle); a vertical axis is seen from
// the front and above.
viz::Camera joint_camera(const Eigen::Vector3d& axis_W, const Eigen::Vector3d& joint_from_root,
                         const Eigen::AlignedBox3d& bounds, int w, int h) {
  Eigen::Vector3d d = axis_W.normalized();
  if (std::abs(d.z()) > 0.8) {
    d = Eigen::Vector3d(1.0, 0.35 * (joint_from_root.y() < 0 ? -1 : 1), 1.3).normalized();
  } else {
    const double side = std::abs(d.dot(joint_from_root)) > 0.02 ? d.dot(joint_from_root) : d.x();
    if (side < 0) d = -d;
  }
  viz::Camera cam;
  cam.width_px = w, cam.height_px = h, cam.fov_y_deg = 30;
  const double half_y = cam.fov_y_deg * kPi / 360;
  const double half_x = std::atan(std::tan(half_y) * w / h);
  const double radius = std::max(0.05, 0.5 * bounds.diagonal().norm());
  cam.look_at = bounds.center();
  cam.position = cam.look_at + d * (1.05 * radius / std::sin(std::min(half_x, half_y)));
  return cam;
}

std::vector<std::string> caption(const model::Joint& j, const model::ChainJoint& c) {
  if (j.type == model::JointType::Prismatic)
    return {c.name, fmt::format("lower {:.3f} m", c.lower), fmt::format("upper {:.3f} m", c.upper),
            fmt::format("range {:.3f} m", c.upper - c.lower)};
  const double deg = 180 / kPi;
  std::vector<std::string> t{c.name, fmt::format("lower {:.3f} rad ({:.1f} deg)", c.lower, c.lower * deg),
                             fmt::format("upper {:.3f} rad ({:.1f} deg)", c.upper, c.upper * deg),
                             fmt::format("range {:.2f} rad = {:.1f} deg", c.upper - c.lower, (c.upper - c.lower) * deg)};
  if (c.unlimited) t.push_back("no limits: sampled over [-pi, pi]");
  return t;
}

// Text lines on a light panel in the top-left corner; lines 1 and 2 in the poses' colours.
void write_caption(cv::Mat& img, const std::vector<std::string>& lines, const RangeOfMotionOptions& o) {
  const int face = cv::FONT_HERSHEY_SIMPLEX, line_h = 22;
  const double scale = 0.52;
  int w = 0, base = 0;
  for (const std::string& s : lines) w = std::max(w, cv::getTextSize(s, face, scale, 1, &base).width);
  const cv::Rect panel = cv::Rect(6, 6, w + 16, line_h * static_cast<int>(lines.size()) + 10) &
                         cv::Rect(0, 0, img.cols, img.rows);
  cv::Mat area = img(panel);
  area.convertTo(area, -1, 0.25, 255 * 0.75);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const viz::Color c = i == 1 ? o.lower_color : i == 2 ? o.upper_color : viz::Color{20, 20, 20};
    cv::putText(img, lines[i], {14, 6 + line_h * static_cast<int>(i + 1)}, face, scale,
                cv::Scalar(c.b * 0.8, c.g * 0.8, c.r * 0.8), i == 0 ? 2 : 1, cv::LINE_AA);
  }
}

}  // namespace

std::vector<bool> links_moved_by(const model::RobotDescription& robot, int joint) {
  std::vector<bool> moved(robot.links.size(), false);
  const int child = robot.link_index(robot.joints.at(static_cast<std::size_t>(joint)).child);
  if (child >= 0) moved[static_cast<std::size_t>(child)] = true;
  for (std::size_t j = static_cast<std::size_t>(joint) + 1; j < robot.joints.size(); ++j) {  // parent before child
    const int p = robot.link_index(robot.joints[j].parent), c = robot.link_index(robot.joints[j].child);
    if (p >= 0 && c >= 0 && moved[static_cast<std::size_t>(p)]) moved[static_cast<std::size_t>(c)] = true;
  }
  return moved;
}

cv::Mat range_of_motion_image(const model::RobotDescription& robot, const std::vector<model::ChainJoint>& chain,
                              const RangeOfMotionOptions& o) {
  if (chain.empty()) throw std::invalid_argument("range of motion: no joints to draw");
  const int w = o.panel_width_px, h = o.panel_height_px;
  viz::Renderer renderer(w, h);
  renderer.style().ground = false;
  renderer.style().shadows = false;
  const viz::Scene scene = scene_from_robot(robot);
  const std::vector<double> rest = model::rest_positions(robot);
  std::vector<Eigen::Isometry3d> X_rest = model::link_frames(robot, rest);
  const double lift = viz::place_on_ground(scene, X_rest);  // the rest pose stands on z = 0
  std::vector<cv::Mat> panels;
  for (const model::ChainJoint& c : chain) {
    if (c.joint < 0 || c.joint >= static_cast<int>(robot.joints.size()))
      throw std::invalid_argument(fmt::format("range of motion: joint index {} out of range", c.joint));
    const model::Joint& joint = robot.joints[static_cast<std::size_t>(c.joint)];
    const std::vector<bool> moved = links_moved_by(robot, c.joint);
    const auto X_lo = pose(robot, rest, c.joint, c.lower, lift), X_hi = pose(robot, rest, c.joint, c.upper, lift);
    Eigen::AlignedBox3d bounds = viz::scene_bounds(scene, X_lo);
    bounds.extend(viz::scene_bounds(scene, X_hi));
    for (std::size_t l = 0; l < X_lo.size(); ++l) bounds.extend(X_lo[l].translation()).extend(X_hi[l].translation());
    const Eigen::Isometry3d X_WJ = X_rest[static_cast<std::size_t>(robot.link_index(joint.parent))] * joint.X_PJ;
    const viz::Camera cam = joint_camera(X_WJ.linear() * joint.axis, X_WJ.translation() - X_rest.front().translation(),
                                         bounds, w, h);
    renderer.set_scene(tinted(scene, moved, o.upper_color));
    const cv::Mat hi = renderer.render(X_hi, cam).clone(), hi_ids = renderer.body_ids().clone();
    renderer.set_scene(tinted(scene, moved, o.lower_color));
    const cv::Mat& lo = renderer.render(X_lo, cam);
    const cv::Mat& lo_ids = renderer.body_ids();
    cv::Mat out = hi.clone();
    const auto is_moved = [&](short id) { return id >= 0 && static_cast<std::size_t>(id) < moved.size() && moved[id]; };
    for (int r = 0; r < h; ++r)
      for (int col = 0; col < w; ++col)
        if (is_moved(lo_ids.at<short>(r, col)) && !is_moved(hi_ids.at<short>(r, col))) {
          const cv::Vec3b a = lo.at<cv::Vec3b>(r, col), b = hi.at<cv::Vec3b>(r, col);
          cv::Vec3b& p = out.at<cv::Vec3b>(r, col);
          for (int k = 0; k < 3; ++k)
            p[k] = static_cast<unsigned char>(std::lround(o.lower_opacity * a[k] + (1 - o.lower_opacity) * b[k]));
        }
    write_caption(out, caption(joint, c), o);
    cv::rectangle(out, cv::Rect(0, 0, w, h), cv::Scalar(120, 120, 120), 1);
    panels.push_back(out);
  }
  cv::Mat image;
  cv::hconcat(panels, image);
  return image;
}

}  // namespace dmbd::report
