// dmbd::blocks pole placement: the unique single-input gain of a companion form (closed
// form), several inputs with complex pairs and repeated poles, a 10th-order chain against
// its exact integer gain, an eightfold pole, and the refusals.
#include <gtest/gtest.h>

#include <cmath>

#include "dmbd/base/error.hpp"
#include "dmbd/blocks/pole_placement.hpp"
#include "dmbd/blocks/polynomial.hpp"

namespace dmbd::blocks {
namespace {

// Requested and achieved poles, both sorted, differ by at most tol relative to |p| + 1.
void expect_placed(const PolePlacement& r, std::vector<Complex> want, double tol) {
  sort_roots(want);
  ASSERT_EQ(r.achieved.size(), want.size());
  for (size_t k = 0; k < want.size(); ++k)
    EXPECT_LE(std::abs(r.achieved[k] - want[k]), tol * (std::abs(want[k]) + 1.0)) << k << ": " << r.achieved[k];
}

// The controllable canonical form of s^n + a_{n-1} s^{n-1} + ... + a0 (states x, x', ...).
Matrix companion(const std::vector<double>& a_ascending) {
  const Eigen::Index n = static_cast<Eigen::Index>(a_ascending.size());
  Matrix a = Matrix::Zero(n, n);
  for (Eigen::Index i = 0; i + 1 < n; ++i) a(i, i + 1) = 1.0;
  for (Eigen::Index j = 0; j < n; ++j) a(n - 1, j) = -a_ascending[static_cast<size_t>(j)];
  return a;
}

TEST(PolePlacement, SingleInputCompanionClosedForm) {
  // With b = e_n, A - b K is the companion form of s^3 + (a + K) ...: K = d - a
  // coefficient by coefficient, d the coefficients of prod (s - p).
  const std::vector<double> a{2.0, -1.0, 0.5};
  const std::vector<Complex> poles{{-2.0, 0.0}, {-1.0, 1.5}, {-1.0, -1.5}};
  const Polynomial d = Polynomial::from_roots(poles);
  const PolePlacement r = place(companion(a), Matrix(Vector::Unit(3, 2)), poles);
  ASSERT_EQ(r.k.rows(), 1);
  ASSERT_EQ(r.k.cols(), 3);
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(r.k(0, j), d[j] - a[static_cast<size_t>(j)], 1e-13 * 10) << j;
  EXPECT_EQ(r.sweeps, 0);
  expect_placed(r, poles, 1e-13);
}

TEST(PolePlacement, SeveralInputsComplexPairsAndRepeats) {
  Matrix a(4, 4), b(4, 2);
  a << 0, 1, 0, 0,  //
      2, -0.5, 1, 0,  //
      0, 0, 0, 1,  //
      1, 0, -3, -0.2;
  b << 0, 0, 1, 0, 0, 0, 0.5, 1;
  const std::vector<Complex> pairs{{-1.0, 2.0}, {-1.0, -2.0}, {-3.0, 0.0}, {-4.0, 0.0}};
  const PolePlacement r = place(a, b, pairs);
  // The eigenvalues of the computed A - BK: well-conditioned X (condition reported), 1e-12.
  expect_placed(r, pairs, 1e-12);
  EXPECT_LT(r.eigenvector_condition, 100.0);
  EXPECT_GE(r.sweeps, 1);
  // A pole twice with two inputs: allowed (rank B = 2).
  const std::vector<Complex> twice{{-2.0, 0.0}, {-2.0, 0.0}, {-1.0, 0.0}, {-5.0, 0.0}};
  expect_placed(place(a, b, twice), twice, 1e-9);  // a double eigenvalue (nonderogatory not needed): 1e-9
}

TEST(PolePlacement, TenthOrderChainAgainstItsExactGain) {
  // x1' = x2, ..., x10' = u (a chain of integrators, companion form with a = 0): K is
  // exactly the coefficients of prod (s + k), k = 1..10 (integers up to 10! = 3628800).
  // Its closed loop's eigenvectors are a Vandermonde matrix (condition ~1e12 here): the
  // placed poles are that sensitive, the gain itself is not.
  std::vector<Complex> poles;
  for (int k = 1; k <= 10; ++k) poles.push_back(-k);
  const Polynomial d = Polynomial::from_roots(poles);
  const PolePlacement r = place(companion(std::vector<double>(10, 0.0)), Matrix(Vector::Unit(10, 9)), poles);
  double worst = 0.0;
  for (int j = 0; j < 10; ++j) worst = std::max(worst, std::abs(r.k(0, j) - d[j]) / d[j]);
  EXPECT_LT(worst, 1e-10) << "worst relative gain error";  // measured 1.3e-11 (docs/python.md)
}

TEST(PolePlacement, EightfoldPoleWithOneInput) {
  // (s + 2)^8 on a chain of integrators: K = the binomial coefficients times powers of 2,
  // exact integers up to 1792.
  const std::vector<Complex> poles(8, -2.0);
  const Polynomial d = Polynomial::from_roots(poles);
  const PolePlacement r = place(companion(std::vector<double>(8, 0.0)), Matrix(Vector::Unit(8, 7)), poles);
  for (int j = 0; j < 8; ++j) EXPECT_NEAR(r.k(0, j), d[j], 1e-12 * d[j]) << j;
}

TEST(PolePlacement, Refusals) {
  Matrix a(2, 2), b(2, 1);
  a << 1, 0, 0, 2;
  b << 1, 0;  // the mode at 2 is not reachable
  EXPECT_THROW(place(a, b, {-1.0, -3.0}), InputError);
  a << 0, 1, 0, 0;
  b << 0, 1;
  const PolePlacement twice = place(a, b, {-1.0, -1.0});  // a repeated pole, one input: (s + 1)^2
  EXPECT_NEAR(twice.k(0, 0), 1.0, 1e-14);
  EXPECT_NEAR(twice.k(0, 1), 2.0, 1e-14);
  EXPECT_THROW(place(a, b, {Complex(-1.0, 1.0), -2.0}), InputError);  // no conjugate
  EXPECT_THROW(place(a, b, {-1.0}), InputError);  // too few
  EXPECT_NO_THROW(place(a, b, {-1.0, -2.0}));
}

}  // namespace
}  // namespace dmbd::blocks
