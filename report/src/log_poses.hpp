#pragma once
// Internal to report/: where a variant's log holds the robot's pose (joint angles, base
// pose), its contact forces and the overlays' signals, and the links' poses at a row of
// it. The frames (frames.cpp) and the 3-D replay (replay.cpp) read the log through it.
#include <array>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "contact_sites.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/scenario/scenario.hpp"
#include "dmbd/sim/overlay.hpp"
#include "dmbd/sim/run_result.hpp"

namespace dmbd::report::detail {

struct PoseColumns {
  std::vector<int> joint;  // per robot.joints: the column of "<name>.q", or -1 (no coordinate)
  int base = -1;           // floating: "base.x", then y, z, roll, pitch, yaw
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();  // fixed base
  // Every colliding shape (contact_sites.hpp) with the column of its logged force
  // "contact.K.fx" (then fy, fz); none when the log has no contact forces.
  struct Contact {
    ContactSite site;
    int force;
  };
  std::vector<Contact> contacts;
  // What the variant's bus controllers and experiment declare (sim::Overlay: paths,
  // markers, text), each with the columns of its signals (-1: an empty signal, 0); drawn
  // only when every named signal was logged.
  struct Path {
    sim::Overlay overlay;
    std::array<int, 3> column;
  };
  std::vector<Path> paths, markers, texts;
};

// Throws InputError naming `file` and the variant for a joint of the robot missing from
// the log, a floating base without 'base.x', or contact forces logged for another number
// of shapes than the robot's colliding ones.
PoseColumns pose_columns(const model::RobotDescription& robot, const sim::VariantResult& r, const scenario::VariantSetup& v,
                         const std::vector<sim::Overlay>& overlays, const std::string& file);

// The value in `column` at `row` (0 for column -1).
double at(const sim::Log& log, int column, std::size_t row);
Eigen::Vector3d point_at(const sim::Log& log, const std::array<int, 3>& column, std::size_t row);

// The base's pose at the row: the logged one (R = Rz(yaw) Ry(pitch) Rx(roll), as the
// simulation logs it) or the fixed base's.
Eigen::Isometry3d base_pose(const sim::Log& log, const PoseColumns& c, std::size_t row);
// Every link's pose at the row (model::link_frames of the logged angles and base pose).
std::vector<Eigen::Isometry3d> link_poses(const model::RobotDescription& robot, const sim::Log& log, const PoseColumns& c,
                                          std::size_t row);

}  // namespace dmbd::report::detail
