#pragma once
// The range-of-motion figure (the paper's Fig. 2a-d): one panel per joint of a chain,
// the rendered robot at the joint's lower limit (blue, drawn see-through) and at its
// upper limit (orange) overlaid, every other joint at its rest position, the camera
// looking along the joint's axis (from the front and above for a vertical axis), and
// the joint's name and range in rad and deg written on the panel.
//
//   const auto chain = dmbd::model::moving_chain(robot, "l_foot", "torso");
//   const cv::Mat image = dmbd::report::range_of_motion_image(robot, chain);
#include <vector>

#include <opencv2/core.hpp>

#include "dmbd/model/robot_description.hpp"
#include "dmbd/model/workspace.hpp"
#include "dmbd/viz/plot.hpp"  // Color

namespace dmbd::report {

struct RangeOfMotionOptions {
  int panel_width_px = 420, panel_height_px = 520;  // the panels stand in one row
  viz::Color lower_color{60, 110, 230}, upper_color{240, 130, 30};  // the links the joint moves
  double lower_opacity = 0.6;  // of the lower-limit pose where it is not behind the upper one
};

// Throws std::invalid_argument for an empty chain, a joint index outside robot.joints or
// a panel smaller than the renderer allows (16 px).
cv::Mat range_of_motion_image(const model::RobotDescription& robot, const std::vector<model::ChainJoint>& chain,
                              const RangeOfMotionOptions& options = {});

// The links a joint moves: its child and every link below it (flags, robot.links order).
std::vector<bool> links_moved_by(const model::RobotDescription& robot, int joint);

}  // namespace dmbd::report
