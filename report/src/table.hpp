#pragma once
// Internal to report/: the table a fixed base without ground contact is clamped to (the
// paper's table tests), drawn by the frames (frames.cpp) and the 3-D replay (replay.cpp).
#include <vector>

#include <Eigen/Geometry>

#include "dmbd/viz/renderer.hpp"

namespace dmbd::report::detail {

struct Table {
  viz::SceneBody body;
  Eigen::Isometry3d X_WT = Eigen::Isometry3d::Identity();
};

// One scene body in the world at X_WT, placed from the robot's first pose X (one per
// robot_scene body) with its base at X_WB (table.cpp says where).
Table table_under(const viz::Scene& robot_scene, const std::vector<Eigen::Isometry3d>& X, const Eigen::Isometry3d& X_WB);

}  // namespace dmbd::report::detail
