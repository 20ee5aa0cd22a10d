// DynamicallyConsistentInverse (projection.hpp): at full rank the identities of the
// A-weighted pseudo-inverse (J J̄ = I, N² = N, J N = 0, J A⁻¹ Nᵀ = 0, N A⁻¹ = A⁻¹ Nᵀ) and
// J̄, Λ against the closed form with dense inverses; at a singular configuration of the
// two-link arm (stretched out, q2 = 0) the dropped row, the finite result and the
// truncated Λ against its hand value; the threshold relative to the largest eigenvalue.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <cmath>
#include <random>

#include "arm_fixtures.hpp"
#include "dmbd/wholebody/projection.hpp"
#include "dmbd/wholebody/task.hpp"
#include "planar_point_task.hpp"
#include "two_link_arm.hpp"

namespace dmbd::wholebody::testing {
namespace {

// A = BᵀB + I: symmetric, eigenvalues in [1, ~nv²/3 + 1]; condition number ≲ 20 for
// nv = 7, so products of O(1) matrices and A⁻¹ round at ~1e-15: 1e-12 is a margin of ~100.
Eigen::MatrixXd random_spd(std::mt19937& rng, int n) {
  Eigen::MatrixXd B(n, n);
  for (int i = 0; i < n; ++i) B.col(i) = uniform(rng, n, 1.0);
  return B.transpose() * B + Eigen::MatrixXd::Identity(n, n);
}

Eigen::MatrixXd random_jacobian(std::mt19937& rng, int m, int n) {
  Eigen::MatrixXd J(m, n);
  for (int i = 0; i < n; ++i) J.col(i) = uniform(rng, m, 1.0);
  return J;
}

void expect_full_rank_identities(const Eigen::MatrixXd& A, const Eigen::MatrixXd& J, double tol) {
  const int m = static_cast<int>(J.rows()), n = static_cast<int>(J.cols());
  DynamicallyConsistentInverse dci(m, n);
  dci.compute(A, J);
  const Eigen::MatrixXd A_inv = A.inverse(), &Jbar = dci.Jbar(), &N = dci.N();
  const Eigen::MatrixXd I_m = Eigen::MatrixXd::Identity(m, m);
  EXPECT_EQ(dci.rank(), m);
  EXPECT_LT((J * Jbar - I_m).norm(), tol);
  EXPECT_LT((N * N - N).norm(), tol);
  EXPECT_LT((J * N).norm(), tol * J.norm());
  EXPECT_LT((J * A_inv * N.transpose()).norm(), tol * (J * A_inv).norm());
  EXPECT_LT((N * A_inv - A_inv * N.transpose()).norm(), tol * A_inv.norm());
  // The closed form, with dense inverses computed independently.
  const Eigen::MatrixXd Lambda = (J * A_inv * J.transpose()).inverse();
  const Eigen::MatrixXd Jbar_closed = A_inv * J.transpose() * Lambda;
  EXPECT_LT((Jbar - Jbar_closed).norm(), tol * Jbar_closed.norm());
  EXPECT_LT((dci.Lambda() - Lambda).norm(), tol * Lambda.norm());
  EXPECT_LT((dci.A_inv_Jt() - A_inv * J.transpose()).norm(), tol * (A_inv * J.transpose()).norm());
  EXPECT_LT((N - (Eigen::MatrixXd::Identity(n, n) - Jbar_closed * J)).norm(), tol * N.norm());
  const Eigen::VectorXd y = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  Eigen::VectorXd x(n);
  dci.solve_A(y, x);
  EXPECT_LT((x - A_inv * y).norm(), tol * (A_inv * y).norm());
}

TEST(DynamicallyConsistentInverse, FullRankIdentitiesOnRandomMatrices) {
  std::mt19937 rng(3);
  for (int k = 0; k < 20; ++k) {
    const int n = 7, m = 1 + k % 4;
    expect_full_rank_identities(random_spd(rng, n), random_jacobian(rng, m, n), 1e-12);
  }
}

TEST(DynamicallyConsistentInverse, FullRankIdentitiesOnTheThreeLinkArm) {
  // The arm's A (eigenvalues ~1e-2 to 1) and the tip's in-plane rows, away from a
  // singularity: A's condition number ~100, hence the tolerance 1e-11.
  PlanarArm arm = three_link_arm();
  const int tip = arm.add_frame({"link3", Eigen::Vector3d(link_c().length, 0, 0)});
  const ModelData d = evaluate(arm, Eigen::Vector3d(0.3, 0.9, -0.6), Eigen::Vector3d::Zero());
  PlanarPointTask task(tip, 3);
  task.update(d);
  expect_full_rank_identities(d.A, task.jacobian(), 1e-11);
}

TEST(DynamicallyConsistentInverse, ReusedObjectForgetsThePreviousCall) {
  std::mt19937 rng(4);
  const Eigen::MatrixXd A1 = random_spd(rng, 5), A2 = random_spd(rng, 5);
  const Eigen::MatrixXd J1 = random_jacobian(rng, 2, 5), J2 = random_jacobian(rng, 2, 5);
  DynamicallyConsistentInverse reused(2, 5), fresh(2, 5);
  reused.compute(A1, J1);
  reused.compute(A2, J2);
  fresh.compute(A2, J2);
  EXPECT_EQ(reused.Jbar(), fresh.Jbar());
  EXPECT_EQ(reused.N(), fresh.N());
}

// The two-link arm's tip, rows (x, z), at (q1, q2), and A there.
struct ArmTip {
  Eigen::MatrixXd A, J;
};
ArmTip arm_tip(double q1, double q2) {
  TwoLinkArm arm = two_link_arm();
  const int tip = arm.add_frame({"link2", Eigen::Vector3d(link_b().length, 0, 0)});
  const ModelData d = evaluate(arm, Eigen::Vector2d(q1, q2), Eigen::Vector2d::Zero());
  PlanarPointTask task(tip, 2);
  task.update(d);
  return {d.A, task.jacobian()};
}

TEST(DynamicallyConsistentInverse, SingularStretchedArmKeepsTheMovableDirection) {
  // Stretched out (q2 = 0) the tip moves only perpendicular to the arm: in (x, z),
  // u = (−sin q1, −cos q1). J A⁻¹ Jᵀ = μ u uᵀ with μ = uᵀ J A⁻¹ Jᵀ u, so the truncated
  // Λ = u uᵀ / μ and J J̄ = u uᵀ (a rank-1 orthogonal projector). J's rank deficiency is
  // exact up to rounding (its 2 x 2 determinant ~1e-17): 1e-9 relative.
  const double q1 = 0.3;
  const ArmTip a = arm_tip(q1, 0.0);
  DynamicallyConsistentInverse dci(2, 2);
  dci.compute(a.A, a.J);
  EXPECT_EQ(dci.rank(), 1);
  EXPECT_TRUE(dci.Jbar().allFinite());
  EXPECT_TRUE(dci.N().allFinite());
  const Eigen::Vector2d u(-std::sin(q1), -std::cos(q1));
  const double mu = u.dot(a.J * a.A.inverse() * a.J.transpose() * u);
  const Eigen::Matrix2d Lambda = u * u.transpose() / mu;
  EXPECT_LT((dci.Lambda() - Lambda).norm(), 1e-9 * Lambda.norm()) << dci.Lambda();
  EXPECT_LT((a.J * dci.Jbar() - u * u.transpose()).norm(), 1e-9);
  EXPECT_LT((dci.N() * dci.N() - dci.N()).norm(), 1e-9);
  EXPECT_LT((a.J * dci.N()).norm(), 1e-9 * a.J.norm());  // uᵀ⊥ J = 0: J N = 0 still
}

TEST(DynamicallyConsistentInverse, NearSingularRowsAreDroppedNotAmplified) {
  // At q2 = 1e-7 the small eigenvalue of J A⁻¹ Jᵀ is ~(l1 l2 q2)² ≈ 1e-16 of the largest,
  // below the threshold 1e-9: dropped, so J̄ is the singular one up to O(q2), where
  // the exact inverse would be ~1e7 times larger.
  const ArmTip s = arm_tip(0.3, 0.0), n = arm_tip(0.3, 1e-7);
  DynamicallyConsistentInverse singular(2, 2), near(2, 2);
  singular.compute(s.A, s.J);
  near.compute(n.A, n.J);
  EXPECT_EQ(near.rank(), 1);
  EXPECT_LT((near.Jbar() - singular.Jbar()).norm(), 1e-5 * singular.Jbar().norm());
  const Eigen::MatrixXd exact = n.A.inverse() * n.J.transpose() * (n.J * n.A.inverse() * n.J.transpose()).inverse();
  EXPECT_GT(exact.norm(), 1e5 * near.Jbar().norm());
  // Bent enough (q2 = 0.1: eigenvalue ratio ~1e-3) both rows are kept.
  const ArmTip b = arm_tip(0.3, 0.1);
  DynamicallyConsistentInverse bent(2, 2);
  bent.compute(b.A, b.J);
  EXPECT_EQ(bent.rank(), 2);
}

TEST(DynamicallyConsistentInverse, ThresholdIsRelativeToTheLargestEigenvalue) {
  // Scaling J by s scales J A⁻¹ Jᵀ by s²: the kept rows do not change and J̄ scales by 1/s.
  std::mt19937 rng(5);
  const Eigen::MatrixXd A = random_spd(rng, 6), J = random_jacobian(rng, 3, 6);
  DynamicallyConsistentInverse unit(3, 6);
  unit.compute(A, J);
  for (const double s : {1e-6, 1e6}) {
    DynamicallyConsistentInverse scaled(3, 6);
    scaled.compute(A, s * J);
    EXPECT_EQ(scaled.rank(), 3) << "s " << s;
    EXPECT_LT((s * scaled.Jbar() - unit.Jbar()).norm(), 1e-12 * unit.Jbar().norm()) << "s " << s;
  }
}

TEST(DynamicallyConsistentInverse, PointTaskOnAPlanarArmDropsTheOutOfPlaneRow) {
  // PointTask's y row of an arm in the x-z plane is zero: rank 2, and J̄'s x and z columns
  // are the planar task's J̄ (its y column zero).
  PlanarArm arm = three_link_arm();
  const int tip = arm.add_frame({"link3", Eigen::Vector3d(link_c().length, 0, 0)});
  const ModelData d = evaluate(arm, Eigen::Vector3d(0.3, 0.9, -0.6), Eigen::Vector3d::Zero());
  PointTask point(tip, 3);
  PlanarPointTask planar(tip, 3);
  point.update(d);
  planar.update(d);
  DynamicallyConsistentInverse p3(3, 3), p2(2, 3);
  p3.compute(d.A, point.jacobian());
  p2.compute(d.A, planar.jacobian());
  EXPECT_EQ(p3.rank(), 2);
  EXPECT_LT(p3.Jbar().col(1).norm(), 1e-12);
  EXPECT_LT((p3.Jbar().col(0) - p2.Jbar().col(0)).norm(), 1e-11 * p2.Jbar().norm());
  EXPECT_LT((p3.Jbar().col(2) - p2.Jbar().col(1)).norm(), 1e-11 * p2.Jbar().norm());
  EXPECT_LT((p3.N() - p2.N()).norm(), 1e-11);
}

// Λ is formed two ways (projection.cpp): a Cholesky factor when κ₂(J A⁻¹ Jᵀ) is
// certified below 1/threshold by ‖S‖_F ‖S⁻¹‖_F, else the truncated eigen-decomposition.
// A threshold between 1/bound and 1/κ₂ makes the certificate fail while no eigenvalue
// is dropped: both ways must then give the same Λ and J̄ (1e-12 relative: two
// backward-stable factorisations of a matrix with κ₂ ~ 1e2).
TEST(DynamicallyConsistentInverse, CholeskyAndEigenPathsAgreeWhereNothingIsDropped) {
  const ArmTip b = arm_tip(0.3, 0.4);
  const Eigen::MatrixXd S = b.J * b.A.inverse() * b.J.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(S);
  const double kappa = es.eigenvalues().maxCoeff() / es.eigenvalues().minCoeff();
  const double bound = S.norm() * S.inverse().norm();
  ASSERT_LT(kappa, bound);
  DynamicallyConsistentInverse fast(2, 2), eigen(2, 2, 1.0 / std::sqrt(kappa * bound));
  fast.compute(b.A, b.J);
  eigen.compute(b.A, b.J);
  EXPECT_FALSE(fast.used_eigen());
  EXPECT_TRUE(eigen.used_eigen());
  EXPECT_EQ(eigen.rank(), 2);
  EXPECT_LT((fast.Lambda() - eigen.Lambda()).norm(), 1e-12 * fast.Lambda().norm());
  EXPECT_LT((fast.Jbar() - eigen.Jbar()).norm(), 1e-12 * fast.Jbar().norm());
  // At the singular configuration the certificate cannot hold.
  const ArmTip s = arm_tip(0.3, 0.0);
  DynamicallyConsistentInverse singular(2, 2);
  singular.compute(s.A, s.J);
  EXPECT_TRUE(singular.used_eigen());
}

}  // namespace
}  // namespace dmbd::wholebody::testing
