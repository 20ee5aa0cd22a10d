// SelectionTask (selection_task.hpp): the rows it picks are exactly the source tasks'
// rows (J, J̇v, e, ė, ẍ_cmd) after its own update; bad rows are refused.
#include <gtest/gtest.h>

#include "arm_fixtures.hpp"
#include "dmbd/base/error.hpp"
#include "dmbd/wholebody/selection_task.hpp"
#include "two_link_arm.hpp"

namespace dmbd::wholebody::testing {
namespace {

TEST(SelectionTask, CopiesTheChosenRowsOfItsSources) {
  TwoLinkArm arm = two_link_arm();
  const int tip = arm.add_frame({"link2", Eigen::Vector3d(0.4, 0, 0)});
  const ModelData data = evaluate(arm, Eigen::Vector2d(0.3, -0.7), Eigen::Vector2d(1.1, -0.4));
  PointTask point(tip, 2);
  point.set_reference(Eigen::Vector3d(0.5, 0.1, 0.2), Eigen::Vector3d(0.3, 0, -0.2), Eigen::Vector3d(1, 2, 3));
  point.set_gains(Eigen::Vector3d(10, 20, 30), Eigen::Vector3d(1, 2, 3));
  OrientationTask orientation(tip, 2);
  orientation.set_reference(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY()).toRotationMatrix(), Eigen::Vector3d(0, 0.5, 0),
                            Eigen::Vector3d::Zero());
  orientation.set_gains(7.0, 3.0);
  SelectionTask torso({{&orientation, 1}, {&point, 2}, {&point, 0}}, 2);
  ASSERT_EQ(torso.dim(), 3);
  torso.update(data);  // updates both sources
  const std::pair<const Task*, int> rows[] = {{&orientation, 1}, {&point, 2}, {&point, 0}};
  for (int i = 0; i < 3; ++i) {
    const Task& t = *rows[i].first;
    const int r = rows[i].second;
    EXPECT_EQ(torso.jacobian().row(i), t.jacobian().row(r));  // copies: exact
    EXPECT_EQ(torso.jacobian_dot_v()[i], t.jacobian_dot_v()[r]);
    EXPECT_EQ(torso.error()[i], t.error()[r]);
    EXPECT_EQ(torso.error_rate()[i], t.error_rate()[r]);
    EXPECT_EQ(torso.command()[i], t.command()[r]);
  }
  EXPECT_NE(torso.error()[1], 0.0);  // the sources were updated (not left at zero)
}

TEST(SelectionTask, RefusesARowOutOfRangeOrANullTask) {
  PointTask point(0, 2);
  EXPECT_THROW(SelectionTask({{&point, 3}}, 2), InputError);
  EXPECT_THROW(SelectionTask({{&point, -1}}, 2), InputError);
  EXPECT_THROW(SelectionTask({{nullptr, 0}}, 2), InputError);
  EXPECT_THROW(SelectionTask({{&point, 0}}, 5), InputError);  // another model size
}

}  // namespace
}  // namespace dmbd::wholebody::testing
