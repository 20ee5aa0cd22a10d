// Operational space control (osc.hpp) on the hand-derived planar arms, with their exact
// forward dynamics q̈ = A⁻¹(τ − b − g): the task acceleration J q̈ + J̇ v is the command
// ẍ_cmd (decoupled response); the law equals A J̄ (ẍ_cmd − J̇ v) + b + g; the closed loop
// (RK4) follows the analytic critically damped error e(t) = (e0 + (ė0 + ω e0) t) e^{−ωt}
// per axis, also on a moving reference; a posture task acts only in the task's null space
// (its torque is Nᵀ J_pᵀ Λ_p ẍ_cmd,p, it moves no task coordinate) and converges while
// the tip tracks.
#include <gtest/gtest.h>

#include <Eigen/LU>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "arm_fixtures.hpp"
#include "dmbd/base/error.hpp"
#include "dmbd/wholebody/osc.hpp"
#include "dmbd/wholebody/task.hpp"
#include "planar_point_task.hpp"
#include "two_link_arm.hpp"

namespace dmbd::wholebody::testing {
namespace {

// One-step checks compare quantities formed with A⁻¹ two ways (the library's Cholesky
// and Λ, a dense LU here): A's condition number is ≲ 1e3 on these arms away from a
// singularity, so ~1e-13 relative; 1e-9 leaves a wide margin, and any error in a term
// (a missing J̇v, b, g, a transposed N) is O(1).
constexpr double kRelTol = 1e-9;

// The arm with its tip registered (frame 0).
template <class Arm>
Arm with_tip(Arm arm) {
  arm.add_frame({"link" + std::to_string(arm.size()), Eigen::Vector3d(arm.link(arm.size() - 1).length, 0, 0)});
  return arm;
}

Eigen::VectorXd osc_torque(OperationalSpaceControl& osc, const ModelData& d, const Task& task, const Task* posture) {
  Eigen::VectorXd tau(d.v.size());
  osc.compute(d, task, posture, tau);
  return tau;
}

Eigen::MatrixXd closed_form_Jbar(const Eigen::MatrixXd& A, const Eigen::MatrixXd& J) {
  const Eigen::MatrixXd A_inv = A.inverse();
  return A_inv * J.transpose() * (J * A_inv * J.transpose()).inverse();
}

TEST(OperationalSpaceControl, RejectsAFloatingBase) {
  Layout l;
  l.base_dofs = 6;
  l.nq = 7;
  l.nv = 6;
  EXPECT_THROW(OperationalSpaceControl(l, 3), InputError);
}

TEST(OperationalSpaceControl, TaskAccelerationIsTheCommand) {
  TwoLinkArm arm = with_tip(two_link_arm());
  OperationalSpaceControl osc(arm.layout(), 2);
  PlanarPointTask task(0, 2);
  task.set_gains(Eigen::Vector2d(100, 60), Eigen::Vector2d(20, 15));
  std::mt19937 rng(21);
  for (int k = 0; k < 20; ++k) {
    // Away from the singularities q2 ∈ {0, π}: q2 ∈ [0.3, 2.8] (either sign).
    Eigen::VectorXd q = uniform(rng, 2, M_PI);
    q[1] = (k % 2 ? 1 : -1) * (0.3 + 2.5 * std::abs(q[1]) / M_PI);
    const ModelData d = evaluate(arm, q, uniform(rng, 2, 3.0));
    task.set_reference(uniform(rng, 2, 1.0), uniform(rng, 2, 1.0), uniform(rng, 2, 5.0));
    task.update(d);
    const Eigen::VectorXd tau = osc_torque(osc, d, task, nullptr);
    const Eigen::VectorXd qdd = forward_dynamics(d, tau);
    const Eigen::VectorXd xdd = task.jacobian() * qdd + task.jacobian_dot_v();
    const double scale = task.command().norm() + task.jacobian_dot_v().norm();
    EXPECT_LT((xdd - task.command()).norm(), kRelTol * scale) << "state " << k;
    // The law's two forms: Jᵀ F + b + g = A J̄ (ẍ_cmd − J̇ v) + b + g, F = Λ (ẍ_cmd − J̇ v).
    const Eigen::VectorXd a = task.command() - task.jacobian_dot_v();
    const Eigen::VectorXd tau_closed = d.A * closed_form_Jbar(d.A, task.jacobian()) * a + d.bg;
    EXPECT_LT((tau - tau_closed).norm(), kRelTol * tau_closed.norm()) << "state " << k;
    const Eigen::MatrixXd A_inv = d.A.inverse();
    const Eigen::VectorXd F = (task.jacobian() * A_inv * task.jacobian().transpose()).inverse() * a;
    EXPECT_LT((osc.task_force() - F).norm(), kRelTol * F.norm());
  }
}

TEST(OperationalSpaceControl, PointTaskGivesThePlanarTorque) {
  // PointTask's y row cannot move (the arm is in the x-z plane): the inverse drops it and
  // the torque is the planar task's, whatever the y reference asks.
  PlanarArm arm = with_tip(three_link_arm());
  const ModelData d = evaluate(arm, Eigen::Vector3d(0.2, 0.8, -0.5), Eigen::Vector3d(0.5, -1.0, 1.5));
  PointTask point(0, 3);
  PlanarPointTask planar(0, 3);
  point.set_reference({0.9, 0.3, -0.4}, {0.1, 0.2, 0.3}, {1.0, -2.0, 0.5});
  planar.set_reference({0.9, -0.4}, {0.1, 0.3}, {1.0, 0.5});
  point.set_gains(50, 10);
  planar.set_gains(50, 10);
  point.update(d);
  planar.update(d);
  OperationalSpaceControl osc3(arm.layout(), 3), osc2(arm.layout(), 2);
  const Eigen::VectorXd tau3 = osc_torque(osc3, d, point, nullptr), tau2 = osc_torque(osc2, d, planar, nullptr);
  EXPECT_EQ(osc3.inverse().rank(), 2);
  EXPECT_LT((tau3 - tau2).norm(), kRelTol * tau2.norm()) << tau3.transpose() << " vs " << tau2.transpose();
}

TEST(OperationalSpaceControl, SingularTaskGivesAFiniteTorque) {
  // Stretched out (q2 = 0) the tip cannot move along the arm: that row is dropped and the
  // torque stays finite (and equal to gravity compensation plus the movable row's force).
  TwoLinkArm arm = with_tip(two_link_arm());
  const ModelData d = evaluate(arm, Eigen::Vector2d(0.3, 0.0), Eigen::Vector2d::Zero());
  PlanarPointTask task(0, 2);
  task.set_reference(Eigen::Vector2d(2.0, 2.0), Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero());  // out of reach
  task.set_gains(100, 20);
  task.update(d);
  OperationalSpaceControl osc(arm.layout(), 2);
  const Eigen::VectorXd tau = osc_torque(osc, d, task, nullptr);
  EXPECT_EQ(osc.inverse().rank(), 1);
  EXPECT_TRUE(tau.allFinite());
  EXPECT_LT((tau - d.bg).norm(), 1e3);  // ~1e2 N m (a ~100 N force on a 0.9 m arm), not ~1e16
}

// Simulated error of a critically damped tip task against the analytic solution.
struct TrackingRun {
  double max_deviation = 0.0;  // |e_sim − e_analytic| over the run, per axis, m
  double max_error = 0.0;      // |e_sim| over the run (the scale), m
  double final_error = 0.0;    // |e_sim| at the end, m
  int min_rank = 2;
};

// The reference: a circle of radius r at `rate` rad/s through x_d(0) = c, in (x, z)
// (r = 0: a fixed target).
struct Circle {
  Eigen::Vector2d c;
  double r = 0.0, rate = 0.0;
  Eigen::Vector2d p(double t) const { return c + r * Eigen::Vector2d(std::cos(rate * t) - 1, std::sin(rate * t)); }
  Eigen::Vector2d v(double t) const { return r * rate * Eigen::Vector2d(-std::sin(rate * t), std::cos(rate * t)); }
  Eigen::Vector2d a(double t) const {
    return -r * rate * rate * Eigen::Vector2d(std::cos(rate * t), std::sin(rate * t));
  }
};

// The tip of `arm` (frame 0) at q, in (x, z).
Eigen::Vector2d tip_at(PlanarArm& arm, const Eigen::VectorXd& q) {
  return in_plane(evaluate(arm, q, Eigen::VectorXd::Zero(q.size())).frames[0].X_WF.translation());
}

// Runs the tip task (gains ω², 2ω) with an optional posture task for `seconds` from
// (q, v), RK4 at dt; q and v end at the final state.
TrackingRun track(PlanarArm& arm, const Circle& ref, double omega, PostureTask* posture, double seconds, double dt,
                  Eigen::VectorXd& q, Eigen::VectorXd& v) {
  const int n = arm.size();
  PlanarPointTask task(0, n);
  task.set_gains(omega * omega, 2 * omega);
  OperationalSpaceControl osc(arm.layout(), 2, posture ? posture->dim() : 0);
  TrackingRun run;
  const TorqueLaw law = [&](double t, const ModelData& d) {
    task.set_reference(ref.p(t), ref.v(t), ref.a(t));
    task.update(d);
    if (posture) posture->update(d);
    const Eigen::VectorXd tau = osc_torque(osc, d, task, posture);
    run.min_rank = std::min(run.min_rank, osc.inverse().rank());
    return tau;
  };
  auto error = [&](double t, Eigen::Vector2d& e, Eigen::Vector2d& edot) {
    const ModelData d = evaluate(arm, q, v);
    task.set_reference(ref.p(t), ref.v(t), ref.a(t));
    task.update(d);
    e = task.error();
    edot = task.error_rate();
  };
  Eigen::Vector2d e0, edot0, e, edot;
  error(0.0, e0, edot0);
  const int steps = static_cast<int>(std::lround(seconds / dt));
  for (int k = 0; k < steps; ++k) {
    rk4_step(arm, law, k * dt, dt, q, v);
    const double t = (k + 1) * dt;
    error(t, e, edot);
    const Eigen::Vector2d analytic = ((e0 + (edot0 + omega * e0) * t) * std::exp(-omega * t)).eval();
    run.max_deviation = std::max(run.max_deviation, (e - analytic).cwiseAbs().maxCoeff());
    run.max_error = std::max(run.max_error, e.cwiseAbs().maxCoeff());
  }
  run.final_error = e.norm();
  return run;
}

// With exact dynamics the simulated error differs from the analytic one only by RK4's
// global error, O(dt⁴): at dt = 1 ms it measures ~1e-11 m on a ~0.1 m transient (the bound
// (ω dt)⁴ |e0| = 1e-9 m is pessimistic). 1e-9 m is 1e-8 of the transient and a margin of
// ~100 over the measurement; a missing J̇v, b + g or feed-forward gives > 1e-4 m.
constexpr double kTrackingTol = 1e-9;

TEST(OperationalSpaceControl, ClosedLoopIsCriticallyDampedPerAxis) {
  TwoLinkArm arm = with_tip(two_link_arm());
  Eigen::VectorXd q_target = Eigen::Vector2d(0.7, 0.6), q = Eigen::Vector2d(0.4, 1.2), v = Eigen::Vector2d(0.5, -0.3);
  const Circle fixed{tip_at(arm, q_target), 0.0, 0.0};
  const TrackingRun run = track(arm, fixed, 10.0, nullptr, 1.0, 1e-3, q, v);
  EXPECT_EQ(run.min_rank, 2);
  EXPECT_GT(run.max_error, 0.05);  // a real transient
  EXPECT_LT(run.max_deviation, kTrackingTol) << "scale " << run.max_error;
  EXPECT_LT(run.final_error, 1e-2 * run.max_error);
  // The tip's error at 1 s (~5e-5 m) is ~5e-4 rad through J⁻¹; the other elbow solution
  // for the same tip is > 1 rad away: the arm converged to q_target's branch.
  EXPECT_LT((q - q_target).norm(), 1e-2);
}

TEST(OperationalSpaceControl, ClosedLoopFollowsAMovingReference) {
  // ẍ_d and ẋ_d enter the law: with them the error obeys the same linear ODE.
  TwoLinkArm arm = with_tip(two_link_arm());
  Eigen::VectorXd q = Eigen::Vector2d(0.4, 1.2), v = Eigen::Vector2d(0.0, 0.0);
  const Circle circle{tip_at(arm, Eigen::Vector2d(0.7, 0.6)), 0.1, 2.0};
  const TrackingRun run = track(arm, circle, 10.0, nullptr, 1.0, 1e-3, q, v);
  EXPECT_EQ(run.min_rank, 2);
  EXPECT_LT(run.max_deviation, kTrackingTol) << "scale " << run.max_error;
}

TEST(OperationalSpaceControl, PostureTorqueIsProjectedIntoTheNullSpace) {
  // τ_with − τ_without = Nᵀ J_pᵀ Λ_p ẍ_cmd,p (J̇_p = 0), N = I − J̄ J from dense inverses;
  // it moves no task coordinate: J A⁻¹ (τ_with − τ_without) = 0.
  PlanarArm arm = with_tip(three_link_arm());
  const ModelData d = evaluate(arm, Eigen::Vector3d(0.2, 0.8, -0.5), Eigen::Vector3d(0.5, -1.0, 1.5));
  PlanarPointTask task(0, 3);
  task.set_reference(Eigen::Vector2d(0.9, -0.4), Eigen::Vector2d(0.1, 0.3), Eigen::Vector2d(1.0, 0.5));
  task.set_gains(100, 20);
  task.update(d);
  const Eigen::MatrixXd A_inv = d.A.inverse(), &J = task.jacobian();
  const Eigen::MatrixXd N = Eigen::MatrixXd::Identity(3, 3) - closed_form_Jbar(d.A, J) * J;
  OperationalSpaceControl plain(arm.layout(), 2);
  const Eigen::VectorXd tau_without = osc_torque(plain, d, task, nullptr);
  for (const std::vector<int>& joints : {std::vector<int>{0, 1, 2}, std::vector<int>{2, 0}}) {
    PostureTask posture(arm.layout(), joints);
    const int m = posture.dim();
    posture.set_reference(Eigen::VectorXd::Constant(m, 0.4), Eigen::VectorXd::Zero(m), Eigen::VectorXd::Zero(m));
    posture.set_gains(16, 8);
    posture.update(d);
    OperationalSpaceControl osc(arm.layout(), 2, m);
    const Eigen::VectorXd delta = osc_torque(osc, d, task, &posture) - tau_without;
    const Eigen::MatrixXd& Jp = posture.jacobian();
    const Eigen::MatrixXd Lambda_p = (Jp * A_inv * Jp.transpose()).inverse();
    const Eigen::VectorXd expected = N.transpose() * Jp.transpose() * Lambda_p * posture.command();
    SCOPED_TRACE("posture of " + std::to_string(m) + " joints");
    EXPECT_GT(delta.norm(), 0.1);  // not vacuous
    EXPECT_LT((delta - expected).norm(), kRelTol * expected.norm());
    EXPECT_LT((J * A_inv * delta).norm(), kRelTol * J.norm() * (A_inv * delta).norm());
  }
}

TEST(OperationalSpaceControl, PostureConvergesInTheNullSpaceWhileTheTipTracks) {
  // The tip's target is the tip of the posture target q_p, so both can be met. The tip
  // error still follows the analytic response (the posture cannot disturb it); the
  // posture error decays.
  PlanarArm arm = with_tip(three_link_arm());
  const Eigen::VectorXd q_p = Eigen::Vector3d(0.3, 0.9, 0.6);
  Eigen::VectorXd q = Eigen::Vector3d(0.6, 0.5, 1.0), v = Eigen::Vector3d::Zero();
  const Circle fixed{tip_at(arm, q_p), 0.0, 0.0};
  PostureTask posture(arm.layout(), {0, 1, 2});
  posture.set_reference(q_p, Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(3));
  posture.set_gains(16, 8);  // ω = 4 rad/s, critically damped in joint space
  const double initial = (q - q_p).norm();
  std::vector<double> posture_error;
  for (int second = 0; second < 3; ++second) {
    const TrackingRun run = track(arm, fixed, 10.0, &posture, 1.0, 1e-3, q, v);
    // Each second restarts the analytic response from that second's e0, ė0.
    EXPECT_EQ(run.min_rank, 2);
    EXPECT_LT(run.max_deviation, kTrackingTol) << "second " << second << ", scale " << run.max_error;
    posture_error.push_back((q - q_p).norm());
  }
  EXPECT_LT(posture_error[0], 0.5 * initial);
  EXPECT_LT(posture_error[1], 0.5 * posture_error[0]);
  EXPECT_LT(posture_error[2], 1e-2 * initial) << posture_error[0] << " " << posture_error[1];
}

}  // namespace
}  // namespace dmbd::wholebody::testing
