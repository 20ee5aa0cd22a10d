// Primitive tessellation (box, cylinder, sphere), mesh transforms and the default 3/4
// camera for a robot.
#include "dmbd/viz/primitives.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace dmbd::viz {

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("viz::" + what);
}

// Appends a quad (a, b, c, d counter-clockwise seen from outside) with one normal.
void add_quad(SceneMesh& m, const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
              const Eigen::Vector3f& d, const Eigen::Vector3f& n) {
  const int i = static_cast<int>(m.vertices.size());
  for (const auto* v : {&a, &b, &c, &d}) {
    m.vertices.push_back(*v);
    m.normals.push_back(n);
  }
  m.triangles.push_back({i, i + 1, i + 2});
  m.triangles.push_back({i, i + 2, i + 3});
}

}  // namespace

SceneMesh transformed(SceneMesh m, const Eigen::Isometry3d& X) {
  const Eigen::Matrix3f R = X.linear().cast<float>();
  const Eigen::Vector3f p = X.translation().cast<float>();
  for (auto& v : m.vertices) v = R * v + p;
  for (auto& n : m.normals) n = R * n;
  return m;
}


SceneMesh box_mesh(const Eigen::Vector3d& size_m) {
  require(size_m.allFinite() && (size_m.array() > 0).all(), "box_mesh: sizes must be finite and > 0");
  const Eigen::Vector3f h = (0.5 * size_m).cast<float>();
  const auto P = [&](int sx, int sy, int sz) { return Eigen::Vector3f(sx * h.x(), sy * h.y(), sz * h.z()); };
  SceneMesh m;
  add_quad(m, P(1, -1, -1), P(1, 1, -1), P(1, 1, 1), P(1, -1, 1), Eigen::Vector3f::UnitX());
  add_quad(m, P(-1, 1, -1), P(-1, -1, -1), P(-1, -1, 1), P(-1, 1, 1), -Eigen::Vector3f::UnitX());
  add_quad(m, P(1, 1, -1), P(-1, 1, -1), P(-1, 1, 1), P(1, 1, 1), Eigen::Vector3f::UnitY());
  add_quad(m, P(-1, -1, -1), P(1, -1, -1), P(1, -1, 1), P(-1, -1, 1), -Eigen::Vector3f::UnitY());
  add_quad(m, P(-1, -1, 1), P(1, -1, 1), P(1, 1, 1), P(-1, 1, 1), Eigen::Vector3f::UnitZ());
  add_quad(m, P(-1, 1, -1), P(1, 1, -1), P(1, -1, -1), P(-1, -1, -1), -Eigen::Vector3f::UnitZ());
  return m;
}

SceneMesh cylinder_mesh(double radius_m, double length_m, int segments) {
  require(std::isfinite(radius_m) && radius_m > 0 && std::isfinite(length_m) && length_m > 0,
          "cylinder_mesh: radius and length must be finite and > 0");
  require(segments >= 3, "cylinder_mesh: at least 3 segments");
  const float r = static_cast<float>(radius_m), hz = static_cast<float>(0.5 * length_m);
  std::vector<Eigen::Vector2f> ring(segments);
  for (int i = 0; i < segments; ++i) {
    const double t = 2 * M_PI * i / segments;
    ring[i] = Eigen::Vector2f(static_cast<float>(std::cos(t)), static_cast<float>(std::sin(t)));
  }
  SceneMesh m;
  // Side: bottom and top rings with radial normals.
  for (int i = 0; i < segments; ++i) {
    const Eigen::Vector3f n(ring[i].x(), ring[i].y(), 0);
    m.vertices.emplace_back(r * ring[i].x(), r * ring[i].y(), -hz);
    m.normals.push_back(n);
    m.vertices.emplace_back(r * ring[i].x(), r * ring[i].y(), hz);
    m.normals.push_back(n);
  }
  for (int i = 0; i < segments; ++i) {
    const int j = (i + 1) % segments;
    const int b0 = 2 * i, t0 = 2 * i + 1, b1 = 2 * j, t1 = 2 * j + 1;
    m.triangles.push_back({b0, b1, t1});
    m.triangles.push_back({b0, t1, t0});
  }
  // Caps: centre fans with axial normals.
  for (int side = -1; side <= 1; side += 2) {
    const int c = static_cast<int>(m.vertices.size());
    const Eigen::Vector3f n(0, 0, float(side));
    m.vertices.emplace_back(0, 0, side * hz);
    m.normals.push_back(n);
    for (int i = 0; i < segments; ++i) {
      m.vertices.emplace_back(r * ring[i].x(), r * ring[i].y(), side * hz);
      m.normals.push_back(n);
    }
    for (int i = 0; i < segments; ++i) {
      const int a = c + 1 + i, b = c + 1 + (i + 1) % segments;
      if (side > 0)
        m.triangles.push_back({c, a, b});
      else
        m.triangles.push_back({c, b, a});
    }
  }
  return m;
}

SceneMesh sphere_mesh(double radius_m, int segments) {
  require(std::isfinite(radius_m) && radius_m > 0, "sphere_mesh: radius must be finite and > 0");
  require(segments >= 4, "sphere_mesh: at least 4 segments");
  const int n_lat = segments / 2, n_lon = segments;
  const float r = static_cast<float>(radius_m);
  SceneMesh m;
  // Poles are single vertices; rings in between share their seam vertex (index modulo).
  m.vertices.emplace_back(0, 0, r);
  m.normals.emplace_back(0, 0, 1);
  for (int i = 1; i < n_lat; ++i) {
    const double th = M_PI * i / n_lat;
    for (int j = 0; j < n_lon; ++j) {
      const double ph = 2 * M_PI * j / n_lon;
      const Eigen::Vector3f n(static_cast<float>(std::sin(th) * std::cos(ph)),
                              static_cast<float>(std::sin(th) * std::sin(ph)), static_cast<float>(std::cos(th)));
      m.vertices.push_back(r * n);
      m.normals.push_back(n);
    }
  }
  const int south = static_cast<int>(m.vertices.size());
  m.vertices.emplace_back(0, 0, -r);
  m.normals.emplace_back(0, 0, -1);
  const auto at = [&](int ring, int j) { return 1 + (ring - 1) * n_lon + (j % n_lon); };
  for (int j = 0; j < n_lon; ++j) m.triangles.push_back({0, at(1, j), at(1, j + 1)});
  for (int i = 1; i + 1 < n_lat; ++i)
    for (int j = 0; j < n_lon; ++j) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  for (int j = 0; j < n_lon; ++j) m.triangles.push_back({south, at(n_lat - 1, j + 1), at(n_lat - 1, j)});
  return m;
}

Camera default_robot_camera(double robot_height_m, int width_px, int height_px, const Eigen::Vector3d& ground_point_W) {
  require(std::isfinite(robot_height_m) && robot_height_m > 0, "default_robot_camera: height must be finite and > 0");
  Camera cam;
  cam.width_px = width_px;
  cam.height_px = height_px;
  cam.fov_y_deg = 40;
  const double az = 35.0 * M_PI / 180.0, el = 12.0 * M_PI / 180.0;
  const double fov = cam.fov_y_deg * M_PI / 180.0;
  // The visible height at distance D is 2 D tan(fov/2); the robot fills 75% of it.
  const double dist = robot_height_m / (0.75 * 2.0 * std::tan(0.5 * fov));
  cam.look_at = ground_point_W + Eigen::Vector3d(0, 0, 0.5 * robot_height_m);
  cam.position =
      cam.look_at + dist * Eigen::Vector3d(std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), std::sin(el));
  cam.up = Eigen::Vector3d::UnitZ();
  return cam;
}

}  // namespace dmbd::viz
