// dmbd::blocks Riccati solvers and LQR: scalar closed forms, the double integrator's
// closed-form LQR, the cross term against the equivalent problem without it, residuals
// of larger problems, a discrete model with a singular A, and the refusals.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "dmbd/base/error.hpp"
#include "dmbd/blocks/riccati.hpp"

namespace dmbd::blocks {
namespace {

Matrix m1(double v) { return Matrix::Constant(1, 1, v); }

// A fixed, well-conditioned test system (entries from a linear congruential sequence).
Matrix pseudo_random(Eigen::Index rows, Eigen::Index cols, unsigned seed) {
  Matrix m(rows, cols);
  for (Eigen::Index j = 0; j < cols; ++j)
    for (Eigen::Index i = 0; i < rows; ++i) {
      seed = seed * 1103515245u + 12345u;
      m(i, j) = static_cast<double>((seed >> 8) % 2001u) / 1000.0 - 1.0;
    }
  return m;
}

TEST(Riccati, ScalarContinuousClosedForm) {
  // 2 a x - b^2 x^2 / r + q = 0: x = r (a + sqrt(a^2 + b^2 q / r)) / b^2, the positive root.
  for (double a : {-2.0, 0.0, 3.0}) {
    const double b = 1.5, q = 2.0, r = 0.5;
    const double x = r * (a + std::sqrt(a * a + b * b * q / r)) / (b * b);
    const LinearQuadratic l = lqr(m1(a), m1(b), m1(q), m1(r));
    EXPECT_NEAR(l.s(0, 0), x, 1e-14 * x) << "a = " << a;  // rounding of a 2 x 2 Schur form
    EXPECT_NEAR(l.k(0, 0), b * x / r, 1e-14 * b * x / r);
    ASSERT_EQ(l.poles.size(), 1u);
    EXPECT_NEAR(l.poles[0].real(), -std::sqrt(a * a + b * b * q / r), 1e-13 * (std::abs(a) + 2.0));
  }
}

TEST(Riccati, DoubleIntegratorLqrClosedForm) {
  // x1' = x2, x2' = u; Q = diag(q1, q2), R = r: s12 = sqrt(q1 r), s22 = sqrt(r (q2 + 2 s12)),
  // s11 = s12 s22 / r, K = [s12, s22] / r (the three scalar equations of the ARE).
  Matrix a(2, 2), b(2, 1);
  a << 0, 1, 0, 0;
  b << 0, 1;
  const double q1 = 4.0, q2 = 0.5, r = 0.25;
  const double s12 = std::sqrt(q1 * r), s22 = std::sqrt(r * (q2 + 2 * s12)), s11 = s12 * s22 / r;
  const LinearQuadratic l = lqr(a, b, Vector(Eigen::Vector2d(q1, q2)).asDiagonal(), m1(r));
  EXPECT_NEAR(l.s(0, 0), s11, 1e-14 * s11);
  EXPECT_NEAR(l.s(0, 1), s12, 1e-14 * s11);
  EXPECT_NEAR(l.s(1, 0), s12, 1e-14 * s11);
  EXPECT_NEAR(l.s(1, 1), s22, 1e-14 * s11);
  EXPECT_NEAR(l.k(0, 0), s12 / r, 1e-14 * s11 / r);
  EXPECT_NEAR(l.k(0, 1), s22 / r, 1e-14 * s11 / r);
  // The closed loop s^2 + k2 s + k1.
  const Complex disc = std::sqrt(Complex(l.k(0, 1) * l.k(0, 1) - 4 * l.k(0, 0)));
  EXPECT_NEAR(std::abs(l.poles[0] - (-l.k(0, 1) - disc) / 2.0), 0.0, 1e-13);
  EXPECT_NEAR(std::abs(l.poles[1] - (-l.k(0, 1) + disc) / 2.0), 0.0, 1e-13);
}

TEST(Riccati, ScalarDiscreteClosedForm) {
  // b^2 x^2 + (r (1 - a^2) - q b^2) x - q r = 0, the positive root.
  for (double a : {0.0, 0.5, 1.0, 2.0}) {
    const double b = 0.7, q = 1.5, r = 2.0;
    const double p = r * (1 - a * a) - q * b * b;
    const double x = (-p + std::sqrt(p * p + 4 * b * b * q * r)) / (2 * b * b);
    const LinearQuadratic l = dlqr(m1(a), m1(b), m1(q), m1(r));
    EXPECT_NEAR(l.s(0, 0), x, 1e-14 * x) << "a = " << a;
    EXPECT_NEAR(l.k(0, 0), b * x * a / (r + b * b * x), 1e-14 * (1 + a));
    EXPECT_LT(std::abs(l.poles[0]), 1.0);
  }
}

TEST(Riccati, CrossTermEqualsTheProblemWithoutIt) {
  // u = v - R^-1 N' x turns the cost with N into one without: A~ = A - B R^-1 N',
  // Q~ = Q - N R^-1 N' have the same S, and K = K~ + R^-1 N'.
  const Matrix a = pseudo_random(4, 4, 7), b = pseudo_random(4, 2, 11);
  const Matrix q = Matrix::Identity(4, 4) * 3.0, r = Matrix::Identity(2, 2) * 2.0;
  const Matrix n = pseudo_random(4, 2, 13) * 0.5;
  const Matrix rinv_nt = r.inverse() * n.transpose();
  for (bool discrete : {false, true}) {
    const LinearQuadratic with = discrete ? dlqr(a * 0.5, b, q, r, n) : lqr(a, b, q, r, n);
    const Matrix at = (discrete ? a * 0.5 : a) - b * rinv_nt;
    const LinearQuadratic without = discrete ? dlqr(at, b, q - n * rinv_nt, r) : lqr(at, b, q - n * rinv_nt, r);
    // Two independent Schur forms of differently reduced data: 1e-12 of |S|.
    EXPECT_LE((with.s - without.s).cwiseAbs().maxCoeff(), 1e-12 * with.s.cwiseAbs().maxCoeff()) << discrete;
    if (!discrete) {
      EXPECT_LE((with.k - (without.k + rinv_nt)).cwiseAbs().maxCoeff(), 1e-12 * with.k.cwiseAbs().maxCoeff());
    }
    const double res = discrete ? dare_residual(a * 0.5, b, q, r, n, with.s) : care_residual(a, b, q, r, n, with.s);
    EXPECT_LT(res, 1e-13) << discrete;
  }
}

TEST(Riccati, LargerProblemsSolveToRounding) {
  // 8 states, 3 inputs, an unstable A: residual relative to the terms' size, and a stable
  // closed loop.
  const Matrix a = pseudo_random(8, 8, 3) + Matrix::Identity(8, 8) * 0.3, b = pseudo_random(8, 3, 5);
  const Matrix c = pseudo_random(8, 8, 9);
  const Matrix q = c.transpose() * c + Matrix::Identity(8, 8), r = Matrix::Identity(3, 3);
  const LinearQuadratic lc = lqr(a, b, q, r);
  EXPECT_LT(care_residual(a, b, q, r, Matrix(), lc.s), 1e-13);
  for (const Complex& p : lc.poles) EXPECT_LT(p.real(), 0.0);
  const LinearQuadratic ld = dlqr(a, b, q, r);
  EXPECT_LT(dare_residual(a, b, q, r, Matrix(), ld.s), 1e-13);
  for (const Complex& p : ld.poles) EXPECT_LT(std::abs(p), 1.0);
  // S symmetric positive definite.
  EXPECT_EQ((lc.s - lc.s.transpose()).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Matrix>(lc.s).eigenvalues().minCoeff(), 0.0);
}

TEST(Riccati, DiscreteWithSingularA) {
  // A one-step delay in front of an integrator: A has an eigenvalue at z = 0, which the
  // Cayley-transformed pencil does not need to invert.
  Matrix a(2, 2), b(2, 1);
  a << 1, 1, 0, 0;
  b << 0, 1;
  const Matrix q = Matrix::Identity(2, 2), r = m1(1.0);
  const LinearQuadratic l = dlqr(a, b, q, r);
  EXPECT_LT(dare_residual(a, b, q, r, Matrix(), l.s), 1e-14);
  for (const Complex& p : l.poles) EXPECT_LT(std::abs(p), 1.0);
}

TEST(Riccati, Refusals) {
  Matrix a(2, 2), b(2, 1);
  a << 1, 0, 0, -1;
  b << 0, 1;  // the unstable mode z = 1 / s = 1 is not reachable
  EXPECT_THROW(lqr(a, b, Matrix::Identity(2, 2), m1(1.0)), InputError);
  EXPECT_THROW(dlqr(a * 2.0, b, Matrix::Identity(2, 2), m1(1.0)), InputError);
  Matrix ok(2, 2);
  ok << 0, 1, 0, 0;
  EXPECT_THROW(lqr(ok, b, Matrix::Identity(2, 2), m1(-1.0)), InputError);  // R not positive definite
  Matrix qa(2, 2);
  qa << 1, 2, 0, 1;
  EXPECT_THROW(lqr(ok, b, qa, m1(1.0)), InputError);  // Q not symmetric
  EXPECT_THROW(lqr(ok, b, Matrix::Identity(3, 3), m1(1.0)), InputError);  // Q's size
  try {
    lqr(a, b, Matrix::Identity(2, 2), m1(1.0));
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no stabilising solution"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dmbd::blocks
