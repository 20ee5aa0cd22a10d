// Tasks (task.hpp) against hand values on the two-link arm and hand-made ModelData:
// PointTask (also relative to a second frame), ComTask, OrientationTask and
// PostureTask's Jacobian, J̇v, error, error rate and command ẍ_cmd = ẍ_d + Kp e + Kd ė;
// the orientation error as a world-axes rotation vector; the posture task's q and v
// indices on a floating base; bad input.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>

#include "arm_fixtures.hpp"
#include "dmbd/base/error.hpp"
#include "dmbd/wholebody/task.hpp"
#include "two_link_arm.hpp"

namespace dmbd::wholebody::testing {
namespace {

// The hand values below are sums of a few O(1) products: exact to ~1e-16; 1e-12 allows
// for the trigonometry of the arm.
constexpr double kTol = 1e-12;

Eigen::VectorXd vec(std::initializer_list<double> x) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(x.size()));
  Eigen::Index i = 0;
  for (double e : x) v[i++] = e;
  return v;
}

// The two-link arm (l1 = 0.5, l2 = 0.4) stretched along +x, the shoulder turning at
// 1 rad/s: the tip at (0.9, 0, 0) moving at (0, 0, −0.9) (ŷ × r), accelerating at
// J̇v = −ω² r = (−0.9, 0, 0).
struct StretchedArm {
  TwoLinkArm arm = two_link_arm();
  int tip = arm.add_frame({"link2", Eigen::Vector3d(0.4, 0, 0)});
  int elbow = arm.add_frame({"link1", Eigen::Vector3d(0.5, 0, 0)});
  ModelData data = evaluate(arm, Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0));
};

TEST(PointTask, HandValuesOnTheStretchedArm) {
  StretchedArm s;
  PointTask task(s.tip, 2);
  task.set_reference({1.0, 0.0, 0.2}, {0.0, 0.0, 0.0}, {0.1, 0.0, 0.0});
  task.set_gains(vec({100, 50, 25}), vec({20, 10, 5}));
  task.update(s.data);
  EXPECT_EQ(task.dim(), 3);
  EXPECT_EQ(task.jacobian(), s.data.frames[0].J.bottomRows<3>());
  EXPECT_EQ(task.jacobian_dot_v(), s.data.frames[0].Jdot_v.tail<3>());
  EXPECT_LT((task.position() - Eigen::Vector3d(0.9, 0, 0)).norm(), kTol);
  EXPECT_LT((task.jacobian_dot_v() - Eigen::Vector3d(-0.9, 0, 0)).norm(), kTol);
  EXPECT_LT((task.error() - Eigen::Vector3d(0.1, 0, 0.2)).norm(), kTol);
  EXPECT_LT((task.error_rate() - Eigen::Vector3d(0, 0, 0.9)).norm(), kTol);
  // ẍ_cmd = (0.1 + 100·0.1 + 20·0, 0, 0 + 25·0.2 + 5·0.9).
  EXPECT_LT((task.command() - Eigen::Vector3d(10.1, 0, 9.5)).norm(), kTol) << task.command().transpose();
}

// The three-link arm bent and moving, its tip (frame 0) and a point on link 1 off its
// axis (frame 1, 5 cm along y: the difference has all three components).
struct MovingArm {
  PlanarArm arm = three_link_arm();
  int tip = arm.add_frame({"link3", Eigen::Vector3d(link_c().length, 0, 0)});
  int base = arm.add_frame({"link1", Eigen::Vector3d(0.35, 0.05, 0)});
  ModelData data = evaluate(arm, Eigen::Vector3d(0.3, -0.8, 1.1), Eigen::Vector3d(0.7, -1.2, 0.5));
};

// x = p_F − p_B, J = J_F − J_B, J̇v = J̇_F v − J̇_B v against two plain point tasks on the
// same data (the same subtractions: 1e-15), e = x_d − x, ė = ẋ_d − J v and ẍ_cmd from
// them (1e-12, as the hand values above).
TEST(PointTask, RelativeToAFrameIsTheDifferenceOfTheTwoPoints) {
  MovingArm m;
  PointTask relative(m.tip, 3, m.base), at_tip(m.tip, 3), at_base(m.base, 3);
  const Eigen::Vector3d p_d(0.3, 0.02, -0.4), v_d(0.1, -0.2, 0.3), a_d(1.0, 0.5, -2.0);
  relative.set_reference(p_d, v_d, a_d);
  relative.set_gains(vec({100, 50, 25}), vec({20, 10, 5}));
  for (PointTask* t : {&relative, &at_tip, &at_base}) t->update(m.data);
  const Eigen::Vector3d x = at_tip.position() - at_base.position();
  const Eigen::MatrixXd J = at_tip.jacobian() - at_base.jacobian();
  EXPECT_LT((relative.position() - x).norm(), 1e-15);
  EXPECT_LT((relative.jacobian() - J).norm(), 1e-15);
  EXPECT_LT((relative.jacobian_dot_v() - (at_tip.jacobian_dot_v() - at_base.jacobian_dot_v())).norm(), 1e-15);
  EXPECT_GT(x.cwiseAbs().minCoeff(), 0.01);  // every component non-trivial: (0.742, −0.05, −0.022) m
  EXPECT_GT(at_base.jacobian().norm(), 0.1);  // and B moves (|J_B| = 0.35): J differs from J_F
  const Eigen::Vector3d e = p_d - x, edot = v_d - J * m.data.v;
  EXPECT_LT((relative.error() - e).norm(), kTol);
  EXPECT_LT((relative.error_rate() - edot).norm(), kTol);
  const Eigen::Vector3d cmd = a_d + vec({100, 50, 25}).cwiseProduct(e) + vec({20, 10, 5}).cwiseProduct(edot);
  EXPECT_LT((relative.command() - cmd).norm(), kTol);
}

// A world target (p_W, v_W) given to the relative task as (p_W − p_B, v_W − J_B v) gives
// the world task's error and error rate (1e-12).
TEST(PointTask, RelativeTaskWithTheTargetFromBIsTheWorldTask) {
  MovingArm m;
  PointTask relative(m.tip, 3, m.base), world(m.tip, 3), at_base(m.base, 3);
  at_base.update(m.data);
  const Eigen::Vector3d p_W(0.6, 0.1, -0.7), v_W(-0.3, 0.2, 0.4), a_W(0.5, 0.0, 1.0);
  world.set_reference(p_W, v_W, a_W);
  relative.set_reference(p_W - at_base.position(), v_W - at_base.jacobian() * m.data.v, a_W);
  world.update(m.data);
  relative.update(m.data);
  EXPECT_LT((relative.error() - world.error()).norm(), kTol);
  EXPECT_LT((relative.error_rate() - world.error_rate()).norm(), kTol);
  EXPECT_GT(world.error_rate().norm(), 0.1);  // a moving arm: a rate error to match (0.60 m/s)
}

TEST(ComTask, HandValuesOnTheStretchedArm) {
  StretchedArm s;
  // CoM at x = (m1 lc1 + m2 (l1 + lc2)) / M, moving at (0, 0, −x), accelerating at (−x, 0, 0).
  const double x = (2.0 * 0.3 + 1.5 * 0.75) / 3.5;
  ComTask task(2);
  task.set_reference({0.5, 0.0, 0.1}, {0.1, 0.0, 0.0}, {0.0, 0.0, 1.0});
  task.set_gains(10.0, 2.0);
  task.update(s.data);
  EXPECT_EQ(task.jacobian(), s.data.J_com);
  EXPECT_LT((task.jacobian_dot_v() - Eigen::Vector3d(-x, 0, 0)).norm(), kTol);
  const Eigen::Vector3d e(0.5 - x, 0, 0.1), edot(0.1, 0, x);
  EXPECT_LT((task.error() - e).norm(), kTol);
  EXPECT_LT((task.error_rate() - edot).norm(), kTol);
  EXPECT_LT((task.command() - (Eigen::Vector3d(0, 0, 1) + 10 * e + 2 * edot)).norm(), kTol);
}

// Link 1 turned by 0.3 about y, its frame at the elbow; the shoulder turning at 0.5 rad/s.
struct TurnedArm {
  TwoLinkArm arm = two_link_arm();
  int elbow = arm.add_frame({"link1", Eigen::Vector3d(0.5, 0, 0)});
  ModelData data = evaluate(arm, Eigen::Vector2d(0.3, 1.1), Eigen::Vector2d(0.5, -1.0));
  Eigen::Matrix3d R = rotation_y(0.3);
};

TEST(OrientationTask, ErrorOfARotationAboutYIsItsRotationVector) {
  TurnedArm t;
  OrientationTask task(t.elbow, 2);
  task.set_reference(rotation_y(0.8), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  task.update(t.data);
  EXPECT_LT((task.error() - Eigen::Vector3d(0, 0.5, 0)).norm(), kTol) << task.error().transpose();
  EXPECT_EQ(task.jacobian(), t.data.frames[0].J.topRows<3>());
  EXPECT_EQ(task.jacobian_dot_v(), t.data.frames[0].Jdot_v.head<3>());
}

TEST(OrientationTask, ErrorIsInWorldAxes) {
  // R_d = exp(θ n) R: e = θ n. R is not about n, so the body-axes reading Rᵀ θ n differs
  // by |θ n − Rᵀ θ n| ≈ 0.2 (checked: the test can tell them apart). Up to θ = 3 (near π,
  // where the axis comes from the quaternion's vector part: still ~1e-15).
  TurnedArm t;
  const Eigen::Vector3d n = Eigen::Vector3d(1, 2, 2) / 3.0;
  for (const double theta : {0.7, 3.0}) {
    OrientationTask task(t.elbow, 2);
    task.set_reference(Eigen::AngleAxisd(theta, n).toRotationMatrix() * t.R, Eigen::Vector3d::Zero(),
                       Eigen::Vector3d::Zero());
    task.update(t.data);
    EXPECT_LT((task.error() - theta * n).norm(), kTol) << "θ " << theta << ": " << task.error().transpose();
    EXPECT_GT((task.error() - t.R.transpose() * theta * n).norm(), 0.1);
  }
}

TEST(OrientationTask, RateErrorAndCommand) {
  // Link 1's angular velocity is (0, v1, 0) = (0, 0.5, 0) in world axes.
  TurnedArm t;
  OrientationTask task(t.elbow, 2);
  task.set_reference(t.R, Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(1, 0, 0));
  task.set_gains(4.0, 2.0);
  task.update(t.data);
  EXPECT_LT(task.error().norm(), kTol);
  EXPECT_LT((task.error_rate() - Eigen::Vector3d(0.1, -0.3, 0.3)).norm(), kTol);
  EXPECT_LT((task.command() - Eigen::Vector3d(1.2, -0.6, 0.6)).norm(), kTol);
}

TEST(PostureTask, SelectsJointsInTheGivenOrder) {
  PlanarArm arm = three_link_arm();
  const ModelData d = evaluate(arm, Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(1, 2, 3));
  PostureTask task(arm.layout(), {2, 0});
  task.set_reference(Eigen::Vector2d(0.5, -0.5), Eigen::Vector2d(0, 1), Eigen::Vector2d(2, 0));
  task.set_gains(vec({4, 9}), vec({1, 2}));
  task.update(d);
  Eigen::MatrixXd J(2, 3);
  J << 0, 0, 1, 1, 0, 0;
  EXPECT_EQ(task.jacobian(), J);
  EXPECT_EQ(task.jacobian_dot_v(), Eigen::VectorXd::Zero(2));
  EXPECT_LT((task.error() - Eigen::Vector2d(0.2, -0.6)).norm(), kTol);
  EXPECT_LT((task.error_rate() - Eigen::Vector2d(-3, 0)).norm(), kTol);
  // (2 + 4·0.2 + 1·(−3), 0 + 9·(−0.6) + 2·0)
  EXPECT_LT((task.command() - Eigen::Vector2d(-0.2, -5.4)).norm(), kTol) << task.command().transpose();
}

TEST(PostureTask, ReadsQAndVAtTheirOwnIndicesOnAFloatingBase) {
  // A floating base shifts a joint's q index (7 + k) and v index (6 + k) differently.
  Layout l;
  l.base_dofs = 6;
  l.nq = 9;
  l.nv = 8;
  l.joints = {{"a", 7, 6, {}}, {"b", 8, 7, {}}};
  ModelData d;
  d.q = Eigen::VectorXd::LinSpaced(9, 0.0, 0.8);   // q[k] = 0.1 k
  d.v = Eigen::VectorXd::LinSpaced(8, 10.0, 17.0);  // v[k] = 10 + k
  PostureTask task(l, {1});
  task.update(d);
  EXPECT_EQ(task.jacobian(), Eigen::RowVectorXd::Unit(8, 7));
  EXPECT_NEAR(task.error()[0], -0.8, kTol);
  EXPECT_NEAR(task.error_rate()[0], -17.0, kTol);
}

TEST(Tasks, RejectBadInput) {
  PlanarArm arm = three_link_arm();
  EXPECT_THROW(PostureTask(arm.layout(), {3}), InputError);
  EXPECT_THROW(PostureTask(arm.layout(), {-1}), InputError);
  PointTask task(0, 3);
  EXPECT_THROW(task.set_gains(vec({1, 2}), vec({1, 2, 3})), InputError);
  task.set_gains(vec({1, 2, 3}), vec({4, 5, 6}));
  EXPECT_EQ(task.kp(), vec({1, 2, 3}));
  EXPECT_EQ(task.kd(), vec({4, 5, 6}));
}

}  // namespace
}  // namespace dmbd::wholebody::testing
