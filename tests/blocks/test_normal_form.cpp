// Normal form of a SISO plant and the DOB fast subsystem (paper eq. ss_realization_1/2
// and the proof of the theorem in Sec. III-B).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/frequency.hpp"
#include "dmbd/blocks/normal_form.hpp"

namespace {

using namespace dmbd::blocks;  // NOLINT: no SimTK here

// The plant whose normal form the paper prints for the nominal actuator:
// psi = -9.53e3, phi = 1e4 [-1.49, -0.01], S = -0.0433, G = [1 0], g = 1.31e4.
// Built from those numbers as y'' = psi z + phi' (y, y') + g u, z' = S z + y.
StateSpace paper_nominal_realisation() {
  Matrix a(3, 3), b(3, 1), c(1, 3), d = Matrix::Zero(1, 1);
  a << 0, 1, 0,  //
      -1.49e4, -0.01e4, -9.53e3,  //
      1, 0, -0.0433;
  b << 0, 1.31e4, 0;
  c << 1, 0, 0;
  return StateSpace(a, b, c, d);
}

TEST(NormalForm, RecoversThePapersPrintedNominalParameters) {
  const NormalForm nf = normal_form(paper_nominal_realisation().to_tf());
  // The TF round trip is accurate to ~1e-12 relative; 1e-9 leaves margin.
  EXPECT_EQ(nf.relative_degree, 2);
  EXPECT_NEAR(nf.g, 1.31e4, 1e-9 * 1.31e4);
  ASSERT_EQ(nf.phi.size(), 2);
  EXPECT_NEAR(nf.phi(0), -1.49e4, 1e-9 * 1.49e4);
  EXPECT_NEAR(nf.phi(1), -0.01e4, 1e-9 * 1.49e4);
  ASSERT_EQ(nf.psi.size(), 1);
  EXPECT_NEAR(nf.psi(0), -9.53e3, 1e-9 * 9.53e3);
  EXPECT_NEAR(nf.S(0, 0), -0.0433, 1e-9);
  EXPECT_DOUBLE_EQ(nf.G(0, 0), 1.0);
  EXPECT_DOUBLE_EQ(nf.G(0, 1), 0.0);
}

TEST(NormalForm, RealisationFromTheNormalFormHasTheSameTransferFunction) {
  // A relative-degree-2 plant with two zeros: rebuild it from its normal form and
  // compare responses (two formulations of the same plant).
  const TransferFunction p = TransferFunction::parse("3*(s+2)*(s+5)/((s+1)*(s^2+2*s+10)*(s+7))");
  const NormalForm nf = normal_form(p);
  ASSERT_EQ(nf.relative_degree, 2);
  const int rho = nf.relative_degree, m = static_cast<int>(nf.S.rows()), n = rho + m;
  Matrix a = Matrix::Zero(n, n), b = Matrix::Zero(n, 1), c = Matrix::Zero(1, n);
  for (int k = 0; k + 1 < rho; ++k) a(k, k + 1) = 1.0;
  a.block(rho - 1, 0, 1, rho) = nf.phi.transpose();
  a.block(rho - 1, rho, 1, m) = nf.psi.transpose();
  a.block(rho, 0, m, rho) = nf.G;
  a.block(rho, rho, m, m) = nf.S;
  b(rho - 1, 0) = nf.g;
  c(0, 0) = 1.0;
  const StateSpace ss(a, b, c, Matrix::Zero(1, 1));
  for (double w : {0.1, 1.0, 3.0, 30.0}) {
    const Complex s(0.0, w);
    // Both are exact evaluations of the same rational function: 1e-12 relative.
    EXPECT_LT(std::abs(ss.evaluate(s)(0, 0) - p.evaluate(s)), 1e-12 * std::abs(p.evaluate(s))) << w;
  }
  // Zero dynamics: the eigenvalues of S are the plant's zeros -2 and -5.
  Eigen::EigenSolver<Matrix> es(nf.S);
  std::vector<double> z{es.eigenvalues()[0].real(), es.eigenvalues()[1].real()};
  std::sort(z.begin(), z.end());
  EXPECT_NEAR(z[0], -5.0, 1e-12);
  EXPECT_NEAR(z[1], -2.0, 1e-12);
}

TEST(NormalForm, RejectsPlantsWithoutARelativeDegree) {
  EXPECT_THROW(normal_form(TransferFunction::parse("(s+1)/(s+2)")), dmbd::InputError);
  EXPECT_THROW(normal_form(TransferFunction(0.0)), dmbd::InputError);
}

TEST(DobFastSubsystem, CharacteristicPolynomialIsPaTimesPb) {
  // Q filters of eq. frc_ctrl in stretched time: A = [0 1; -1 -sqrt 2], B = [0; 1], C = [1 0].
  Matrix a(2, 2), b(2, 1), c(1, 2);
  a << 0, 1, -1, -std::sqrt(2.0);
  b << 0, 1;
  c << 1, 0;
  for (double r : {0.05, 0.5, 1.0, 1.018, 3.0}) {
    SCOPED_TRACE(r);
    const Matrix m = dob_fast_subsystem(a, b, c, r);
    // p_a(s) p_b(s) = (s^2 + sqrt2 s + 1)(s^2 + sqrt2 s + r)  (the paper's proof).
    const Polynomial pa({1.0, std::sqrt(2.0), 1.0}), pb({r, std::sqrt(2.0), 1.0});
    std::vector<Complex> want = (pa * pb).roots();
    Eigen::EigenSolver<Matrix> es(m, false);
    ASSERT_EQ(es.eigenvalues().size(), 4);
    for (const Complex& w : want) {
      double best = 1e9;
      for (int k = 0; k < 4; ++k) best = std::min(best, std::abs(es.eigenvalues()[k] - w));
      // Eigenvalues of a 4x4 with a possible double root (r = 1): sqrt(eps) accuracy.
      EXPECT_LT(best, 1e-7) << w;
    }
    // Hurwitz for every r > 0.
    for (int k = 0; k < 4; ++k) EXPECT_LT(es.eigenvalues()[k].real(), 0.0);
  }
  // A sign change of the high-frequency gain (r < 0) loses stability.
  Eigen::EigenSolver<Matrix> es(dob_fast_subsystem(a, b, c, -0.1), false);
  double max_re = -1e9;
  for (int k = 0; k < 4; ++k) max_re = std::max(max_re, es.eigenvalues()[k].real());
  EXPECT_GT(max_re, 0.0);
}

TEST(DobFastSubsystem, PapersLoadRangeIsHurwitz) {
  // g(M_l) = 3.2e4 M_l / (2.4 M_l + 3.1) against g_bar = 1.31e4 (paper, proof of the
  // theorem), for M_l from 2953 kg to 1e9 kg.
  Matrix a(2, 2), b(2, 1), c(1, 2);
  a << 0, 1, -1, -std::sqrt(2.0);
  b << 0, 1;
  c << 1, 0;
  for (double ml : logspace(2953.0, 1e9, 40)) {
    const double r = 3.2e4 * ml / (2.4 * ml + 3.1) / 1.31e4;
    Eigen::EigenSolver<Matrix> es(dob_fast_subsystem(a, b, c, r), false);
    for (int k = 0; k < 4; ++k) EXPECT_LT(es.eigenvalues()[k].real(), -0.1) << ml;
  }
}

}  // namespace
