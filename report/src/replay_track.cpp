// A variant's log sampled into a replay track: what a frame draws, at every sampled row.
#include "replay_track.hpp"

#include <algorithm>
#include <cmath>

namespace dmbd::report::detail {

std::vector<std::size_t> replay_rows(const sim::Log& log, double rate_hz) {
  const std::size_t rows = log.rows();
  std::vector<std::size_t> out;
  if (rows == 0) return out;
  std::size_t m = 1;
  if (rows > 1) {
    const double dt = (log.time().back() - log.time().front()) / static_cast<double>(rows - 1);
    if (dt > 0 && rate_hz > 0) m = std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(1.0 / (rate_hz * dt))));
  }
  for (std::size_t row = 0; row < rows; row += m) out.push_back(row);
  if (out.back() != rows - 1) out.push_back(rows - 1);
  return out;
}

std::size_t floats_per_sample(const model::RobotDescription& robot, const PoseColumns& c, bool table) {
  return 1 + 7 * (robot.links.size() + (table ? 1 : 0)) + 3 + 6 * c.contacts.size() + 3 * (c.paths.size() + c.markers.size()) +
         c.texts.size();
}

namespace {

viz::Color colour(const sim::Overlay& o) { return viz::Color{o.rgb[0], o.rgb[1], o.rgb[2]}; }

void start_overlays(const PoseColumns& c, viz::ReplayTrack& t) {
  for (const auto& p : c.paths) t.paths.push_back({p.overlay.label, colour(p.overlay), p.overlay.dashed, p.overlay.window_s, {}});
  for (const auto& m : c.markers) t.markers.push_back({m.overlay.label, colour(m.overlay), 0.06, {}});
  for (const auto& x : c.texts) t.texts.push_back({x.overlay.label, x.overlay.value_names, {}});
}

void add_overlays(const sim::Log& log, const PoseColumns& c, std::size_t row, viz::ReplayTrack& t) {
  for (std::size_t k = 0; k < c.paths.size(); ++k) t.paths[k].points_W.push_back(point_at(log, c.paths[k].column, row));
  for (std::size_t k = 0; k < c.markers.size(); ++k) t.markers[k].points_W.push_back(point_at(log, c.markers[k].column, row));
  for (std::size_t k = 0; k < c.texts.size(); ++k) t.texts[k].values.push_back(at(log, c.texts[k].column[0], row));
}

// Every colliding shape's force where the frames draw it (zero when not finite: not drawn).
std::vector<viz::ReplayForce> forces(const sim::Log& log, const PoseColumns& c, std::size_t row,
                                     const std::vector<Eigen::Isometry3d>& X) {
  std::vector<viz::ReplayForce> out;
  out.reserve(c.contacts.size());
  for (const auto& k : c.contacts) {
    const Eigen::Vector3d f(at(log, k.force, row), at(log, k.force + 1, row), at(log, k.force + 2, row));
    const Eigen::Vector3d p = contact_point(k.site, X[static_cast<std::size_t>(k.site.link)]);
    out.push_back({p, f.allFinite() ? f : Eigen::Vector3d::Zero()});
  }
  return out;
}

}  // namespace

viz::ReplayTrack replay_track(const model::RobotDescription& robot, const sim::VariantResult& r, const PoseColumns& c,
                              const std::optional<Table>& table, const std::vector<std::size_t>& rows) {
  viz::ReplayTrack t;
  t.name = r.name;
  start_overlays(c, t);
  for (const std::size_t row : rows) {
    std::vector<Eigen::Isometry3d> X = link_poses(robot, r.log, c, row);
    t.time_s.push_back(r.log.time()[row]);
    t.com_W.push_back(model::center_of_mass(robot, X));
    if (!c.contacts.empty()) t.forces.push_back(forces(r.log, c, row, X));
    add_overlays(r.log, c, row, t);
    if (table) X.push_back(table->X_WT);
    t.X_WB.push_back(std::move(X));
  }
  return t;
}

}  // namespace dmbd::report::detail
