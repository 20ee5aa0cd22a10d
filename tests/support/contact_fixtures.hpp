#pragma once
// Robots for the contact tests, written as URDF text: one floating body with one
// collision shape, and a hopper (torso, thigh, shank, foot); mesh files (OBJ) written
// into a temporary folder. Closed-form inertias of boxes and cylinders.
#include "dmbd/model/robot_description.hpp"

#include <Eigen/Core>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

namespace dmbd::model::testing {

inline std::string num(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

inline std::string inertial(double m, const Eigen::Vector3d& I, const Eigen::Vector3d& com = Eigen::Vector3d::Zero()) {
  return "<inertial><origin xyz=\"" + num(com.x()) + " " + num(com.y()) + " " + num(com.z()) + "\"/><mass value=\"" + num(m) +
         "\"/><inertia ixx=\"" + num(I.x()) + "\" ixy=\"0\" ixz=\"0\" iyy=\"" + num(I.y()) + "\" iyz=\"0\" izz=\"" + num(I.z()) +
         "\"/></inertial>";
}

// Principal moments of a uniform box (full edge lengths) and a uniform cylinder (axis z).
inline Eigen::Vector3d box_inertia(double m, const Eigen::Vector3d& s) {
  return m / 12 * Eigen::Vector3d(s.y() * s.y() + s.z() * s.z(), s.x() * s.x() + s.z() * s.z(), s.x() * s.x() + s.y() * s.y());
}
inline Eigen::Vector3d cylinder_inertia(double m, double R, double L) {
  const double t = m * (3 * R * R + L * L) / 12;
  return {t, t, m * R * R / 2};
}

inline std::string box_xml(const Eigen::Vector3d& s) {
  return "<box size=\"" + num(s.x()) + " " + num(s.y()) + " " + num(s.z()) + "\"/>";
}
inline std::string cylinder_xml(double R, double L) {
  return "<cylinder radius=\"" + num(R) + "\" length=\"" + num(L) + "\"/>";
}

// A fresh temporary folder for mesh files, removed with it.
struct TempDir {
  std::string path;
  explicit TempDir(const std::string& tag)
      : path((std::filesystem::temp_directory_path() / ("dmbd_" + tag + "_" + std::to_string(::getpid()))).string()) {
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
};

inline void write_obj(const std::string& path, const std::vector<Eigen::Vector3d>& v, const std::vector<Eigen::Vector3i>& f) {
  std::ofstream out(path);
  for (const Eigen::Vector3d& p : v) out << "v " << num(p.x()) << " " << num(p.y()) << " " << num(p.z()) << "\n";
  for (const Eigen::Vector3i& t : f) out << "f " << t.x() + 1 << " " << t.y() + 1 << " " << t.z() + 1 << "\n";
}

// A box mesh of edge lengths s centred at the origin, each face split into four
// triangles around its centre (14 vertices, of which the 8 corners are the hull's).
inline void write_box_obj(const std::string& path, const Eigen::Vector3d& s) {
  std::vector<Eigen::Vector3d> v;
  std::vector<Eigen::Vector3i> f;
  for (int k = 0; k < 8; ++k) v.emplace_back(0.5 * Eigen::Vector3d(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1).cwiseProduct(s));
  // Faces as corner quadruples in order around the face.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    const int c = static_cast<int>(v.size());
    v.push_back(0.25 * (v[q[0]] + v[q[1]] + v[q[2]] + v[q[3]]));
    for (int e = 0; e < 4; ++e) f.emplace_back(c, q[e], q[(e + 1) % 4]);
  }
  write_obj(path, v, f);
}

// A UV sphere of radius R: `rings` latitudes between the poles, `segments` longitudes.
inline void write_sphere_obj(const std::string& path, double R, int rings, int segments) {
  const double pi = 3.14159265358979323846;
  std::vector<Eigen::Vector3d> v{{0, 0, R}, {0, 0, -R}};
  std::vector<Eigen::Vector3i> f;
  for (int i = 1; i <= rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double th = pi * i / (rings + 1), ph = 2 * pi * j / segments;
      v.emplace_back(R * std::sin(th) * std::cos(ph), R * std::sin(th) * std::sin(ph), R * std::cos(th));
    }
  auto at = [&](int i, int j) { return 2 + (i - 1) * segments + (j % segments); };
  for (int j = 0; j < segments; ++j) {
    f.emplace_back(0, at(1, j), at(1, j + 1));
    f.emplace_back(1, at(rings, j + 1), at(rings, j));
    for (int i = 1; i < rings; ++i) {
      f.emplace_back(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      f.emplace_back(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  }
  write_obj(path, v, f);
}

// One floating link 'body' of mass m and principal moments I whose one collision is
// `geometry` (URDF text) at `origin` (URDF attributes, e.g. rpy="..."); mesh paths
// relative to `dir`.
inline RobotDescription single_body(const std::string& geometry, double m, const Eigen::Vector3d& I,
                                    const std::string& dir = ".", const std::string& origin = "") {
  const std::string xml = "<?xml version=\"1.0\"?>\n<robot name=\"body\">\n<link name=\"body\">\n" + inertial(m, I) +
                          "\n<collision><origin " + origin + "/>\n<geometry>" + geometry + "</geometry>\n</collision>\n</link>\n</robot>\n";
  return parse_urdf(xml, dir, dir + "/body.urdf");
}

// The hopper: torso box 0.2 x 0.2 x 0.3 m (6 kg), thigh and shank 0.3 m (1.5 and 1 kg,
// cylinder collisions of radius 3 and 2.5 cm), foot (0.5 kg) whose collision is
// `foot` (URDF geometry text) 3 cm below the ankle; hip, knee and ankle pitch about y.
// Standing straight, the torso's origin is 0.81 m above the bottom of a 6 cm-high foot.
inline std::string hopper_urdf(const std::string& foot) {
  auto joint = [](const char* name, const char* parent, const char* child, double z) {
    return std::string("<joint name=\"") + name + "\" type=\"revolute\"><parent link=\"" + parent + "\"/><child link=\"" + child +
           "\"/><origin xyz=\"0 0 " + num(z) + "\"/><axis xyz=\"0 1 0\"/><limit lower=\"-2\" upper=\"2\" effort=\"200\" velocity=\"20\"/></joint>\n";
  };
  auto cyl = [](double R, double L) {
    return "<collision><origin xyz=\"0 0 " + num(-L / 2) + "\"/><geometry>" + cylinder_xml(R, L) + "</geometry></collision>";
  };
  const std::string xml =
      "<?xml version=\"1.0\"?>\n<robot name=\"hopper\">\n"
      "<link name=\"torso\">" + inertial(6.0, box_inertia(6.0, {0.2, 0.2, 0.3})) +
      "<collision><geometry>" + box_xml({0.2, 0.2, 0.3}) + "</geometry></collision></link>\n" +
      joint("hip", "torso", "thigh", -0.15) +
      "<link name=\"thigh\">" + inertial(1.5, cylinder_inertia(1.5, 0.03, 0.3), {0, 0, -0.15}) + cyl(0.03, 0.3) + "</link>\n" +
      joint("knee", "thigh", "shank", -0.3) +
      "<link name=\"shank\">" + inertial(1.0, cylinder_inertia(1.0, 0.025, 0.3), {0, 0, -0.15}) + cyl(0.025, 0.3) + "</link>\n" +
      joint("ankle", "shank", "foot", -0.3) +
      "<link name=\"foot\">" + inertial(0.5, box_inertia(0.5, {0.24, 0.12, 0.06}), {0, 0, -0.03}) +
      "<collision><origin xyz=\"0 0 -0.03\"/><geometry>" + foot + "</geometry></collision></link>\n</robot>\n";
  return xml;
}
inline RobotDescription hopper(const std::string& foot, const std::string& dir = ".") {
  return parse_urdf(hopper_urdf(foot), dir, dir + "/hopper.urdf");
}

}  // namespace dmbd::model::testing
