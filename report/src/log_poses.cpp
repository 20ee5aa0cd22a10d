// Where a variant's log holds the robot's pose, contact forces and overlays' signals, and
// the links' poses at one of its rows (moved here from frames.cpp: the replay reads them too).
#include "log_poses.hpp"

#include <fmt/format.h>

#include "dmbd/base/error.hpp"

namespace dmbd::report::detail {

namespace {

bool one_dof(model::JointType t) {
  return t == model::JointType::Revolute || t == model::JointType::Continuous || t == model::JointType::Prismatic;
}

// The contact forces' columns, one per colliding shape in the plant's order. A log whose
// contact columns do not count the robot's colliding shapes was written for another
// robot: an error, as a missing joint angle is.
void add_contacts(const model::RobotDescription& robot, const sim::VariantResult& r, const std::string& file,
                  PoseColumns& c) {
  if (r.log.find("contact.0.fx") < 0) return;
  const std::vector<ContactSite> sites = contact_sites(robot);
  std::size_t logged = 0;
  while (r.log.find(fmt::format("contact.{}.fx", logged)) >= 0) ++logged;
  if (logged != sites.size())
    throw InputError(fmt::format("{}: variant '{}' logged the contact forces of {} shapes, its robot has {} colliding "
                                 "shapes: the robot cannot be drawn from its log",
                                 file, r.name, logged, sites.size()));
  for (std::size_t k = 0; k < sites.size(); ++k)
    c.contacts.push_back({sites[k], r.log.find(fmt::format("contact.{}.fx", k))});
}

}  // namespace

PoseColumns pose_columns(const model::RobotDescription& robot, const sim::VariantResult& r, const scenario::VariantSetup& v,
                         const std::vector<sim::Overlay>& overlays, const std::string& file) {
  PoseColumns c;
  for (const auto& j : robot.joints) {
    c.joint.push_back(one_dof(j.type) ? r.log.find(j.name + ".q") : -1);
    if (one_dof(j.type) && c.joint.back() < 0)
      throw InputError(file + ": variant '" + r.name + "' logged no '" + j.name + ".q': the robot cannot be drawn from its log");
  }
  c.X_WB = v.robot.X_WB;
  if (v.robot.base == model::BaseMode::Floating) {
    c.base = r.log.find("base.x");
    if (c.base < 0) throw InputError(file + ": variant '" + r.name + "' logged no 'base.x': the robot cannot be drawn from its log");
  }
  for (const sim::Overlay& o : overlays) {
    std::array<int, 3> col{-1, -1, -1};
    bool logged = true;
    for (int k = 0; k < 3; ++k)
      if (!o.signals[static_cast<std::size_t>(k)].empty()) {
        col[static_cast<std::size_t>(k)] = r.log.find(o.signals[static_cast<std::size_t>(k)]);
        logged = logged && col[static_cast<std::size_t>(k)] >= 0;
      }
    if (!logged) continue;
    auto& list = o.kind == sim::Overlay::Kind::Path ? c.paths : o.kind == sim::Overlay::Kind::Marker ? c.markers : c.texts;
    list.push_back({o, col});
  }
  add_contacts(robot, r, file, c);
  return c;
}

double at(const sim::Log& log, int column, std::size_t row) { return column < 0 ? 0.0 : log.column(column)[row]; }

Eigen::Vector3d point_at(const sim::Log& log, const std::array<int, 3>& column, std::size_t row) {
  return {at(log, column[0], row), at(log, column[1], row), at(log, column[2], row)};
}

Eigen::Isometry3d base_pose(const sim::Log& log, const PoseColumns& c, std::size_t row) {
  if (c.base < 0) return c.X_WB;
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() << at(log, c.base, row), at(log, c.base + 1, row), at(log, c.base + 2, row);
  X.linear() = (Eigen::AngleAxisd(at(log, c.base + 5, row), Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(at(log, c.base + 4, row), Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(at(log, c.base + 3, row), Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return X;
}

std::vector<Eigen::Isometry3d> link_poses(const model::RobotDescription& robot, const sim::Log& log, const PoseColumns& c,
                                          std::size_t row) {
  std::vector<double> q(robot.joints.size(), 0.0);
  for (std::size_t j = 0; j < q.size(); ++j)
    if (c.joint[j] >= 0) q[j] = at(log, c.joint[j], row);
  return model::link_frames(robot, q, base_pose(log, c, row));
}

}  // namespace dmbd::report::detail
