// Prioritised inverse kinematics (wholebody/prioritized_ik.hpp) on the planar test arms:
// compatible tasks all met exactly (configuration step, rates, accelerations); a lower
// task never disturbs a higher one; a conflicting lower task gets the least-squares
// best in the higher one's null space (against an independent null-space basis); the
// contacts are kept still; a singular arm gives finite results; no allocation in a solve.
// This executable counts allocations (malloc_counter.hpp).
#include <gtest/gtest.h>

#include "malloc_counter.hpp"

#include <Eigen/LU>
#include <Eigen/QR>

#include <random>

#include "arm_fixtures.hpp"
#include "dmbd/wholebody/prioritized_ik.hpp"
#include "planar_point_task.hpp"
#include "two_link_arm.hpp"

namespace dmbd::wholebody::testing {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

PlanarArm four_link_arm() { return PlanarArm({link_a(), link_b(), link_c(), link_a()}); }

// A bent four-link arm in motion, its tip task (x, z) and a posture task of joint 0,
// with errors, reference rates and accelerations that the arm can all meet.
struct Scene {
  PlanarArm arm = four_link_arm();
  int tip = arm.add_frame({"link4", Eigen::Vector3d(link_a().length, 0, 0)});
  ModelData data;
  PlanarPointTask tip_task{tip, 4};
  PostureTask joint0{arm.layout(), {0}};
  Scene() {
    const VectorXd q = (VectorXd(4) << 0.3, -0.7, 0.9, 0.4).finished();
    const VectorXd v = (VectorXd(4) << 0.5, -0.2, 0.8, -0.6).finished();
    data = evaluate(arm, q, v);
    const Eigen::Vector2d p = in_plane(data.frames[0].X_WF.translation());
    tip_task.set_reference(p + Eigen::Vector2d(0.01, -0.02), Eigen::Vector2d(0.3, 0.1), Eigen::Vector2d(-1.0, 2.0));
    tip_task.set_gains(100.0, 20.0);
    joint0.set_reference(VectorXd::Constant(1, 0.32), VectorXd::Constant(1, -0.4), VectorXd::Constant(1, 1.5));
    joint0.set_gains(50.0, 10.0);
    tip_task.update(data);
    joint0.update(data);
  }
};

// Each task's three equations, to `tol` (absolute: quantities of order 1).
void expect_met(const Task& t, const ModelData& d, const PrioritizedIk& ik, double tol) {
  const MatrixXd& J = t.jacobian();
  EXPECT_LT((J * ik.delta_q() - t.error()).norm(), tol) << "configuration step";
  EXPECT_LT((J * ik.qd() - (t.error_rate() + J * d.v)).norm(), tol) << "rate";
  EXPECT_LT((J * ik.qdd() + t.jacobian_dot_v() - t.command()).norm(), tol) << "acceleration";
}

TEST(PrioritizedIk, CompatibleTasksAreAllMetExactly) {
  Scene s;
  PrioritizedIk ik(4, 0, {2, 1});
  const Task* tasks[] = {&s.tip_task, &s.joint0};
  ik.solve(s.data, MatrixXd(0, 4), VectorXd(0), tasks);
  expect_met(s.tip_task, s.data, ik, 1e-12);
  expect_met(s.joint0, s.data, ik, 1e-12);
}

TEST(PrioritizedIk, ALowerTaskDoesNotDisturbAHigherOne) {
  Scene s;
  PrioritizedIk one(4, 0, {2}), two(4, 0, {2, 1});
  const Task* tasks[] = {&s.tip_task, &s.joint0};
  one.solve(s.data, MatrixXd(0, 4), VectorXd(0), tasks);
  two.solve(s.data, MatrixXd(0, 4), VectorXd(0), tasks);
  const MatrixXd& J = s.tip_task.jacobian();
  EXPECT_LT((J * (two.qd() - one.qd())).norm(), 1e-13);
  EXPECT_LT((J * (two.qdd() - one.qdd())).norm(), 1e-12);
  EXPECT_LT((J * (two.delta_q() - one.delta_q())).norm(), 1e-13);
  EXPECT_GT((two.qd() - one.qd()).norm(), 0.1);  // the lower task did move the arm
  EXPECT_LT((J * two.null_space()).norm(), 1e-13);
}

// Three joints' posture under a 2-D tip task on a 3-link arm: one degree of freedom is
// left for three posture rows. The achieved posture rate must be the least-squares best
// over q̇ = q̇₁ + Z z, Z a basis of J_tip's null space from a full-pivoting LU (a second,
// independent construction).
TEST(PrioritizedIk, AConflictingLowerTaskGetsItsLeastSquaresBestInTheNullSpace) {
  PlanarArm arm = three_link_arm();
  const int tip = arm.add_frame({"link3", Eigen::Vector3d(link_c().length, 0, 0)});
  const ModelData d = evaluate(arm, (VectorXd(3) << 0.2, 0.5, -0.4).finished(), (VectorXd(3) << 0.1, 0.3, -0.2).finished());
  PlanarPointTask tip_task(tip, 3);
  tip_task.set_reference(in_plane(d.frames[0].X_WF.translation()), Eigen::Vector2d(0.2, -0.1), Eigen::Vector2d::Zero());
  PostureTask posture(arm.layout(), {0, 1, 2});
  posture.set_reference(VectorXd::Zero(3), (VectorXd(3) << 0.5, -0.5, 0.7).finished(), VectorXd::Zero(3));
  tip_task.update(d);
  posture.update(d);
  PrioritizedIk ik(3, 0, {2, 3});
  const Task* tasks[] = {&tip_task, &posture};
  ik.solve(d, MatrixXd(0, 3), VectorXd(0), tasks);
  const MatrixXd& J1 = tip_task.jacobian();
  const Eigen::Vector2d xd1 = tip_task.error_rate() + J1 * d.v;
  EXPECT_LT((J1 * ik.qd() - xd1).norm(), 1e-12);
  const VectorXd qd1 = J1.completeOrthogonalDecomposition().solve(xd1);
  const MatrixXd Z = J1.fullPivLu().kernel();
  const VectorXd xd2 = posture.error_rate() + d.v;
  const VectorXd z = Z.colPivHouseholderQr().solve(xd2 - qd1);
  EXPECT_LT((ik.qd() - (qd1 + Z * z)).norm(), 1e-10);
}

// A contact that holds joint 0 still (J_c = e₀ᵀ, J̇_c = 0): no task may move it.
TEST(PrioritizedIk, ContactsAreKeptStill) {
  Scene s;
  PrioritizedIk ik(4, 1, {2, 1});
  const MatrixXd J_c = (MatrixXd(1, 4) << 1, 0, 0, 0).finished();
  const Task* tasks[] = {&s.tip_task, &s.joint0};
  ik.solve(s.data, J_c, VectorXd::Zero(1), tasks);
  EXPECT_LT(std::abs(ik.qd()[0]), 1e-14);
  EXPECT_LT(std::abs(ik.qdd()[0]), 1e-13);
  EXPECT_LT(std::abs(ik.delta_q()[0]), 1e-14);
  // The tip task is still met with the three other joints.
  const MatrixXd& J = s.tip_task.jacobian();
  EXPECT_LT((J * ik.qd() - (s.tip_task.error_rate() + J * s.data.v)).norm(), 1e-12);
}

// Stretched out, the tip cannot move along the arm: that row is dropped (singular value
// below 0.003 of the largest), the results stay finite and the movable direction is met.
TEST(PrioritizedIk, SingularTaskIsTruncatedNotAmplified) {
  PlanarArm arm = three_link_arm();
  const int tip = arm.add_frame({"link3", Eigen::Vector3d(link_c().length, 0, 0)});
  const ModelData d = evaluate(arm, (VectorXd(3) << 0.4, 0.0, 0.0).finished(), VectorXd::Zero(3));
  PlanarPointTask tip_task(tip, 3);
  tip_task.set_reference(in_plane(d.frames[0].X_WF.translation()), Eigen::Vector2d(1.0, 1.0), Eigen::Vector2d::Zero());
  tip_task.update(d);
  PrioritizedIk ik(3, 0, {2});
  const Task* tasks[] = {&tip_task};
  ik.solve(d, MatrixXd(0, 3), VectorXd(0), tasks);
  EXPECT_TRUE(ik.qd().allFinite());
  EXPECT_LT(ik.qd().norm(), 10.0);
  // The achievable direction, perpendicular to the arm: u = (−sin q1, −cos q1) in (x, z).
  const Eigen::Vector2d u(-std::sin(0.4), -std::cos(0.4));
  const Eigen::Vector2d achieved = tip_task.jacobian() * ik.qd();
  EXPECT_NEAR(u.dot(achieved), u.dot(Eigen::Vector2d(1.0, 1.0)), 1e-12);
}

TEST(PrioritizedIk, NoAllocationInASolve) {
  DMBD_SKIP_UNDER_ASAN();
  Scene s;
  PrioritizedIk ik(4, 1, {2, 1});
  const MatrixXd J_c = (MatrixXd(1, 4) << 0, 0, 0, 1).finished();
  const VectorXd Jc_dot_v = VectorXd::Zero(1);
  const Task* tasks[] = {&s.tip_task, &s.joint0};
  ik.solve(s.data, J_c, Jc_dot_v, tasks);  // warm-up
  const long before = dmbd::test::allocations();
  for (int k = 0; k < 100; ++k) ik.solve(s.data, J_c, Jc_dot_v, tasks);
  EXPECT_EQ(dmbd::test::allocations() - before, 0);
}

}  // namespace
}  // namespace dmbd::wholebody::testing
