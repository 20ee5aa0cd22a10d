// Prioritised inverse kinematics (wholebody/prioritized_ik.hpp) on the planar test arms:
// compatible tasks all met exactly (configuration step, rates, accelerations); a lower
// task never disturbs a higher one; a conflicting lower task gets the least-squares
// best in the higher one's null space (against an independent null-space basis); the
// contacts are kept still; a singular arm gives finite results; with weights
// (set_weights) the weighted least-norm solution, the priorities and contacts kept, a
// W-orthogonal null space, unit weights as the default, bad weights rejected; no
// allocation in a solve.
// This executable counts allocations (malloc_counter.hpp).
#include <gtest/gtest.h>

#include "malloc_counter.hpp"

#include <Eigen/LU>
#include <Eigen/QR>

#include <cmath>
#include <initializer_list>
#include <limits>
#include <random>
#include <vector>

#include "arm_fixtures.hpp"
#include "dmbd/base/error.hpp"
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

// --- Weights (set_weights): J⁺ = W⁻¹Jᵀ(JW⁻¹Jᵀ)⁺, W = diag w ------------------------------

// Spread over a factor 36, so the weighted and unweighted solutions differ visibly.
VectorXd four_weights() { return (VectorXd(4) << 1.0, 4.0, 0.25, 9.0).finished(); }

// The least Σ w_i x_i² solution of J x = r in closed form, W⁻¹Jᵀ(JW⁻¹Jᵀ)⁻¹ r (J of full
// row rank), with a dense LU (independent of the library's Cholesky and SVD).
VectorXd weighted_least_norm(const MatrixXd& J, const VectorXd& w, const VectorXd& r) {
  const MatrixXd Winv_Jt = w.cwiseInverse().asDiagonal() * J.transpose();
  return Winv_Jt * (J * Winv_Jt).partialPivLu().solve(r);
}

double weighted_norm2(const VectorXd& x, const VectorXd& w) { return x.cwiseProduct(x).dot(w); }

// One task, no contact: Δq, q̇ and q̈ are the weighted least-norm solutions of the
// task's three equations (1e-12 relative to each right-hand side's solution: the two
// constructions round differently at ~1e-15 and J W⁻¹ Jᵀ is well conditioned here), and
// not the unweighted ones.
TEST(PrioritizedIk, WeightedSingleTaskIsTheWeightedLeastNormSolution) {
  Scene s;
  const VectorXd w = four_weights();
  PrioritizedIk weighted(4, 0, {2}), plain(4, 0, {2});
  weighted.set_weights(w);
  const Task* tasks[] = {&s.tip_task};
  weighted.solve(s.data, MatrixXd(0, 4), VectorXd(0), tasks);
  plain.solve(s.data, MatrixXd(0, 4), VectorXd(0), tasks);
  const Task& t = s.tip_task;
  const MatrixXd& J = t.jacobian();
  const VectorXd dq = weighted_least_norm(J, w, t.error());
  const VectorXd qd = weighted_least_norm(J, w, t.error_rate() + J * s.data.v);
  const VectorXd qdd = weighted_least_norm(J, w, t.command() - t.jacobian_dot_v());
  EXPECT_LT((weighted.delta_q() - dq).norm(), 1e-12 * dq.norm());
  EXPECT_LT((weighted.qd() - qd).norm(), 1e-12 * qd.norm());
  EXPECT_LT((weighted.qdd() - qdd).norm(), 1e-12 * qdd.norm());
  // Unweighted, Δq is another solution of J Δq = e with a larger weighted norm.
  // Measured: |Δq_w − Δq| = 0.0373 for |Δq| = 0.0502 (74 %); Σ w Δq² 0.00189 against
  // 0.00906; the closed forms agree to ~5e-16 relative.
  EXPECT_GT((weighted.delta_q() - plain.delta_q()).norm(), 0.3 * plain.delta_q().norm());
  EXPECT_LT((J * plain.delta_q() - t.error()).norm(), 1e-12);
  EXPECT_LT(weighted_norm2(weighted.delta_q(), w), weighted_norm2(plain.delta_q(), w));
}

// A six-link arm held at its third link's end (a 2-D contact, J̇_c v ≠ 0), a tip task
// above a posture task of joint 0, with weights: 2 + 2 + 1 rows of 6 leave one degree of
// freedom, so the weights change the solution.
struct HeldArm {
  PlanarArm arm = PlanarArm({link_a(), link_b(), link_c(), link_a(), link_b(), link_c()});
  int tip = arm.add_frame({"link6", Eigen::Vector3d(link_c().length, 0, 0)});
  int held = arm.add_frame({"link3", Eigen::Vector3d(link_c().length, 0, 0)});
  ModelData data;
  PlanarPointTask tip_task{tip, 6}, contact{held, 6};  // contact: its J and J̇v are J_c, J̇_c v
  PostureTask joint0{arm.layout(), {0}};
  VectorXd w = (VectorXd(6) << 1.0, 9.0, 0.5, 4.0, 0.2, 2.0).finished();
  HeldArm() {
    data = evaluate(arm, (VectorXd(6) << 0.3, -0.6, 0.8, 0.4, -0.5, 0.7).finished(),
                    (VectorXd(6) << 0.5, -0.2, 0.8, -0.6, 0.3, 0.4).finished());
    tip_task.set_reference(in_plane(data.frames[0].X_WF.translation()) + Eigen::Vector2d(0.02, 0.01),
                           Eigen::Vector2d(0.2, -0.3), Eigen::Vector2d(1.0, 0.5));
    tip_task.set_gains(100.0, 20.0);
    joint0.set_reference(VectorXd::Constant(1, 0.35), VectorXd::Constant(1, 0.2), VectorXd::Constant(1, -1.0));
    joint0.set_gains(50.0, 10.0);
    for (Task* t : std::initializer_list<Task*>{&tip_task, &contact, &joint0}) t->update(data);
  }
  // Solved with the given tasks, weighted or not.
  PrioritizedIk solve(const std::vector<const Task*>& tasks, bool weighted) const {
    std::vector<int> dims;
    for (const Task* t : tasks) dims.push_back(t->dim());
    PrioritizedIk ik(6, 2, dims);
    if (weighted) ik.set_weights(w);
    ik.solve(data, contact.jacobian(), contact.jacobian_dot_v(), tasks.data());
    return ik;
  }
};

// With weights: the contact is kept (J_c Δq = 0, J_c q̇ = 0, J_c q̈ + J̇_c v = 0), the
// higher task is met exactly and the lower one does not disturb it (J_tip of the
// difference to a solve without it), the lower one is met with what is left; the
// weights did change the solution. Tolerance 1e-11: q̈ is of order 40 here (the tip's
// acceleration residual measured 4.6e-13, the others ≲ 1e-13).
TEST(PrioritizedIk, WeightedPrioritiesAndContactsHold) {
  const HeldArm h;
  const PrioritizedIk two = h.solve({&h.tip_task, &h.joint0}, true);
  const PrioritizedIk one = h.solve({&h.tip_task}, true);
  const MatrixXd& J_c = h.contact.jacobian();
  const double tol = 1e-11;
  EXPECT_LT((J_c * two.delta_q()).norm(), tol);
  EXPECT_LT((J_c * two.qd()).norm(), tol);
  EXPECT_LT((J_c * two.qdd() + h.contact.jacobian_dot_v()).norm(), tol);
  expect_met(h.tip_task, h.data, two, tol);
  expect_met(h.joint0, h.data, two, tol);
  const MatrixXd& J = h.tip_task.jacobian();
  EXPECT_LT((J * (two.delta_q() - one.delta_q())).norm(), tol);
  EXPECT_LT((J * (two.qd() - one.qd())).norm(), tol);
  EXPECT_LT((J * (two.qdd() - one.qdd())).norm(), tol);
  EXPECT_GT((two.delta_q() - one.delta_q()).norm(), 0.05);  // the lower task did move the arm (0.109)
  // Measured, weighted against unweighted: |ΔΔq| = 0.0603 (|Δq| = 0.122), |Δq̇| = 1.42
  // (|q̇| = 3.26), |Δq̈| = 11.6 (|q̈| = 37.6).
  const PrioritizedIk plain = h.solve({&h.tip_task, &h.joint0}, false);
  EXPECT_GT((two.delta_q() - plain.delta_q()).norm(), 0.02);
  EXPECT_GT((two.qd() - plain.qd()).norm(), 0.5);
}

// The null space after the tasks is a W-orthogonal projector: N² = N and W N symmetric
// (1e-12: entries of order 1; measured 5e-14 and 1.4e-14), and it moves neither the
// contact nor the task.
TEST(PrioritizedIk, WeightedNullSpaceIsAWOrthogonalProjector) {
  const HeldArm h;
  const PrioritizedIk ik = h.solve({&h.tip_task}, true);
  const MatrixXd& N = ik.null_space();
  const MatrixXd WN = h.w.asDiagonal() * N;
  EXPECT_LT((N * N - N).norm(), 1e-12);
  EXPECT_LT((WN - WN.transpose()).norm(), 1e-12);
  EXPECT_LT((h.contact.jacobian() * N).norm(), 1e-12);
  EXPECT_LT((h.tip_task.jacobian() * N).norm(), 1e-12);
  EXPECT_GT((N - N.transpose()).norm(), 0.5);  // not an orthogonal projector (measured 2.11)
}

// All-ones weights are the default: the same results, bit for bit (the Cholesky factor
// of I is I either way), with a contact and two tasks.
TEST(PrioritizedIk, UnitWeightsAreTheDefault) {
  const HeldArm h;
  PrioritizedIk ones(6, 2, {2, 1}), never(6, 2, {2, 1});
  ones.set_weights(VectorXd::Ones(6));
  const Task* tasks[] = {&h.tip_task, &h.joint0};
  ones.solve(h.data, h.contact.jacobian(), h.contact.jacobian_dot_v(), tasks);
  never.solve(h.data, h.contact.jacobian(), h.contact.jacobian_dot_v(), tasks);
  EXPECT_EQ(ones.delta_q(), never.delta_q());
  EXPECT_EQ(ones.qd(), never.qd());
  EXPECT_EQ(ones.qdd(), never.qdd());
  EXPECT_EQ(ones.null_space(), never.null_space());
}

TEST(PrioritizedIk, RejectsWeightsOfTheWrongSizeOrNotPositiveAndFinite) {
  PrioritizedIk ik(4, 0, {2});
  EXPECT_THROW(ik.set_weights(VectorXd::Ones(3)), InputError);
  EXPECT_THROW(ik.set_weights(VectorXd::Ones(5)), InputError);
  const double bad[] = {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()};
  for (const double b : bad) {
    VectorXd w = VectorXd::Ones(4);
    w[2] = b;
    EXPECT_THROW(ik.set_weights(w), InputError) << b;
  }
  EXPECT_NO_THROW(ik.set_weights(four_weights()));
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
