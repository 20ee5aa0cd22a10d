// The range-of-motion figure (report/range_of_motion.hpp) on DRACO's left leg: one panel
// per joint, the moved links at both limits in their colours, nothing else tinted.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "dmbd/model/robot_description.hpp"
#include "dmbd/model/workspace.hpp"
#include "dmbd/report/range_of_motion.hpp"

namespace dmbd::report {
namespace {

const model::RobotDescription& draco() {
  static const model::RobotDescription robot = model::load_urdf(std::string(DMBD_ROBOTS_DIR "/draco") + "/draco.urdf");
  return robot;
}

TEST(RangeOfMotion, LinksMovedByAJointAreItsChildAndBelow) {
  const auto& r = draco();
  const std::vector<bool> moved = links_moved_by(r, r.joint_index("l_knee"));
  std::vector<std::string> names;
  for (std::size_t l = 0; l < moved.size(); ++l)
    if (moved[l]) names.push_back(r.links[l].name);
  EXPECT_EQ(names, (std::vector<std::string>{"l_shank", "l_foot"}));
}

// Pixels clearly of the lower colour (green here, which DRACO's visuals do not use) and
// of the upper colour (magenta) in each panel: both poses are drawn in every panel.
TEST(RangeOfMotion, EachPanelShowsTheRobotAtBothLimitsInTheirColours) {
  const auto chain = model::moving_chain(draco(), "l_foot", "torso");
  RangeOfMotionOptions o;
  o.panel_width_px = 240, o.panel_height_px = 300;
  o.lower_color = {40, 220, 40};
  o.upper_color = {220, 40, 220};
  const cv::Mat img = range_of_motion_image(draco(), chain, o);
  ASSERT_EQ(img.cols, 240 * static_cast<int>(chain.size()));
  ASSERT_EQ(img.rows, 300);
  for (std::size_t i = 0; i < chain.size(); ++i) {
    // Below the caption panel (its text is in the same colours).
    const cv::Mat panel = img(cv::Rect(240 * static_cast<int>(i), 110, 240, 190));
    int green = 0, magenta = 0;
    for (int y = 0; y < panel.rows; ++y)
      for (int x = 0; x < panel.cols; ++x) {
        const cv::Vec3b p = panel.at<cv::Vec3b>(y, x);  // BGR
        green += p[1] > p[0] + 60 && p[1] > p[2] + 60;
        magenta += p[0] > p[1] + 60 && p[2] > p[1] + 60;
      }
    EXPECT_GT(green, 60) << chain[i].name;  // the foot alone (ankle): about 100 px
    EXPECT_GT(magenta, 60) << chain[i].name;
  }
  EXPECT_THROW(range_of_motion_image(draco(), {}, o), std::invalid_argument);
}

}  // namespace
}  // namespace dmbd::report
