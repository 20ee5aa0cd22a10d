// The Goldfarb–Idnani QP solver (wholebody/qp.hpp) against closed forms (unconstrained,
// equality-constrained by the KKT system, a box by clamping), against an exhaustive
// enumeration of active sets on small random problems, the KKT conditions on larger
// random ones, and its failure results (infeasible, dependent equalities, G not
// positive definite).
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <cmath>
#include <limits>
#include <random>

#include "dmbd/wholebody/qp.hpp"

namespace dmbd::wholebody::testing {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

struct Problem {
  MatrixXd G, C_eq, C_in;
  VectorXd a, b_eq, b_in;
};

MatrixXd random_matrix(std::mt19937& rng, int rows, int cols) {
  std::normal_distribution<double> g(0.0, 1.0);
  MatrixXd m(rows, cols);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i) m(i, j) = g(rng);
  return m;
}

// A strictly convex problem with a strictly feasible point x_f: b_in = C_in x_f − s,
// s in (0.05, 1); G = MᵀM + 0.1 I.
Problem random_feasible(std::mt19937& rng, int n, int m_eq, int m_in) {
  std::uniform_real_distribution<double> s(0.05, 1.0);
  Problem p;
  const MatrixXd M = random_matrix(rng, n, n);
  p.G = M.transpose() * M + 0.1 * MatrixXd::Identity(n, n);
  p.a = random_matrix(rng, n, 1);
  const VectorXd x_f = random_matrix(rng, n, 1);
  p.C_eq = random_matrix(rng, m_eq, n);
  p.b_eq = p.C_eq * x_f;
  p.C_in = random_matrix(rng, m_in, n);
  p.b_in = p.C_in * x_f;
  for (int i = 0; i < m_in; ++i) p.b_in[i] -= s(rng);
  return p;
}

QpStatus solve(QpSolver& qp, const Problem& p) { return qp.solve(p.G, p.a, p.C_eq, p.b_eq, p.C_in, p.b_in); }

// Stationarity, primal and dual feasibility, complementarity, each relative to the
// problem's scale (1e-9: the solver's factorisations are backward stable, the problems
// have condition numbers below ~1e4).
void expect_kkt(const QpSolver& qp, const Problem& p, double tol = 1e-9) {
  const VectorXd& x = qp.x();
  const double scale = 1.0 + p.G.norm() * x.norm() + p.a.norm();
  const VectorXd residual = p.G * x + p.a - p.C_eq.transpose() * qp.lambda_eq() - p.C_in.transpose() * qp.mu_in();
  EXPECT_LT(residual.norm(), tol * scale) << "stationarity";
  if (p.C_eq.rows() > 0) {
    EXPECT_LT((p.C_eq * x - p.b_eq).cwiseAbs().maxCoeff(), tol * scale) << "equalities";
  }
  for (int i = 0; i < p.C_in.rows(); ++i) {
    const double slack = p.C_in.row(i).dot(x) - p.b_in[i];
    EXPECT_GT(slack, -tol * scale) << "inequality " << i;
    EXPECT_GE(qp.mu_in()[i], 0.0) << "multiplier " << i;
    EXPECT_LT(std::abs(qp.mu_in()[i] * slack), tol * scale * (1.0 + qp.mu_in().norm())) << "complementarity " << i;
  }
}

// The optimum by enumeration: for every subset S of the inequalities, the KKT point with
// S as equalities; the best one feasible with multipliers ≥ 0 (small problems only).
double brute_force_optimum(const Problem& p) {
  const int n = static_cast<int>(p.G.rows()), m_eq = static_cast<int>(p.C_eq.rows());
  const int m_in = static_cast<int>(p.C_in.rows());
  double best = std::numeric_limits<double>::infinity();
  for (int mask = 0; mask < (1 << m_in); ++mask) {
    std::vector<int> set;
    for (int i = 0; i < m_in; ++i)
      if (mask & (1 << i)) set.push_back(i);
    const int m = m_eq + static_cast<int>(set.size());
    if (m > n) continue;
    MatrixXd A(m, n);
    VectorXd b(m);
    A.topRows(m_eq) = p.C_eq;
    b.head(m_eq) = p.b_eq;
    for (size_t k = 0; k < set.size(); ++k) {
      A.row(m_eq + static_cast<int>(k)) = p.C_in.row(set[k]);
      b[m_eq + static_cast<int>(k)] = p.b_in[set[k]];
    }
    MatrixXd K = MatrixXd::Zero(n + m, n + m);
    K.topLeftCorner(n, n) = p.G;
    K.topRightCorner(n, m) = -A.transpose();
    K.bottomLeftCorner(m, n) = A;
    VectorXd rhs(n + m);
    rhs << -p.a, b;
    const Eigen::FullPivLU<MatrixXd> lu(K);
    if (!lu.isInvertible()) continue;
    const VectorXd sol = lu.solve(rhs);
    const VectorXd x = sol.head(n), mult = sol.tail(m);
    bool ok = (mult.tail(m - m_eq).array() >= -1e-12).all();
    for (int i = 0; i < m_in && ok; ++i) ok = p.C_in.row(i).dot(x) - p.b_in[i] >= -1e-10;
    if (ok) best = std::min(best, 0.5 * x.dot(p.G * x) + p.a.dot(x));
  }
  return best;
}

TEST(QpSolver, UnconstrainedMinimumIsMinusGInverseA) {
  std::mt19937 rng(1);
  const Problem p = random_feasible(rng, 5, 0, 0);
  QpSolver qp(5, 0, 0);
  ASSERT_EQ(solve(qp, p), QpStatus::Optimal);
  const VectorXd x = -p.G.ldlt().solve(p.a);
  EXPECT_LT((qp.x() - x).norm(), 1e-12 * (1.0 + x.norm()));
  EXPECT_NEAR(qp.objective(), 0.5 * p.a.dot(x), 1e-12 * (1.0 + std::abs(p.a.dot(x))));  // = −½ aᵀG⁻¹a
}

TEST(QpSolver, EqualitiesGiveTheKktSystemsSolution) {
  std::mt19937 rng(2);
  for (int trial = 0; trial < 10; ++trial) {
    const Problem p = random_feasible(rng, 7, 3, 0);
    QpSolver qp(7, 3, 0);
    ASSERT_EQ(solve(qp, p), QpStatus::Optimal);
    MatrixXd K = MatrixXd::Zero(10, 10);
    K.topLeftCorner(7, 7) = p.G;
    K.topRightCorner(7, 3) = -p.C_eq.transpose();
    K.bottomLeftCorner(3, 7) = p.C_eq;
    VectorXd rhs(10);
    rhs << -p.a, p.b_eq;
    const VectorXd sol = K.fullPivLu().solve(rhs);
    EXPECT_LT((qp.x() - sol.head(7)).norm(), 1e-10 * (1.0 + sol.norm())) << trial;
    EXPECT_LT((qp.lambda_eq() - sol.tail(3)).norm(), 1e-10 * (1.0 + sol.norm())) << trial;
  }
}

// min ½‖x − c‖² on a box: x = clamp(c), the multiplier of a bound that holds is its
// distance |c − bound| (x − c = μ_lo − μ_hi).
TEST(QpSolver, BoxProblemIsTheClampedTarget) {
  const int n = 4;
  const VectorXd c = (VectorXd(n) << -2.0, 0.3, 1.7, -0.4).finished();
  MatrixXd C_in(2 * n, n);
  C_in << MatrixXd::Identity(n, n), -MatrixXd::Identity(n, n);
  VectorXd b_in(2 * n);
  b_in << VectorXd::Constant(n, -1.0), VectorXd::Constant(n, -1.0);  // −1 ≤ x ≤ 1
  QpSolver qp(n, 0, 2 * n);
  ASSERT_EQ(qp.solve(MatrixXd::Identity(n, n), -c, MatrixXd(0, n), VectorXd(0), C_in, b_in), QpStatus::Optimal);
  const VectorXd x = c.cwiseMax(-1.0).cwiseMin(1.0);
  EXPECT_LT((qp.x() - x).norm(), 1e-14);
  const VectorXd mu = qp.mu_in();
  EXPECT_NEAR(mu[0], 1.0, 1e-14);      // x0 = −1: lower bound, 1 away from c
  EXPECT_NEAR(mu[n + 2], 0.7, 1e-14);  // x2 = 1: upper bound, 0.7 away
  EXPECT_EQ(mu[1] + mu[3] + mu[n] + mu[n + 1] + mu[n + 3] + mu[2], 0.0);
  EXPECT_EQ(qp.active_inequalities(), 2);
}

TEST(QpSolver, SmallRandomProblemsMatchEnumerationOfActiveSets) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 60; ++trial) {
    const Problem p = random_feasible(rng, 4, trial % 2, 7);
    QpSolver qp(4, trial % 2, 7);
    ASSERT_EQ(solve(qp, p), QpStatus::Optimal) << trial;
    const double best = brute_force_optimum(p);
    EXPECT_NEAR(qp.objective(), best, 1e-9 * (1.0 + std::abs(best))) << trial;
    expect_kkt(qp, p);
  }
}

// The whole-body controller's size (issue 15: 16 accelerations, 6 forces, 6 slacks;
// 6 + 6 equalities, 2 × 5 pyramid faces + 2 normal bounds + 10 torque bounds).
TEST(QpSolver, KktConditionsHoldOnRandomProblemsOfTheWholeBodySize) {
  std::mt19937 rng(4);
  for (int trial = 0; trial < 30; ++trial) {
    const Problem p = random_feasible(rng, 28, 12, 32);
    QpSolver qp(28, 12, 32);
    ASSERT_EQ(solve(qp, p), QpStatus::Optimal) << trial;
    expect_kkt(qp, p);
  }
}

TEST(QpSolver, ContradictoryInequalitiesAreInfeasible) {
  // x ≥ 1 and x ≤ 0.
  MatrixXd C(2, 1);
  C << 1.0, -1.0;
  QpSolver qp(1, 0, 2);
  EXPECT_EQ(qp.solve(MatrixXd::Identity(1, 1), VectorXd::Zero(1), MatrixXd(0, 1), VectorXd(0), C, (VectorXd(2) << 1.0, 0.0).finished()),
            QpStatus::Infeasible);
  // Random problems made infeasible by a pair cᵀx ≥ 1, −cᵀx ≥ 0 among feasible ones.
  std::mt19937 rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    Problem p = random_feasible(rng, 6, 2, 8);
    const VectorXd c = random_matrix(rng, 6, 1);
    p.C_in.row(3) = c.transpose();
    p.b_in[3] = 1.0;
    p.C_in.row(6) = -c.transpose();
    p.b_in[6] = 0.0;
    QpSolver qp(6, 2, 8);
    EXPECT_EQ(solve(qp, p), QpStatus::Infeasible) << trial;
  }
}

TEST(QpSolver, DependentEqualitiesAndIndefiniteHessiansFail) {
  std::mt19937 rng(6);
  Problem p = random_feasible(rng, 5, 3, 2);
  p.C_eq.row(2) = 2.0 * p.C_eq.row(0) - p.C_eq.row(1);
  p.b_eq[2] = 2.0 * p.b_eq[0] - p.b_eq[1] + 1.0;  // inconsistent
  QpSolver qp(5, 3, 2);
  EXPECT_EQ(solve(qp, p), QpStatus::Infeasible);
  Problem q = random_feasible(rng, 5, 1, 2);
  q.G(2, 2) = -1.0;
  QpSolver qp2(5, 1, 2);
  EXPECT_EQ(solve(qp2, q), QpStatus::NotPositiveDefinite);
  EXPECT_STREQ(to_string(QpStatus::Infeasible), "infeasible");
}

TEST(QpSolver, ReusedSolverForgetsThePreviousProblem) {
  std::mt19937 rng(7);
  const Problem p1 = random_feasible(rng, 6, 1, 9), p2 = random_feasible(rng, 6, 1, 9);
  QpSolver reused(6, 1, 9), fresh(6, 1, 9);
  ASSERT_EQ(solve(reused, p1), QpStatus::Optimal);
  ASSERT_EQ(solve(reused, p2), QpStatus::Optimal);
  ASSERT_EQ(solve(fresh, p2), QpStatus::Optimal);
  EXPECT_EQ((reused.x() - fresh.x()).norm(), 0.0);
  EXPECT_EQ((reused.mu_in() - fresh.mu_in()).norm(), 0.0);
}

// A sequence of problems that drift, as a controller's do from tick to tick: warm
// started, each solve gives the cold solve's minimiser and multipliers (to 1e-9 of the
// problem's scale), and every path is taken: the previous active set solved directly
// (it is still the active set), going on from it by the dual method (something else
// became violated), and starting again when a multiplier of it turns negative.
TEST(QpSolver, WarmStartGivesTheColdSolutionAlongADriftingSequence) {
  std::mt19937 rng(11);
  Problem p = random_feasible(rng, 16, 0, 32);
  const MatrixXd da = random_matrix(rng, 16, 1), db = random_matrix(rng, 32, 1);
  QpSolver warm(16, 0, 32), cold(16, 0, 32);
  warm.set_warm_start(true);
  int direct = 0, went_on = 0, restarted = 0;
  for (int tick = 0; tick < 400; ++tick) {
    const double phase = 0.05 * tick;
    Problem q = p;
    q.a += 3.0 * std::sin(phase) * da;  // the active set changes along the way
    q.b_in += 0.2 * std::sin(0.7 * phase) * db;
    ASSERT_EQ(solve(cold, q), QpStatus::Optimal) << tick;
    ASSERT_EQ(solve(warm, q), QpStatus::Optimal) << tick;
    const double scale = 1.0 + cold.x().norm() + cold.mu_in().norm();
    EXPECT_LT((warm.x() - cold.x()).norm(), 1e-9 * scale) << tick;
    EXPECT_LT((warm.mu_in() - cold.mu_in()).norm(), 1e-9 * scale) << tick;
    expect_kkt(warm, q);
    if (tick > 0) (warm.solved_directly() ? direct : warm.warm_started() ? went_on : restarted) += 1;
  }
  EXPECT_GT(direct, 200);
  EXPECT_GT(went_on, 0);
  EXPECT_GT(restarted, 0);
  EXPECT_FALSE(cold.warm_started());
}

// After an infeasible problem the guess is dropped, and a warm solve of a feasible one
// matches the cold solve; with equalities the warm start keeps them first.
TEST(QpSolver, WarmStartRecoversFromInfeasibleProblemsAndKeepsEqualities) {
  std::mt19937 rng(12);
  const Problem p = random_feasible(rng, 8, 2, 12);
  Problem bad = p;
  const VectorXd c = random_matrix(rng, 8, 1);
  bad.C_in.row(1) = c.transpose();
  bad.b_in[1] = 1.0;
  bad.C_in.row(2) = -c.transpose();
  bad.b_in[2] = 0.0;
  QpSolver warm(8, 2, 12), cold(8, 2, 12);
  warm.set_warm_start(true);
  ASSERT_EQ(solve(warm, p), QpStatus::Optimal);
  EXPECT_EQ(solve(warm, bad), QpStatus::Infeasible);
  ASSERT_EQ(solve(warm, p), QpStatus::Optimal);
  EXPECT_FALSE(warm.warm_started());  // nothing remembered from the infeasible solve
  ASSERT_EQ(solve(warm, p), QpStatus::Optimal);
  EXPECT_TRUE(warm.warm_started());
  ASSERT_EQ(solve(cold, p), QpStatus::Optimal);
  EXPECT_LT((warm.x() - cold.x()).norm(), 1e-10 * (1.0 + cold.x().norm()));
  EXPECT_LT((warm.lambda_eq() - cold.lambda_eq()).norm(), 1e-9 * (1.0 + cold.lambda_eq().norm()));
  expect_kkt(warm, p);
}

}  // namespace
}  // namespace dmbd::wholebody::testing
