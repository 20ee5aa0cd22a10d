// A replay's data files: a scene's meshes and a track of poses as JavaScript that
// assigns JSON with base64 float32 arrays (replay.hpp gives the layout).
#include "dmbd/viz/replay.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "base64.hpp"

namespace dmbd::viz {

using nlohmann::json;
using detail::base64_float32;

namespace {

// The statement that files `value` under `key` in the page's global dmbdReplay.
std::string assignment(const char* table, const std::string& key, const json& value) {
  return fmt::format("(window.dmbdReplay = window.dmbdReplay || {{scenes: {{}}, tracks: {{}}}}).{}[{}] = {};\n", table,
                     json(key).dump(), value.dump());
}

json rgb(const Color& c) { return json::array({c.r, c.g, c.b}); }

void push(std::vector<float>& out, const Eigen::Vector3d& v) {
  for (int k = 0; k < 3; ++k) out.push_back(static_cast<float>(v[k]));
}

json mesh_json(const SceneMesh& m, const std::string& where) {
  if (!m.normals.empty() && m.normals.size() != m.vertices.size())
    throw std::invalid_argument(fmt::format("viz: replay scene: {} has {} normals for {} vertices", where, m.normals.size(), m.vertices.size()));
  std::vector<float> positions, normals;
  positions.reserve(3 * m.vertices.size());
  for (const auto& v : m.vertices) push(positions, v.cast<double>());
  for (const auto& n : m.normals) push(normals, n.cast<double>());
  std::vector<std::uint32_t> indices;
  indices.reserve(3 * m.triangles.size());
  for (const auto& t : m.triangles)
    for (const int i : t) {
      if (i < 0 || static_cast<std::size_t>(i) >= m.vertices.size())
        throw std::invalid_argument(fmt::format("viz: replay scene: {} has vertex index {} of {} vertices", where, i, m.vertices.size()));
      indices.push_back(static_cast<std::uint32_t>(i));
    }
  const int index_bytes = m.vertices.size() <= 65536 ? 2 : 4;
  return {{"rgba", {m.rgba[0], m.rgba[1], m.rgba[2], m.rgba[3]}},
          {"positions", base64_float32(positions)},
          {"normals", base64_float32(normals)},
          {"indices", detail::base64_uint(indices, index_bytes)},
          {"index_bytes", index_bytes}};
}

// Throws unless `n` entries, one per sample.
template <class List>
void check_length(const List& list, std::size_t n, const std::string& what) {
  if (list.size() != n)
    throw std::invalid_argument(fmt::format("viz: replay track: {} has {} entries for {} samples", what, list.size(), n));
}

std::string points(const std::vector<Eigen::Vector3d>& p) {
  std::vector<float> out;
  out.reserve(3 * p.size());
  for (const auto& v : p) push(out, v);
  return base64_float32(out);
}

// Per sample and body: x y z and the quaternion x y z w.
std::string poses(const ReplayTrack& t) {
  const std::size_t bodies = t.X_WB.front().size();
  std::vector<float> out;
  out.reserve(7 * bodies * t.X_WB.size());
  for (std::size_t k = 0; k < t.X_WB.size(); ++k) {
    if (t.X_WB[k].size() != bodies)
      throw std::invalid_argument(fmt::format("viz: replay track: sample {} has {} bodies, sample 0 has {}", k, t.X_WB[k].size(), bodies));
    for (const Eigen::Isometry3d& X : t.X_WB[k]) {
      push(out, X.translation());
      const Eigen::Quaterniond q(X.rotation());
      for (const double c : {q.x(), q.y(), q.z(), q.w()}) out.push_back(static_cast<float>(c));
    }
  }
  return base64_float32(out);
}

std::string forces(const ReplayTrack& t) {
  std::vector<float> out;
  for (std::size_t k = 0; k < t.forces.size(); ++k) {
    if (t.forces[k].size() != t.forces.front().size())
      throw std::invalid_argument(fmt::format("viz: replay track: sample {} has {} force sites, sample 0 has {}", k, t.forces[k].size(),
                                              t.forces.front().size()));
    for (const ReplayForce& f : t.forces[k]) {
      push(out, f.p_W);
      push(out, f.f_W_N);
    }
  }
  return base64_float32(out);
}

void check_times(const std::vector<double>& time_s) {
  if (time_s.empty()) throw std::invalid_argument("viz: replay track: no sample");
  for (std::size_t k = 0; k < time_s.size(); ++k)
    if (!std::isfinite(time_s[k]) || (k > 0 && !(time_s[k] > time_s[k - 1])))
      throw std::invalid_argument(fmt::format("viz: replay track: time {} ({} s) is not finite or not after the one before", k, time_s[k]));
}

}  // namespace

std::string replay_scene_script(const Scene& scene, const std::string& key) {
  json bodies = json::array();
  for (const SceneBody& b : scene.bodies) {
    json meshes = json::array();
    for (std::size_t m = 0; m < b.meshes.size(); ++m)
      meshes.push_back(mesh_json(b.meshes[m], fmt::format("body '{}' mesh {}", b.name, m)));
    bodies.push_back({{"name", b.name}, {"meshes", std::move(meshes)}});
  }
  return assignment("scenes", key, {{"bodies", std::move(bodies)}});
}

std::string replay_track_script(const ReplayTrack& t, const std::string& key) {
  check_times(t.time_s);
  const std::size_t n = t.time_s.size();
  check_length(t.X_WB, n, "X_WB");
  if (!t.com_W.empty()) check_length(t.com_W, n, "com_W");
  if (!t.forces.empty()) check_length(t.forces, n, "forces");
  std::vector<float> times(t.time_s.begin(), t.time_s.end());
  json j = {{"name", t.name},
            {"samples", n},
            {"bodies", t.X_WB.front().size()},
            {"times", base64_float32(times)},
            {"poses", poses(t)},
            {"com", points(t.com_W)},
            {"sites", t.forces.empty() ? 0 : t.forces.front().size()},
            {"forces", forces(t)}};
  j["paths"] = json::array();
  for (const ReplayPath& p : t.paths) {
    check_length(p.points_W, n, "path '" + p.label + "'");
    j["paths"].push_back({{"label", p.label}, {"rgb", rgb(p.color)}, {"dashed", p.dashed}, {"window_s", p.window_s}, {"points", points(p.points_W)}});
  }
  j["markers"] = json::array();
  for (const ReplayMarker& m : t.markers) {
    check_length(m.points_W, n, "marker '" + m.label + "'");
    j["markers"].push_back({{"label", m.label}, {"rgb", rgb(m.color)}, {"ring_m", m.ring_m}, {"points", points(m.points_W)}});
  }
  j["texts"] = json::array();
  for (const ReplayText& x : t.texts) {
    check_length(x.values, n, "text '" + x.label + "'");
    j["texts"].push_back({{"label", x.label}, {"names", x.value_names},
                          {"values", base64_float32(std::vector<float>(x.values.begin(), x.values.end()))}});
  }
  return assignment("tracks", key, j);
}

}  // namespace dmbd::viz
