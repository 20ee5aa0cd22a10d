// Points binned into square cells of a coordinate plane (the workspace's density maps).
#include <cmath>

#include "dmbd/base/number_text.hpp"
#include "dmbd/model/error.hpp"
#include "dmbd/model/workspace.hpp"

namespace dmbd::model {

DensityGrid density_grid(const std::vector<Eigen::Vector3d>& points, int axis_h, int axis_v, double cell_m) {
  if (points.empty()) throw ModelError("density grid: no points");
  if (axis_h < 0 || axis_h > 2 || axis_v < 0 || axis_v > 2 || axis_h == axis_v)
    throw ModelError("density grid: axes " + std::to_string(axis_h) + " and " + std::to_string(axis_v) +
                     " are not two different coordinates 0..2");
  if (!(cell_m > 0) || !std::isfinite(cell_m))
    throw ModelError("density grid: the cell size " + number_text(cell_m) + " m is not positive");
  double h_lo = points.front()[axis_h], h_hi = h_lo, v_lo = points.front()[axis_v], v_hi = v_lo;
  for (const Eigen::Vector3d& p : points) {
    h_lo = std::min(h_lo, p[axis_h]), h_hi = std::max(h_hi, p[axis_h]);
    v_lo = std::min(v_lo, p[axis_v]), v_hi = std::max(v_hi, p[axis_v]);
  }
  DensityGrid g;
  g.axis_h = axis_h, g.axis_v = axis_v, g.cell_m = cell_m;
  g.h0 = std::floor(h_lo / cell_m) * cell_m;
  g.v0 = std::floor(v_lo / cell_m) * cell_m;
  const double cols = std::floor((h_hi - g.h0) / cell_m) + 1, rows = std::floor((v_hi - g.v0) / cell_m) + 1;
  if (cols * rows > 16e6)
    throw ModelError("density grid: " + number_text(cols) + " x " + number_text(rows) + " cells of " +
                     number_text(cell_m) + " m are too many (at most 16 million)");
  g.cols = static_cast<int>(cols), g.rows = static_cast<int>(rows);
  g.counts.assign(static_cast<std::size_t>(g.cols) * g.rows, 0.0);
  for (const Eigen::Vector3d& p : points) {
    const int c = std::min(g.cols - 1, static_cast<int>(std::floor((p[axis_h] - g.h0) / cell_m)));
    const int r = std::min(g.rows - 1, static_cast<int>(std::floor((p[axis_v] - g.v0) / cell_m)));
    double& n = g.counts[static_cast<std::size_t>(std::max(r, 0)) * g.cols + std::max(c, 0)];
    n += 1;
    g.max_count = std::max(g.max_count, n);
  }
  return g;
}

}  // namespace dmbd::model
