// The dense Cholesky factor on plain column-major arrays (dmbd/base/dense_cholesky.hpp)
// against Eigen's LLT, inside a larger array (lda > n, as the QP's and plant's callers
// may pass), and its refusal of a matrix that is not positive definite.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "dmbd/base/dense_cholesky.hpp"

namespace {

// Random A = B Bᵀ + n I (condition number below ~10 for these sizes): the factor and the
// solution agree with Eigen's to 1e-13 relative, both being backward stable.
TEST(DenseCholesky, MatchesEigensLltInsideALargerArray) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int n : {1, 3, 4, 7, 16, 26}) {
    Eigen::MatrixXd B(n, n);
    for (int i = 0; i < n * n; ++i) B.data()[i] = u(rng);
    const Eigen::MatrixXd A = B * B.transpose() + n * Eigen::MatrixXd::Identity(n, n);
    const Eigen::VectorXd b = Eigen::VectorXd::Random(n);
    Eigen::MatrixXd big = Eigen::MatrixXd::Constant(n + 3, n, 7.0);  // lda = n + 3
    big.topRows(n) = A;
    big.topRows(n).triangularView<Eigen::StrictlyUpper>().setConstant(std::numeric_limits<double>::quiet_NaN());
    Eigen::VectorXd inv(n), x = b;
    ASSERT_TRUE(dmbd::base::cholesky_in_place(big.data(), big.outerStride(), n, inv.data())) << n;
    const Eigen::MatrixXd L = A.llt().matrixL();
    const Eigen::MatrixXd mine = big.topRows(n).triangularView<Eigen::Lower>();
    EXPECT_LT((mine - L).norm(), 1e-13 * L.norm()) << n;
    for (int i = 0; i < n; ++i) EXPECT_DOUBLE_EQ(inv[i] * L(i, i), 1.0);
    EXPECT_TRUE((big.bottomRows(3).array() == 7.0).all());  // rows past n untouched
    dmbd::base::cholesky_solve_in_place(big.data(), big.outerStride(), n, inv.data(), x.data());
    EXPECT_LT((A * x - b).norm(), 1e-13 * b.norm()) << n;
  }
}

TEST(DenseCholesky, RefusesAMatrixThatIsNotPositiveDefinite) {
  Eigen::Matrix2d A;
  A << 1.0, 2.0, 2.0, 1.0;
  double inv[2];
  EXPECT_FALSE(dmbd::base::cholesky_in_place(A.data(), 2, 2, inv));
  Eigen::Matrix2d N = Eigen::Matrix2d::Identity();
  N(1, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(dmbd::base::cholesky_in_place(N.data(), 2, 2, inv));
}

}  // namespace
