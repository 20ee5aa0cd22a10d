#include "convex_hull.hpp"

extern "C" {
#include <libqhull_r/libqhull_r.h>
}

#include <algorithm>
#include <cstdio>

namespace dmbd::model::detail {

namespace {

// One qhull run with `options` ("qhull ..."); the hull's vertex indices into the input,
// or false when qhull refuses the input (a flat or too small set without QJ).
bool run_qhull(std::vector<double>& coords, int n, const char* options, std::vector<int>& ids) {
  qhT qh_storage;
  qhT* qh = &qh_storage;
  FILE* sink = std::fopen("/dev/null", "w");  // qhull reports refusals on its error file
  qh_zero(qh, sink ? sink : stderr);
  char cmd[64];
  std::snprintf(cmd, sizeof cmd, "%s", options);
  const int code = qh_new_qhull(qh, 3, n, coords.data(), False, cmd, nullptr, sink ? sink : stderr);
  if (code == 0) {
    vertexT* vertex;
    FORALLvertices ids.push_back(qh_pointid(qh, vertex->point));
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  if (sink) std::fclose(sink);
  return code == 0;
}

}  // namespace

std::vector<Eigen::Vector3d> convex_hull_vertices(const std::vector<Eigen::Vector3f>& points) {
  std::vector<Eigen::Vector3d> out;
  if (points.empty()) return out;
  std::vector<double> coords;
  coords.reserve(3 * points.size());
  for (const Eigen::Vector3f& p : points)
    for (int k = 0; k < 3; ++k) coords.push_back(static_cast<double>(p[k]));
  const int n = static_cast<int>(points.size());
  std::vector<int> ids;
  if (n < 4 || !run_qhull(coords, n, "qhull", ids)) {
    ids.clear();
    if (n < 4 || !run_qhull(coords, n, "qhull QJ", ids)) {
      for (const Eigen::Vector3f& p : points) out.push_back(p.cast<double>());  // a point, a segment or a triangle
      return out;
    }
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  for (int i : ids) out.push_back(points[static_cast<std::size_t>(i)].cast<double>());
  return out;
}

std::vector<Eigen::Vector3d> farthest_points(const std::vector<Eigen::Vector3d>& points, std::size_t count) {
  if (points.size() <= count) return points;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) centroid += p;
  centroid /= static_cast<double>(points.size());
  std::vector<double> dist(points.size());  // squared distance to the centroid, then to the chosen set
  for (std::size_t i = 0; i < points.size(); ++i) dist[i] = (points[i] - centroid).squaredNorm();
  std::vector<Eigen::Vector3d> out;
  while (out.size() < count) {
    const std::size_t best = static_cast<std::size_t>(std::max_element(dist.begin(), dist.end()) - dist.begin());
    out.push_back(points[best]);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double d = (points[i] - points[best]).squaredNorm();
      dist[i] = out.size() == 1 ? d : std::min(dist[i], d);
    }
  }
  return out;
}

std::vector<Eigen::Vector3d> mesh_contact_points(const TriangleMesh& mesh, std::size_t max, std::size_t* hull_size) {
  const std::vector<Eigen::Vector3d> hull = convex_hull_vertices(mesh.vertices);
  if (hull_size) *hull_size = hull.size();
  return farthest_points(hull, max);
}

}  // namespace dmbd::model::detail
