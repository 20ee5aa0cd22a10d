#pragma once
// The point contact the balancing tests assume on DRACO's feet: the centre of a link's
// collision spheres (four per foot), as control::BalanceController takes it.
#include <string>

#include <Eigen/Core>

#include "dmbd/model/robot_description.hpp"

namespace dmbd::sim::test {

inline Eigen::Vector3d collision_centre(const model::RobotDescription& r, const std::string& link) {
  const auto& shapes = r.links[static_cast<size_t>(r.link_index(link))].collisions;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& s : shapes) c += s.X_LG.translation();
  return c / static_cast<double>(shapes.size());
}

}  // namespace dmbd::sim::test
