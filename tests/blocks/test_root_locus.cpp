// dmbd::blocks root locus: the closed form of 1/(s(s+2)), a biproper loop losing a root
// to infinity, the state-space formulation against the polynomial one, branch continuity.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "dmbd/base/error.hpp"
#include "dmbd/blocks/root_locus.hpp"
#include "dmbd/blocks/state_space.hpp"

namespace dmbd::blocks {
namespace {

TEST(RootLocus, SecondOrderClosedForm) {
  // s^2 + 2 s + k: -1 -+ sqrt(1 - k).
  const TransferFunction g = TransferFunction::parse("1/(s*(s+2))");
  const std::vector<double> gains{0.0, 0.5, 1.0, 2.0, 5.0};
  const ComplexMatrix r = root_locus(g, gains);
  ASSERT_EQ(r.rows(), 5);
  ASSERT_EQ(r.cols(), 2);
  for (Eigen::Index i = 0; i < r.rows(); ++i) {
    const Complex d = std::sqrt(Complex(1.0 - gains[static_cast<size_t>(i)], 0.0));
    const Complex lo = -1.0 - d, hi = -1.0 + d;
    const bool direct = std::abs(r(i, 0) - lo) < std::abs(r(i, 0) - hi);
    // A double root at k = 1 (-1 twice): sqrt(eps) there, rounding elsewhere.
    const double tol = gains[static_cast<size_t>(i)] == 1.0 ? 1e-7 : 1e-14;
    EXPECT_NEAR(std::abs(r(i, 0) - (direct ? lo : hi)), 0.0, tol) << i;
    EXPECT_NEAR(std::abs(r(i, 1) - (direct ? hi : lo)), 0.0, tol) << i;
  }
  EXPECT_EQ(r(0, 0), Complex(-2.0, 0.0));  // row 0 sorted: the open-loop poles
  EXPECT_EQ(r(0, 1), Complex(0.0, 0.0));
}

TEST(RootLocus, BiproperLoopLosesARootToInfinity) {
  // den + k num = (s + 2) - k (s + 1): degree 0 at k = 1.
  const TransferFunction g = TransferFunction::parse("-(s+1)/(s+2)");
  const ComplexMatrix r = root_locus(g, {0.0, 0.5, 1.0});
  EXPECT_NEAR(r(1, 0).real(), -3.0, 1e-14);  // (2 - 0.5) + (1 - 0.5) s... root -(2 - k)/(1 - k)
  EXPECT_EQ(r(2, 0).real(), std::numeric_limits<double>::infinity());
  // The realisation's D is -1 to rounding: 1 + k D is rounding, the root beyond 1e12.
  const ComplexMatrix rs = root_locus(StateSpace::from_tf(g), {1.0});
  EXPECT_GT(std::abs(rs(0, 0)), 1e12);
}

TEST(RootLocus, StateSpaceAgreesWithPolynomials) {
  const TransferFunction g = TransferFunction::parse("(s+3)/((s+1)*(s^2+0.4*s+4))");
  std::vector<double> gains;
  for (int i = 0; i <= 50; ++i) gains.push_back(0.2 * i);
  const ComplexMatrix rp = root_locus(g, gains), rs = root_locus(StateSpace::from_tf(g), gains);
  // Eigenvalues of A - kBC against polynomial roots, branches sorted the same way
  // (well separated simple roots over these gains): 1e-12 relative.
  for (Eigen::Index i = 0; i < rp.rows(); ++i)
    for (Eigen::Index j = 0; j < rp.cols(); ++j)
      EXPECT_LE(std::abs(rp(i, j) - rs(i, j)), 1e-12 * (1.0 + std::abs(rp(i, j)))) << i << ", " << j;
  // Continuity: a column moves by less than 0.2 per gain step of 0.2 (|dp/dk| <= 1 here).
  for (Eigen::Index i = 1; i < rp.rows(); ++i)
    for (Eigen::Index j = 0; j < rp.cols(); ++j) EXPECT_LT(std::abs(rp(i, j) - rp(i - 1, j)), 0.2) << i << ", " << j;
}

TEST(RootLocus, DefaultGainsAndRefusals) {
  const TransferFunction g = TransferFunction::parse("1/(s*(s+2))");
  const std::vector<double> k = default_root_locus_gains(g);
  ASSERT_EQ(k.size(), 201u);
  EXPECT_EQ(k[0], 0.0);
  for (size_t i = 1; i < k.size(); ++i) EXPECT_GT(k[i], k[i - 1]);
  EXPECT_THROW(root_locus(TransferFunction::parse("s^2/(s+1)"), {1.0}), InputError);
  EXPECT_THROW(root_locus(g, {std::nan("")}), InputError);
}

}  // namespace
}  // namespace dmbd::blocks
