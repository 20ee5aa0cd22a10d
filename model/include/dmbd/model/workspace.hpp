#pragma once
// A link's workspace by sampling the joint space (issue 17 item 2, the paper's Fig. 2):
// the moving joints between a reference link and the link, uniform seeded samples of
// them within their limits, the link origin's position in the reference link's frame
// at each sample, and the density of those positions on a grid of a plane.
//
//   const auto robot = dmbd::model::load_urdf(dmbd::model::find_robot("draco").urdf);
//   const auto ws = dmbd::model::sample_workspace(robot, "l_foot", "torso", {100000, 1});
//   const auto xz = dmbd::model::density_grid(ws.points, 0, 2, 0.02);   // sagittal map
//
// Plain Eigen and std; positions come from model::link_frames (the project's one
// forward-kinematics routine for a description).
#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "dmbd/model/robot_description.hpp"

namespace dmbd::model {

// A joint that moves the link relative to the reference link, with the interval it is
// sampled over: its limits (rad or m), or [-pi, pi] for a joint without limits
// (continuous; `unlimited` says so).
struct ChainJoint {
  int joint = -1;  // index into robot.joints
  std::string name;
  double lower = 0, upper = 0;
  bool unlimited = false;
};

// The revolute, continuous and prismatic joints on the tree path between `reference`
// and `link` (root side first; fixed, floating and planar joints on it are not
// sampled). Throws ModelError for an unknown link (naming it and the robot) and for a
// path without a moving joint ("link 'torso' is not below a moving joint ...").
std::vector<ChainJoint> moving_chain(const RobotDescription& robot, const std::string& link,
                                     const std::string& reference);

// The positions every joint keeps while the chain moves: 0, clamped into the joint's
// limits when 0 is outside them (robot.joints order).
std::vector<double> rest_positions(const RobotDescription& robot);

// n samples of the chain's joints, uniform and independent within each joint's
// interval: row k is sample k, column i chain[i]. The generator is std::mt19937_64
// seeded with `seed`, turned into doubles in [0, 1) by its top 53 bits, so a seed gives
// the same samples on every platform. Throws ModelError when n < 1.
Eigen::MatrixXd sample_joint_space(const std::vector<ChainJoint>& chain, std::size_t n, std::uint64_t seed);

struct WorkspaceOptions {
  std::size_t samples = 100000;
  std::uint64_t seed = 1;
};

struct Workspace {
  std::string link, reference;
  std::vector<ChainJoint> chain;
  std::size_t samples = 0;
  std::uint64_t seed = 0;
  std::vector<Eigen::Vector3d> points;  // link origin in the reference link's frame, m, one per sample
  Eigen::Vector3d min = Eigen::Vector3d::Zero(), max = Eigen::Vector3d::Zero();  // extents of points
};

// Samples the chain (moving_chain, sample_joint_space), every other joint at its
// rest position, and records where the link's origin is relative to the reference.
// Throws as moving_chain and sample_joint_space do.
Workspace sample_workspace(const RobotDescription& robot, const std::string& link, const std::string& reference,
                           const WorkspaceOptions& options = {});

// Counts of points per square cell of a plane spanned by two coordinate axes (0 x,
// 1 y, 2 z): cells of cell_m on a grid aligned to multiples of cell_m that covers
// every point. Row 0 is the lowest v (the vertical axis), column 0 the lowest h.
struct DensityGrid {
  int axis_h = 0, axis_v = 2;
  double h0 = 0, v0 = 0, cell_m = 0;  // lower-left corner of cell (0, 0)
  int cols = 0, rows = 0;
  std::vector<double> counts;  // rows x cols, row-major
  double max_count = 0;
  double count(int row, int col) const { return counts[static_cast<std::size_t>(row) * cols + col]; }
};
// Throws ModelError for no points, an axis outside 0..2 or equal axes, a cell that is
// not positive and finite, or a grid of more than 16 million cells.
DensityGrid density_grid(const std::vector<Eigen::Vector3d>& points, int axis_h, int axis_v, double cell_m);

}  // namespace dmbd::model
