// Tests for the mesh renderer (dmbd::viz::Renderer) on primitive scenes: projection
// against the pinhole formula, z-buffer order independence, silhouette area against
// the analytic projected area, Lambert shading, the ground grid, near-plane clipping,
// overlays (paths here; text, CoM and arrows with DRACO's scene in
// tests/report/test_report_robot.cpp, which also checks render() does not allocate),
// the same bytes drawn by any number of threads.
#include "dmbd/base/file.hpp"
#include "dmbd/viz/renderer.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "dmbd/viz/plot.hpp"
#include "dmbd/viz/primitives.hpp"

namespace dmbd::viz {
namespace {

constexpr int kW = 640, kH = 360;  // small frames keep the tests fast

Eigen::Isometry3d pose(const Eigen::Vector3d& p, const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity()) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = R;
  X.translation() = p;
  return X;
}

Eigen::Matrix3d rot(double angle_rad, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
}

Camera camera(const Eigen::Vector3d& position, const Eigen::Vector3d& look_at, int w = kW, int h = kH,
              double fov_deg = 40) {
  Camera c;
  c.position = position;
  c.look_at = look_at;
  c.width_px = w;
  c.height_px = h;
  c.fov_y_deg = fov_deg;
  return c;
}

SceneMesh coloured(SceneMesh m, float r, float g, float b) {
  m.rgba = {r, g, b, 1.0f};
  return m;
}

Scene one_body(SceneMesh m, const std::string& name = "body") {
  Scene s;
  s.bodies.push_back({name, {std::move(m)}});
  return s;
}

// A square quad in the body's x-y plane, side `side_m`, normal +z, no vertex normals.
SceneMesh quad(double side_m) {
  const float h = static_cast<float>(0.5 * side_m);
  SceneMesh m;
  m.vertices = {{-h, -h, 0}, {h, -h, 0}, {h, h, 0}, {-h, h, 0}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

int count_ids(const cv::Mat& ids, int id) {
  int n = 0;
  for (int r = 0; r < ids.rows; ++r)
    for (int c = 0; c < ids.cols; ++c) n += ids.at<std::int16_t>(r, c) == id ? 1 : 0;
  return n;
}

cv::Vec3b pixel_at(const cv::Mat& img, const Eigen::Vector2d& uv) {
  return img.at<cv::Vec3b>(static_cast<int>(std::floor(uv.y())), static_cast<int>(std::floor(uv.x())));
}

double srgb_to_linear(double c8) {
  const double c = c8 / 255.0;
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

// ---------------------------------------------------------------------------------
// Camera.

TEST(Camera, ProjectionMatchesPinholeFormula) {
  const Camera cam = camera({3.0, -2.0, 1.5}, {0.2, 0.1, 0.7}, 1280, 720, 50);
  // The pinhole model built independently: Gram-Schmidt of `up` against the view axis.
  const Eigen::Vector3d fwd = (cam.look_at - cam.position).normalized();
  const Eigen::Vector3d up_img = (cam.up - cam.up.dot(fwd) * fwd).normalized();
  const Eigen::Vector3d right = fwd.cross(up_img);
  const double f = 360.0 / std::tan(25.0 * M_PI / 180.0);
  EXPECT_NEAR(focal_length_px(cam), f, 1e-9);
  const std::vector<Eigen::Vector3d> points = {cam.look_at, {0, 0, 0}, {1, 1, 2}, {-0.5, 0.7, 0.1}, {2.0, -1.0, 1.4}};
  for (const auto& p : points) {
    const Eigen::Vector3d d = p - cam.position;
    const double u = 640.0 + f * d.dot(right) / d.dot(fwd);
    const double v = 360.0 - f * d.dot(up_img) / d.dot(fwd);
    const auto uv = project(cam, p);
    ASSERT_TRUE(uv.has_value());
    EXPECT_NEAR(uv->x(), u, 0.5) << p.transpose();
    EXPECT_NEAR(uv->y(), v, 0.5) << p.transpose();
  }
  // The look-at point is the image centre; the top edge of the field of view is row 0.
  EXPECT_NEAR(project(cam, cam.look_at)->x(), 640.0, 1e-9);
  EXPECT_NEAR(project(cam, cam.look_at)->y(), 360.0, 1e-9);
  const Eigen::Vector3d top_ray = Eigen::AngleAxisd(25.0 * M_PI / 180.0, right) * fwd;  // tilted up
  EXPECT_NEAR(project(cam, cam.position + 3.0 * top_ray)->y(), 0.0, 1e-6);
  // Behind the camera, or nearer than the near plane: no projection.
  EXPECT_FALSE(project(cam, cam.position - fwd).has_value());
  EXPECT_FALSE(project(cam, cam.position + 0.5 * cam.near_m * fwd).has_value());
}

TEST(Camera, RasterisedSphereCentredOnItsProjection) {
  // The renderer and project() agree: the centroid of a small sphere's pixels lies on
  // the projection of its centre (a sphere's image is an ellipse whose centroid is off
  // the projected centre by ~ f r^2 tan(a) / d^2: 0.03 px here), within 0.5 px.
  const Camera cam = camera({2.5, 1.5, 1.2}, {0, 0, 0.5});
  Renderer renderer(kW, kH);
  renderer.set_scene(one_body(sphere_mesh(0.05, 48)));
  const Eigen::Vector3d centre(0.3, -0.2, 0.7);
  renderer.render({pose(centre)}, cam);
  const cv::Mat mask = renderer.body_ids() == 0;
  const cv::Moments mo = cv::moments(mask, true);
  ASSERT_GT(mo.m00, 100);
  const auto uv = project(cam, centre);
  ASSERT_TRUE(uv.has_value());
  EXPECT_NEAR(mo.m10 / mo.m00 + 0.5, uv->x(), 0.5);  // pixel (c, r) has centre (c + 0.5, r + 0.5)
  EXPECT_NEAR(mo.m01 / mo.m00 + 0.5, uv->y(), 0.5);
}

TEST(Camera, InvalidCamerasAndInputsThrow) {
  Camera c = camera({1, 0, 1}, {0, 0, 1});
  c.up = Eigen::Vector3d::UnitX();  // parallel to the view direction
  EXPECT_THROW(validate(c), std::invalid_argument);
  c = camera({1, 0, 1}, {1, 0, 1});
  EXPECT_THROW(validate(c), std::invalid_argument);
  c = camera({1, 0, 1}, {0, 0, 1});
  c.fov_y_deg = 180;
  EXPECT_THROW(validate(c), std::invalid_argument);

  Renderer renderer(kW, kH);
  renderer.set_scene(one_body(box_mesh({0.1, 0.1, 0.1})));
  EXPECT_THROW(renderer.render({}, camera({1, 0, 1}, {0, 0, 0})), std::invalid_argument);  // 0 poses, 1 body
  EXPECT_THROW(renderer.render({pose({0, 0, 0})}, camera({1, 0, 1}, {0, 0, 0}, 320, 200)), std::invalid_argument);
  SceneMesh bad = quad(0.1);
  bad.triangles.push_back({0, 1, 4});
  EXPECT_THROW(renderer.set_scene(one_body(bad)), std::invalid_argument);
  bad = quad(0.1);
  bad.normals = {Eigen::Vector3f::UnitZ()};
  EXPECT_THROW(renderer.set_scene(one_body(bad)), std::invalid_argument);
  EXPECT_THROW(Renderer(8, 8), std::invalid_argument);
}

// ---------------------------------------------------------------------------------
// Visibility and coverage.

TEST(Rasteriser, NearBoxOccludesFarBoxInEitherDrawOrder) {
  const Camera cam = camera({3, 0, 1}, {0, 0, 1});
  const SceneMesh near_box = coloured(box_mesh({0.3, 0.3, 0.3}), 0.9f, 0.1f, 0.1f);
  const SceneMesh far_box = coloured(box_mesh({0.6, 0.6, 0.6}), 0.1f, 0.2f, 0.9f);
  const Eigen::Isometry3d X_near = pose({1.0, 0.1, 1.0}), X_far = pose({-1.0, 0.0, 1.0});
  Scene near_first, far_first;
  near_first.bodies = {{"near", {near_box}}, {"far", {far_box}}};
  far_first.bodies = {{"far", {far_box}}, {"near", {near_box}}};
  Renderer a(kW, kH), b(kW, kH);
  a.set_scene(near_first);
  b.set_scene(far_first);
  const cv::Mat img_a = a.render({X_near, X_far}, cam).clone();
  const cv::Mat img_b = b.render({X_far, X_near}, cam).clone();
  // The same image whichever body is drawn first (exact: the depth test is strict and
  // the two boxes never tie in depth).
  EXPECT_EQ(cv::norm(img_a, img_b, cv::NORM_INF), 0.0);
  // The near box's centre pixel shows the near box (red), in both renderers.
  const Eigen::Vector2d c_near = *project(cam, X_near.translation());
  EXPECT_EQ(a.body_ids().at<std::int16_t>(int(c_near.y()), int(c_near.x())), 0);
  EXPECT_EQ(b.body_ids().at<std::int16_t>(int(c_near.y()), int(c_near.x())), 1);
  const cv::Vec3b px = pixel_at(img_a, c_near);
  EXPECT_GT(px[2], px[0] + 60);  // red over blue (BGR)
  // The far box shows around it.
  EXPECT_GT(count_ids(a.body_ids(), 1), 2000);
}

TEST(Rasteriser, CubeSilhouetteAreaMatchesProjectedHull) {
  // A convex polyhedron's image under a pinhole is the convex hull of its projected
  // vertices. Pixel-centre sampling of straight edges errs by a fraction of the number
  // of boundary pixels (here ~700 px around ~45000 px, < 1.6% in the worst case and
  // well under it on average); 1% still catches a focal length off by 0.5% or cracks
  // along the diagonals of the faces.
  const Camera cam = camera({1.6, 0.7, 1.2}, {0, 0, 0.6});
  const Eigen::Isometry3d X = pose({0.05, -0.03, 0.62}, rot(0.5, {0.3, 0.2, 1.0}));
  Renderer renderer(kW, kH);
  renderer.set_scene(one_body(box_mesh({0.6, 0.6, 0.6})));
  renderer.render({X}, cam);
  std::vector<cv::Point2f> corners;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d p_B(i & 1 ? 0.3 : -0.3, i & 2 ? 0.3 : -0.3, i & 4 ? 0.3 : -0.3);
    const auto uv = project(cam, X * p_B);
    ASSERT_TRUE(uv.has_value());
    corners.emplace_back(static_cast<float>(uv->x()), static_cast<float>(uv->y()));
  }
  std::vector<cv::Point2f> hull;
  cv::convexHull(corners, hull);
  const double analytic = cv::contourArea(hull);
  const int rendered = count_ids(renderer.body_ids(), 0);
  ASSERT_GT(analytic, 20000);
  EXPECT_NEAR(rendered / analytic, 1.0, 0.01) << rendered << " px vs " << analytic << " px^2";
  // The box is closed, so the faces turned away from the camera (two triangles each) were culled.
  int hidden_faces = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (const double sgn : {-1.0, 1.0}) {
      const Eigen::Vector3d n_W = X.linear() * (sgn * Eigen::Vector3d::Unit(axis));
      const Eigen::Vector3d centre_W = X * (0.3 * sgn * Eigen::Vector3d::Unit(axis));
      hidden_faces += n_W.dot(centre_W - cam.position) > 0 ? 1 : 0;
    }
  EXPECT_EQ(renderer.closed_mesh_count(), 1u);
  EXPECT_EQ(renderer.stats().triangles_backfacing, 2u * hidden_faces);
}

TEST(Rasteriser, TessellatedQuadHasNoCracks) {
  // The same square as 2 triangles and as 242 irregular ones (interior vertices jittered
  // in the plane, diagonals alternating): every pixel at least one pixel inside the
  // square's image is covered in both (exact edge functions and the tie rule leave no
  // gaps along shared edges), and the areas agree to within the boundary pixels whose
  // centres lie within the 1/256 px snapping of the split boundary (~0.1%).
  const Camera cam = camera({1.3, -0.6, 1.4}, {0, 0, 0.6});
  const Eigen::Isometry3d X = pose({0, 0, 0.6}, rot(0.9, {1, 0.4, 0.2}));
  constexpr int n = 12;  // vertices per side
  SceneMesh fine;
  std::uint32_t seed = 12345;
  const auto jitter = [&] {
    seed = seed * 1664525u + 1013904223u;
    return (double(seed >> 8) / double(1 << 24) - 0.5) * 0.5;  // [-0.25, 0.25) of a cell
  };
  const double side = 0.6, cell = side / (n - 1);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const bool inner = i > 0 && j > 0 && i < n - 1 && j < n - 1;
      const double x = -0.5 * side + i * cell + (inner ? jitter() * cell : 0.0);
      const double y = -0.5 * side + j * cell + (inner ? jitter() * cell : 0.0);
      fine.vertices.emplace_back(static_cast<float>(x), static_cast<float>(y), 0.0f);
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
      if ((i + j) % 2 == 0) {
        fine.triangles.push_back({a, b, c});
        fine.triangles.push_back({a, c, d});
      } else {
        fine.triangles.push_back({a, b, d});
        fine.triangles.push_back({b, c, d});
      }
    }
  Renderer renderer(kW, kH);
  renderer.style().ground = false;
  renderer.set_scene(one_body(quad(side)));
  renderer.render({X}, cam);
  const cv::Mat coarse_mask = renderer.body_ids() == 0;
  renderer.set_scene(one_body(fine));
  renderer.render({X}, cam);
  const cv::Mat fine_mask = renderer.body_ids() == 0;
  cv::Mat interior;
  cv::erode(coarse_mask, interior, cv::Mat::ones(3, 3, CV_8U));
  const int n_interior = cv::countNonZero(interior);
  ASSERT_GT(n_interior, 20000);
  EXPECT_EQ(cv::countNonZero(interior & fine_mask), n_interior);
  const int coarse = cv::countNonZero(coarse_mask), fine_n = cv::countNonZero(fine_mask);
  EXPECT_NEAR(fine_n, coarse, 0.001 * coarse);
}

TEST(Rasteriser, CullingOnlyWhereSafeDoesNotChangeTheImage) {
  const Camera cam = camera({2, -1.5, 1.4}, {0, 0, 0.5});
  SceneMesh closed = box_mesh({0.5, 0.3, 0.4});
  SceneMesh two_sided = closed;
  two_sided.faces = SceneMesh::Faces::TwoSided;
  Renderer a(kW, kH), b(kW, kH);
  a.set_scene(one_body(closed));
  b.set_scene(one_body(two_sided));
  const Eigen::Isometry3d X = pose({0, 0, 0.5}, rot(0.3, {1, 2, 3}));
  const cv::Mat img_a = a.render({X}, cam).clone();
  const cv::Mat img_b = b.render({X}, cam).clone();
  EXPECT_EQ(a.closed_mesh_count(), 1u);
  EXPECT_EQ(b.closed_mesh_count(), 0u);
  EXPECT_GT(a.stats().triangles_backfacing, 0u);
  EXPECT_EQ(b.stats().triangles_backfacing, 0u);
  EXPECT_EQ(cv::norm(img_a, img_b, cv::NORM_INF), 0.0);

  // An open quad is not culled: it is seen from behind too.
  Renderer q(kW, kH);
  q.set_scene(one_body(quad(0.4)));
  EXPECT_EQ(q.closed_mesh_count(), 0u);
  q.render({pose({0, 0, 0.5}, rot(M_PI / 2, {0, 1, 0}))}, camera({2, 0, 0.5}, {0, 0, 0.5}));  // normal +x: front
  const int front = count_ids(q.body_ids(), 0);
  q.render({pose({0, 0, 0.5}, rot(-M_PI / 2, {0, 1, 0}))}, camera({2, 0, 0.5}, {0, 0, 0.5}));  // normal -x: back
  const int back = count_ids(q.body_ids(), 0);
  EXPECT_GT(front, 1000);
  EXPECT_EQ(front, back);
}

TEST(Rasteriser, TriangleCrossingTheNearPlaneIsClipped) {
  // Camera at the origin looking along +x (image right = -y, image down = -z).
  const Camera cam = camera({0, 0, 0}, {1, 0, 0});
  const double f = focal_length_px(cam);
  Renderer renderer(kW, kH);
  renderer.style().ground = false;
  SceneMesh tri;
  tri.vertices = {{1.0f, -0.3f, -0.2f}, {1.0f, 0.3f, -0.2f}, {-1.0f, 0.0f, 0.3f}};  // the last one behind the camera
  tri.triangles = {{0, 1, 2}};
  renderer.set_scene(one_body(tri));
  renderer.render({Eigen::Isometry3d::Identity()}, cam);
  const cv::Mat& iz = renderer.inverse_depth();
  double lo = 0, hi = 0;
  cv::minMaxLoc(iz, &lo, &hi);
  EXPECT_TRUE(cv::checkRange(iz));  // no NaN or inf
  EXPECT_GE(lo, 0.0);
  EXPECT_LE(hi, 1.0 / cam.near_m * 1.0001);
  EXPECT_EQ(renderer.stats().triangles_clipped, 1u);
  // Inside the visible part (x >= near): the point 40% of the way from the A-B midpoint
  // towards C is at x = 0.2, in front of the camera.
  const Eigen::Vector3d inside = Eigen::Vector3d(1.0, 0.0, -0.2) + 0.4 * Eigen::Vector3d(-2.0, 0.0, 0.5);
  const auto uv_in = project(cam, inside);
  ASSERT_TRUE(uv_in.has_value());
  EXPECT_EQ(renderer.body_ids().at<std::int16_t>(int(uv_in->y()), int(uv_in->x())), 0);
  // An unclipped rasteriser would divide by C's negative depth and fill the triangle
  // towards C's mirror image at (u, v) = (W/2, H/2 + 0.3 f); that region must stay empty.
  const int v_mirror = static_cast<int>(kH / 2 + 0.25 * f);
  ASSERT_LT(v_mirror, kH);
  EXPECT_EQ(renderer.body_ids().at<std::int16_t>(v_mirror, kW / 2), -1);
  EXPECT_GT(count_ids(renderer.body_ids(), 0), 5000);

  // A vertex exactly in the camera plane (z_C = 0) and one 1e6 m to the side (far
  // beyond the guard band): finite buffers, the triangle still drawn where expected.
  SceneMesh wild;
  wild.vertices = {{0.0f, 0.0f, -0.5f}, {2.0f, 1e6f, -0.5f}, {2.0f, 0.0f, 0.4f}};
  wild.triangles = {{0, 1, 2}, {0, 2, 1}};
  renderer.set_scene(one_body(wild));
  renderer.render({Eigen::Isometry3d::Identity()}, cam);
  EXPECT_TRUE(cv::checkRange(renderer.inverse_depth()));
  // Inside: P0 + 5e-8 (P1 - P0) + 0.9 (P2 - P0).
  const auto uv_w = project(cam, Eigen::Vector3d(1.8, 0.05, 0.31));
  ASSERT_TRUE(uv_w.has_value());
  EXPECT_EQ(renderer.body_ids().at<std::int16_t>(int(uv_w->y()), int(uv_w->x())), 0);
  const auto uv_out = project(cam, Eigen::Vector3d(2.0, -0.2, 0.0));  // beside it (y < 0)
  ASSERT_TRUE(uv_out.has_value());
  EXPECT_EQ(renderer.body_ids().at<std::int16_t>(int(uv_out->y()), int(uv_out->x())), -1);
}

// ---------------------------------------------------------------------------------
// Shading.

TEST(Shading, LambertWithAmbient) {
  // A grey quad facing the camera, lit at angle theta from its normal: the linear
  // radiance is albedo (ambient + diffuse cos(theta)), clamped at 0 past 90 deg. The
  // output is sRGB bytes; converting back with the standard sRGB curve is exact to half
  // an 8-bit step (up to 0.003 in linear at these levels), and the 12-bit linear table
  // before it can shift the rounding by one more step: 0.006.
  const Camera cam = camera({2, 0, 1}, {0, 0, 1});
  Renderer renderer(kW, kH);
  RenderStyle& st = renderer.style();
  st.ground = false;
  st.ambient_up = st.ambient_down = 0.2;
  st.diffuse = 0.7;
  st.fill = 0;
  st.specular = 0;
  renderer.set_scene(one_body(coloured(quad(0.5), 0.8f, 0.8f, 0.8f)));
  const Eigen::Isometry3d X = pose({0, 0, 1}, rot(M_PI / 2, {0, 1, 0}));  // normal +x, towards the camera
  const double albedo = srgb_to_linear(0.8 * 255.0);
  const Eigen::Vector2d centre = *project(cam, X.translation());
  double previous = 1e9;
  for (const double theta_deg : {0.0, 30.0, 60.0, 80.0, 89.0, 120.0}) {
    const double th = theta_deg * M_PI / 180.0;
    st.light_from_W = Eigen::Vector3d(std::cos(th), std::sin(th), 0.0);
    const cv::Vec3b px = pixel_at(renderer.render({X}, cam), centre);
    const double expected = albedo * (0.2 + 0.7 * std::max(0.0, std::cos(th)));
    EXPECT_NEAR(srgb_to_linear(px[1]), expected, 0.006) << theta_deg << " deg";
    EXPECT_LE(px[1], previous) << theta_deg << " deg";
    previous = px[1];
  }
}

TEST(Shading, FaceTowardsTheLightIsBrighterThanAGrazingFace) {
  // Default style (ambient, key, fill and specular): a box face whose normal is the
  // light direction against one at 85 deg from it, both seen by the camera.
  const Camera cam = camera({2.0, 2.0, 1.0}, {0, 0, 0.5});
  Renderer renderer(kW, kH);
  renderer.style().ground = false;
  const Eigen::Vector3d n_lit(1, 0, 0), n_graze(0, 1, 0);
  renderer.style().light_from_W = std::cos(5 * M_PI / 180) * n_lit + std::sin(5 * M_PI / 180) * n_graze;
  renderer.set_scene(one_body(coloured(box_mesh({0.4, 0.4, 0.4}), 0.6f, 0.6f, 0.6f)));
  const Eigen::Isometry3d X = pose({0, 0, 0.5});
  const cv::Mat& img = renderer.render({X}, cam);
  const cv::Vec3b lit = pixel_at(img, *project(cam, X * Eigen::Vector3d(0.2, 0, 0)));    // +x face centre
  const cv::Vec3b graze = pixel_at(img, *project(cam, X * Eigen::Vector3d(0, 0.2, 0)));  // +y face centre
  EXPECT_GT(int(lit[1]), int(graze[1]) + 50) << "lit " << lit << " grazing " << graze;
}

TEST(Shading, VertexNormalsAreInterpolated) {
  // A quad facing the camera with its vertex normals tilted 60 deg left on one side and
  // right on the other, the light from the left: brightness falls across it; the same
  // quad without normals (flat) is uniform.
  const Camera cam = camera({2, 0, 1}, {0, 0, 1});
  Renderer renderer(kW, kH);
  renderer.style().ground = false;
  renderer.style().specular = 0;
  // Image right is world +y here. The light comes from the camera side and 70 deg
  // towards -y, beyond the most tilted normal, so n.l falls monotonically across.
  renderer.style().light_from_W = Eigen::Vector3d(std::cos(1.2217), -std::sin(1.2217), 0);
  SceneMesh smooth = coloured(quad(0.5), 0.7f, 0.7f, 0.7f);
  const Eigen::Vector3f tilt_neg = Eigen::Vector3f(-std::sin(1.0472f), 0, std::cos(1.0472f));
  const Eigen::Vector3f tilt_pos = Eigen::Vector3f(std::sin(1.0472f), 0, std::cos(1.0472f));
  smooth.normals = {tilt_neg, tilt_pos, tilt_pos, tilt_neg};  // by body x: -h -> tilt_neg, +h -> tilt_pos
  // Rotate the quad so its normal is world +x (towards the camera) and its x axis world +y.
  Eigen::Matrix3d R;
  R.col(0) = Eigen::Vector3d(0, 1, 0);
  R.col(1) = Eigen::Vector3d(0, 0, 1);
  R.col(2) = Eigen::Vector3d(1, 0, 0);
  const Eigen::Isometry3d X = pose({0, 0, 1}, R);
  // Light from -y: the body -x side's normals (tilted to world -y) face it.
  const Eigen::Vector3d p_lit = X * Eigen::Vector3d(-0.2, 0, 0), p_dark = X * Eigen::Vector3d(0.2, 0, 0);
  renderer.set_scene(one_body(smooth));
  const cv::Mat img = renderer.render({X}, cam).clone();
  const int lit = pixel_at(img, *project(cam, p_lit))[1], dark = pixel_at(img, *project(cam, p_dark))[1];
  EXPECT_GT(lit, dark + 40);
  // Monotone along the row between them (interpolated, not two flat halves).
  const int r = static_cast<int>(project(cam, X.translation())->y());
  const int c0 = static_cast<int>(project(cam, p_lit)->x()), c1 = static_cast<int>(project(cam, p_dark)->x());
  const int step = c1 > c0 ? 1 : -1;
  int distinct = 0;
  for (int c = c0; c != c1; c += step) {
    const int a = img.at<cv::Vec3b>(r, c)[1], b = img.at<cv::Vec3b>(r, c + step)[1];
    EXPECT_GE(a, b - 1) << "column " << c;  // falls (1 level of rounding allowed)
    distinct += a != b ? 1 : 0;
  }
  EXPECT_GT(distinct, 20);
  SceneMesh flat = smooth;
  flat.normals.clear();
  renderer.set_scene(one_body(flat));
  const cv::Mat img_flat = renderer.render({X}, cam).clone();
  EXPECT_EQ(pixel_at(img_flat, *project(cam, p_lit)), pixel_at(img_flat, *project(cam, p_dark)));
}

// ---------------------------------------------------------------------------------
// Path overlays.

// Distance from the pixel centre (c + 0.5, r + 0.5) to the segment a-b, and where its
// nearest point lies along it (0 at a, 1 at b).
double pixel_to_segment(int c, int r, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double* s_out = nullptr) {
  const Eigen::Vector2d p(c + 0.5, r + 0.5), ab = b - a;
  const double s = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  if (s_out) *s_out = s;
  return (p - (a + s * ab)).norm();
}

// A box in the middle of the scene, so that paths cross geometry as well as the ground.
Scene box_scene() { return one_body(coloured(box_mesh({0.3, 0.3, 0.3}), 0.3f, 0.3f, 0.3f)); }
const Eigen::Isometry3d kBoxPose = pose({0, 0, 0.5});

// A path sampled densely (400 points: most are merged on screen) along the world line
// P0-P1 is drawn along project(P0)-project(P1) (a line projects to a line): every pixel
// whose centre is within 0.5 px of it, away from the ends, is exactly the path's colour
// (fully covered); every pixel more than 3 px from it is untouched (the colour's pen is
// 1 px + 0.5 px of anti-aliasing from the line, the halo's 2 px + 0.5 px). Where the
// line crosses the box, it is drawn over it.
TEST(PathOverlay, SolidPathDrawnWhereProjectedInItsColour) {
  const Camera cam = camera({2.5, 1.8, 1.4}, {0, 0, 0.5});
  Renderer renderer(kW, kH);
  renderer.set_scene(box_scene());
  const cv::Mat base = renderer.render({kBoxPose}, cam).clone();
  const Eigen::Vector3d P0(-0.6, 0.5, 0.3), P1(0.7, -0.4, 0.9);
  Overlays ov;
  PathOverlay path;
  path.color = {255, 0, 255};
  for (int i = 0; i < 400; ++i) path.points_W.push_back(P0 + (P1 - P0) * (i / 399.0));
  ov.paths.push_back(path);
  const cv::Mat img = renderer.render({kBoxPose}, cam, ov).clone();

  const Eigen::Vector2d a = *project(cam, P0), b = *project(cam, P1);
  ASSERT_GT((b - a).norm(), 200);  // long enough to mean something
  int on_line = 0, on_line_coloured = 0, far = 0, far_changed = 0, over_box = 0;
  for (int r = 0; r < kH; ++r)
    for (int c = 0; c < kW; ++c) {
      double s = 0;
      const double d = pixel_to_segment(c, r, a, b, &s);
      const cv::Vec3b px = img.at<cv::Vec3b>(r, c);
      if (d <= 0.5 && s > 0.01 && s < 0.99) {
        ++on_line;
        const bool coloured = px == cv::Vec3b(255, 0, 255);  // BGR
        on_line_coloured += coloured;
        over_box += coloured && renderer.body_ids().at<std::int16_t>(r, c) == 0;
      } else if (d > 3.0) {
        ++far;
        far_changed += px != base.at<cv::Vec3b>(r, c);
      }
    }
  EXPECT_GT(on_line, 200);
  EXPECT_EQ(on_line_coloured, on_line);
  EXPECT_GT(over_box, 10);  // the box is under part of the line and does not hide it
  EXPECT_GT(far, kW * kH / 2);
  EXPECT_EQ(far_changed, 0);
}

// Dashed: along the line, runs of the colour alternate with gaps (10 px on, 8 px off
// at the default 2 px width), the dashes running on across the merged vertices.
TEST(PathOverlay, DashedPathAlternatesAlongTheLine) {
  const Camera cam = camera({2.5, 1.8, 1.4}, {0, 0, 0.5});
  Renderer renderer(kW, kH);
  renderer.set_scene(Scene{});
  const Eigen::Vector3d P0(-0.6, 0.5, 0.3), P1(0.7, -0.4, 0.9);
  Overlays ov;
  PathOverlay path;
  path.color = {255, 0, 255};
  path.dashed = true;
  for (int i = 0; i < 400; ++i) path.points_W.push_back(P0 + (P1 - P0) * (i / 399.0));
  ov.paths.push_back(path);
  const cv::Mat& img = renderer.render({}, cam, ov);
  const Eigen::Vector2d a = *project(cam, P0), b = *project(cam, P1);
  // Walk the line pixel by pixel: coloured or not, and count the changes.
  const double len = (b - a).norm();
  int coloured = 0, samples = 0, changes = 0;
  bool prev = false;
  for (double t = 2; t < len - 2; t += 1.0) {
    const Eigen::Vector2d p = a + (b - a) * (t / len);
    const bool c = pixel_at(img, p) == cv::Vec3b(255, 0, 255);
    if (samples > 0 && c != prev) ++changes;
    prev = c;
    coloured += c;
    ++samples;
  }
  const double on_fraction = double(coloured) / samples;
  EXPECT_GT(on_fraction, 0.4);
  EXPECT_LT(on_fraction, 0.7);
  // About two changes per 18 px period.
  EXPECT_GT(changes, 0.7 * 2 * len / 18);
  EXPECT_LT(changes, 1.5 * 2 * len / 18);
}

// Points behind the camera are left out: a path from in front of the camera to behind
// it is drawn up to the near plane (its visible end is coloured, nothing throws); one
// wholly behind the camera, one with a single point and an empty one draw nothing.
// An empty list of paths changes nothing: the image is pixel-identical to the 3-D pass
// alone (and so is one whose paths are all invisible and unlabelled).
TEST(PathOverlay, BehindTheCameraAndEmptyPathsDrawNothing) {
  const Camera cam = camera({2.5, 1.8, 1.4}, {0, 0, 0.5});
  Renderer renderer(kW, kH);
  renderer.set_scene(box_scene());
  const cv::Mat base = renderer.render({kBoxPose}, cam).clone();
  Overlays none;
  none.paths.clear();
  EXPECT_EQ(cv::norm(renderer.render({kBoxPose}, cam, none), base, cv::NORM_INF), 0.0);

  const Eigen::Vector3d fwd = (cam.look_at - cam.position).normalized();
  Overlays invisible;
  PathOverlay behind;
  behind.color = {255, 0, 255};
  for (int i = 0; i < 50; ++i)
    behind.points_W.push_back(cam.position - (0.5 + 0.02 * i) * fwd + Eigen::Vector3d(0.01 * i, 0, 0));
  invisible.paths.push_back(behind);
  PathOverlay single;
  single.points_W = {Eigen::Vector3d(0, 0, 1)};
  invisible.paths.push_back(single);
  invisible.paths.push_back(PathOverlay{});
  EXPECT_EQ(cv::norm(renderer.render({kBoxPose}, cam, invisible), base, cv::NORM_INF), 0.0);

  Overlays crossing;
  PathOverlay through;
  through.color = {255, 0, 255};
  const Eigen::Vector3d front(0.2, -0.3, 0.9), back = cam.position - 1.0 * fwd;
  for (int i = 0; i <= 100; ++i) through.points_W.push_back(front + (back - front) * (i / 100.0));
  crossing.paths.push_back(through);
  cv::Mat img;
  ASSERT_NO_THROW(img = renderer.render({kBoxPose}, cam, crossing).clone());
  const Eigen::Vector2d uv = *project(cam, front + 0.01 * (back - front));
  bool found = false;
  for (int dr = -1; dr <= 1; ++dr)
    for (int dc = -1; dc <= 1; ++dc)
      found = found || img.at<cv::Vec3b>(int(uv.y()) + dr, int(uv.x()) + dc) == cv::Vec3b(255, 0, 255);
  EXPECT_TRUE(found);
}

// A labelled path gets a legend entry in the top-right corner: a sample of its line in
// its colour and the label in white on a darkened panel; an unlabelled one does not.
TEST(PathOverlay, LabelGoesIntoTheLegend) {
  const Camera cam = camera({2.5, 1.8, 1.4}, {0, 0, 0.5});
  Renderer renderer(kW, kH);
  renderer.set_scene(Scene{});
  const cv::Mat base = renderer.render({}, cam).clone();
  PathOverlay path;
  path.color = {255, 0, 255};
  path.points_W = {Eigen::Vector3d(-0.3, 0, 0.2), Eigen::Vector3d(0.3, 0, 0.2)};  // far from the corner
  const cv::Rect corner(kW / 2, 0, kW / 2, kH / 4);
  Overlays unlabelled;
  unlabelled.paths.push_back(path);
  EXPECT_EQ(cv::norm(renderer.render({}, cam, unlabelled)(corner), base(corner), cv::NORM_INF), 0.0);

  Overlays labelled;
  path.label = "measured";
  labelled.paths.push_back(path);
  const cv::Mat img = renderer.render({}, cam, labelled).clone();
  // The panel: the pixels that changed, in the corner only, darker than they were.
  cv::Mat diff;
  cv::absdiff(img(corner), base(corner), diff);
  cv::cvtColor(diff, diff, cv::COLOR_BGR2GRAY);
  const cv::Rect panel = cv::boundingRect(diff > 0) + corner.tl();
  EXPECT_GT(panel.x + panel.width, kW - 20);  // at the right edge, a small margin off it
  EXPECT_LT(panel.y, 20);
  EXPECT_GT(panel.width, 60);
  EXPECT_GT(panel.height, 10);
  cv::Mat grey, grey_base;
  cv::cvtColor(img(panel), grey, cv::COLOR_BGR2GRAY);
  cv::cvtColor(base(panel), grey_base, cv::COLOR_BGR2GRAY);
  EXPECT_LT(cv::mean(grey)[0], 0.6 * cv::mean(grey_base)[0]);
  EXPECT_GT(cv::countNonZero(grey > 200), 30);  // the label's strokes
  int sample = 0;
  for (int r = panel.y; r < panel.y + panel.height; ++r)
    for (int c = panel.x; c < panel.x + panel.width; ++c) sample += img.at<cv::Vec3b>(r, c) == cv::Vec3b(255, 0, 255);
  EXPECT_GT(sample, 20);  // a 2 px wide line at least 24 px long
}

// A marker: its colour on the ring (a point ring_m from its centre in the horizontal
// plane) and at its centre (the cross), nothing far from it; a labelled one gets a legend
// entry in the top-right corner in its colour; one at a non-finite point draws nothing.
TEST(MarkerOverlay, RingAndCrossWhereProjectedAndALegendEntry) {
  const Camera cam = camera({2.5, 1.8, 1.4}, {0, 0, 0.5});
  Renderer renderer(kW, kH);
  renderer.set_scene(Scene{});
  const cv::Mat base = renderer.render({}, cam).clone();
  MarkerOverlay m;
  m.p_W = Eigen::Vector3d(0.1, -0.2, 0.0);
  m.color = {255, 0, 255};
  m.ring_m = 0.1;
  Overlays o;
  o.markers.push_back(m);
  const cv::Mat img = renderer.render({}, cam, o).clone();
  auto coloured_near = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector2d uv = *project(cam, p);
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc)
        if (img.at<cv::Vec3b>(int(uv.y()) + dr, int(uv.x()) + dc) == cv::Vec3b(255, 0, 255)) return true;
    return false;
  };
  EXPECT_TRUE(coloured_near(m.p_W));                                    // the cross
  EXPECT_TRUE(coloured_near(m.p_W + Eigen::Vector3d(0.1, 0, 0)));        // the ring
  EXPECT_TRUE(coloured_near(m.p_W + Eigen::Vector3d(0, 0.1, 0)));
  EXPECT_FALSE(coloured_near(m.p_W + Eigen::Vector3d(0.3, 0.3, 0)));     // not far from it
  const cv::Rect corner(kW / 2, 0, kW / 2, kH / 4);
  EXPECT_EQ(cv::norm(img(corner), base(corner), cv::NORM_INF), 0.0);  // unlabelled: no legend
  o.markers[0].label = "planned foothold";
  const cv::Mat labelled = renderer.render({}, cam, o).clone();
  int legend = 0;
  for (int r = corner.y; r < corner.y + corner.height; ++r)
    for (int c = corner.x; c < corner.x + corner.width; ++c) legend += labelled.at<cv::Vec3b>(r, c) == cv::Vec3b(255, 0, 255);
  EXPECT_GT(legend, 5);
  o.markers[0].p_W = Eigen::Vector3d(NAN, 0, 0);
  o.markers[0].label.clear();
  EXPECT_EQ(cv::norm(renderer.render({}, cam, o), base, cv::NORM_INF), 0.0);
}

// ---------------------------------------------------------------------------------
// Ground and background.

TEST(Ground, GridLinesWhereProjected) {
  const Camera cam = camera({-1.5, -1.2, 1.6}, {0.8, 0.6, 0});
  Renderer renderer(kW, kH);
  renderer.set_scene(Scene{});
  const cv::Mat& img = renderer.render({}, cam);
  const RenderStyle& st = renderer.style();
  // Darkest green level in the 3x3 pixels around a projected point (a line passes
  // within half a pixel of one of their centres).
  const auto darkest = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector2d uv = *project(cam, p);
    int m = 255;
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc) m = std::min<int>(m, img.at<cv::Vec3b>(int(uv.y()) + dr, int(uv.x()) + dc)[1]);
    return m;
  };
  const int ground = st.ground_color.g;
  // Between lines: the plain ground colour (no shadow, well before the fade at 6 m).
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(0.45, 0.25, 0), Eigen::Vector3d(1.05, 0.75, 0), Eigen::Vector3d(0.65, 1.15, 0)})
    EXPECT_NEAR(pixel_at(img, *project(cam, p))[1], ground, 2) << p.transpose();
  // Minor lines (every 0.1 m): at least half covered, so at least half as dark as the line colour.
  const int minor_drop = (ground - st.grid_minor_color.g) / 2;
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(0.3, 0.25, 0), Eigen::Vector3d(0.45, 0.4, 0), Eigen::Vector3d(0.7, 0.85, 0)})
    EXPECT_LE(darkest(p), ground - minor_drop) << p.transpose();
  // Major lines (every 1 m): darker still.
  const int major_drop = (ground - st.grid_major_color.g) * 3 / 4;
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(1.0, 0.25, 0), Eigen::Vector3d(1.0, 0.75, 0), Eigen::Vector3d(0.45, 1.0, 0)})
    EXPECT_LE(darkest(p), ground - major_drop) << p.transpose();
  // The world x axis (y = 0) is red.
  const Eigen::Vector2d ax = *project(cam, Eigen::Vector3d(0.55, 0, 0));
  int redness = -255;
  for (int dr = -1; dr <= 1; ++dr) {
    const cv::Vec3b px = img.at<cv::Vec3b>(int(ax.y()) + dr, int(ax.x()));
    redness = std::max(redness, int(px[2]) - int(px[1]));
  }
  EXPECT_GT(redness, 60);
  // Turning the grid off leaves plain ground there.
  renderer.style().grid = false;
  renderer.style().axes = false;
  const cv::Mat& plain = renderer.render({}, cam);
  EXPECT_NEAR(pixel_at(plain, *project(cam, Eigen::Vector3d(1.0, 0.25, 0)))[1], ground, 2);
}

TEST(Ground, SkyAboveTheHorizonGroundBelow) {
  // A level camera 1 m up: the horizon is the middle row. Sky above (blue over red, no
  // depth), ground below (depth 1/z of the ground point, no body).
  const Camera cam = camera({0, 0, 1}, {5, 0, 1});
  Renderer renderer(kW, kH);
  renderer.set_scene(Scene{});
  const cv::Mat& img = renderer.render({}, cam);
  const cv::Vec3b sky = img.at<cv::Vec3b>(10, kW / 2);
  EXPECT_GT(sky[0], sky[2] + 30);
  EXPECT_EQ(renderer.inverse_depth().at<float>(10, kW / 2), 0.0f);
  // Row r below the horizon sees the ground at camera depth z = f h / (r + 0.5 - H/2).
  const double f = focal_length_px(cam);
  for (const int r : {kH / 2 + 20, kH / 2 + 90, kH - 1})
    EXPECT_NEAR(renderer.inverse_depth().at<float>(r, kW / 2), (r + 0.5 - kH / 2.0) / f, 1e-5) << r;
  EXPECT_EQ(count_ids(renderer.body_ids(), -1), kW * kH);
}

TEST(Ground, ShadowFallsAwayFromTheLight) {
  const Camera cam = camera({0.0, -3.0, 2.5}, {0, 0, 0.3});
  Renderer renderer(kW, kH);
  renderer.style().light_from_W = Eigen::Vector3d(1, 0, 1);  // 45 deg from +x: shadow towards -x
  renderer.style().grid = false;
  renderer.style().axes = false;
  renderer.set_scene(one_body(box_mesh({0.2, 0.2, 0.2})));
  const cv::Mat& img = renderer.render({pose({0, 0, 0.5})}, cam);
  // The box at height 0.4..0.6 m casts its shadow onto x in [-0.7, -0.3].
  const int in_shadow = pixel_at(img, *project(cam, Eigen::Vector3d(-0.5, 0, 0)))[1];
  const int lit = pixel_at(img, *project(cam, Eigen::Vector3d(0.5, 0, 0)))[1];
  EXPECT_LT(in_shadow, lit - 40);
  EXPECT_NEAR(lit, renderer.style().ground_color.g, 2);
}

// ---------------------------------------------------------------------------------
// Threads.

// A scene with every kind of mesh: closed boxes (flat normals, culled), a smooth sphere
// and cylinder, an open two-sided quad without normals (flat shading) and a quad just
// above the ground that the near plane of one camera cuts.
Scene threads_scene() {
  Scene s;
  s.bodies.push_back({"base", {coloured(box_mesh({0.4, 0.3, 0.5}), 0.6f, 0.3f, 0.2f),
                               coloured(sphere_mesh(0.18, 20), 0.2f, 0.5f, 0.8f)}});
  s.bodies.push_back({"arm", {coloured(cylinder_mesh(0.05, 0.8, 16), 0.8f, 0.8f, 0.3f)}});
  SceneMesh open = coloured(quad(0.6), 0.4f, 0.7f, 0.4f);
  open.faces = SceneMesh::Faces::TwoSided;
  s.bodies.push_back({"panel", {open}});
  s.bodies.push_back({"slab", {coloured(quad(1.2), 0.5f, 0.5f, 0.55f)}});
  return s;
}

struct ThreadsFrame {
  std::vector<Eigen::Isometry3d> X;
  Camera cam;
};

// Moving cameras (each pixel drawn), one camera three times in a row (the kept
// background: drawn and kept, then copied with the shadow drawn again), a camera whose
// near plane cuts the slab and the base, one below the ground, one looking straight down.
std::vector<ThreadsFrame> threads_frames(int w, int h) {
  std::vector<ThreadsFrame> frames;
  for (int k = 0; k < 9; ++k) {
    const double a = 0.3 * k;
    ThreadsFrame f;
    f.X = {pose({0.1 * k, 0, 0.4}, rot(a, {0, 0, 1})), pose({0, 0.3, 0.6}, rot(0.5 + a, {1, 0.2, 0})),
           pose({-0.5, -0.4, 0.5}, rot(1.2, {1, 0, 0}) * rot(a, {0, 0, 1})), pose({0.2, 0, 0.002})};
    const bool fixed = k >= 2 && k <= 4;
    f.cam = camera({2.5 * std::cos(fixed ? 0.0 : a), -2.5 * std::sin(fixed ? 0.0 : a), 1.4}, {0, 0, 0.4}, w, h);
    if (k == 6) {
      f.cam = camera({0.15, 0.05, 0.45}, {-1, 0.3, 0.1}, w, h);
      f.cam.near_m = 0.2;
    } else if (k == 7) {
      f.cam = camera({2, 1, -0.5}, {0, 0, 0.3}, w, h);
    } else if (k == 8) {
      f.cam = camera({0.3, 0.2, 4}, {0, 0, 0}, w, h);
      f.cam.up = Eigen::Vector3d::UnitX();
    }
    frames.push_back(f);
  }
  return frames;
}

bool same_bytes(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != b.type()) return false;
  for (int r = 0; r < a.rows; ++r)
    if (std::memcmp(a.ptr(r), b.ptr(r), a.cols * a.elemSize()) != 0) return false;
  return true;
}

TEST(Threads, SameBytesForAnyThreadCount) {
  // Sizes not a multiple of the bands' chunks; overlays too (drawn by one thread).
  Overlays ov;
  ov.text_lines = {"threads"};
  ov.com_W = Eigen::Vector3d(0, 0, 0.5);
  ov.forces.push_back({Eigen::Vector3d(0.2, 0, 0), Eigen::Vector3d(0, 0, 300), {230, 50, 40}});
  for (const auto& [w, h] : {std::pair{kW, kH}, std::pair{333, 211}}) {
    const std::vector<ThreadsFrame> frames = threads_frames(w, h);
    Renderer one(w, h, 1);
    one.set_scene(threads_scene());
    ASSERT_EQ(one.thread_count(), 1);
    std::vector<Renderer> many;
    for (const int n : {2, 3, 5}) {
      many.emplace_back(w, h, n);
      many.back().set_scene(threads_scene());
      ASSERT_EQ(many.back().thread_count(), n);
    }
    std::size_t clipped = 0;
    for (std::size_t k = 0; k < frames.size(); ++k) {
      one.render(frames[k].X, frames[k].cam, ov);
      clipped += one.stats().triangles_clipped;
      for (Renderer& r : many) {
        r.render(frames[k].X, frames[k].cam, ov);
        const std::string what = std::to_string(r.thread_count()) + " threads, " + std::to_string(w) + "x" +
                                 std::to_string(h) + ", frame " + std::to_string(k);
        EXPECT_TRUE(same_bytes(r.image(), one.image())) << what;
        EXPECT_TRUE(same_bytes(r.inverse_depth(), one.inverse_depth())) << what;
        EXPECT_TRUE(same_bytes(r.body_ids(), one.body_ids())) << what;
        EXPECT_EQ(r.stats().triangles_rasterised, one.stats().triangles_rasterised) << what;
        EXPECT_EQ(r.stats().triangles_clipped, one.stats().triangles_clipped) << what;
      }
    }
    EXPECT_GT(clipped, 0u);  // the frames do exercise clipping
  }
}

TEST(Threads, DefaultCountMovesAndInvalidCounts) {
  const Renderer dflt(kW, kH);
  EXPECT_GE(dflt.thread_count(), 1);
  EXPECT_LE(dflt.thread_count(), 2);
  EXPECT_THROW(Renderer(kW, kH, -1), std::invalid_argument);
  EXPECT_THROW(Renderer(kW, kH, 65), std::invalid_argument);
  // A moved renderer keeps its helper threads and draws as before.
  const std::vector<ThreadsFrame> frames = threads_frames(kW, kH);
  Renderer a(kW, kH, 2);
  a.set_scene(threads_scene());
  const cv::Mat first = a.render(frames[0].X, frames[0].cam).clone();
  Renderer b(std::move(a));
  EXPECT_TRUE(same_bytes(b.render(frames[0].X, frames[0].cam), first));
  Renderer c(kW, kH, 3);
  c = std::move(b);
  EXPECT_EQ(c.thread_count(), 2);
  EXPECT_TRUE(same_bytes(c.render(frames[0].X, frames[0].cam), first));
}

}  // namespace
}  // namespace dmbd::viz
