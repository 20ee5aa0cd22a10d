// dmbd::blocks::Siso (issue 13, items 1 and 11): a state-space interconnection taken
// apart along its structure. Integrators and poles at z = 1 come out exact; hidden modes
// are named; a chain of 1000 lags is 1000 one-state factors with the closed-form poles,
// DC gain and step response; the two formulations of a factor's zeros (numerator
// interpolation, pencil deflation) agree; the transfer agrees with its coefficients.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <cmath>
#include <random>

#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/siso.hpp"
#include "test_support.hpp"

namespace dmbd::blocks {
namespace {

using test::roots_near;

TransferFunction tf(const std::string& e, double ts = 0.0) { return TransferFunction::parse(e, {}, ts); }

// n lags g_i a_i / (s + a_i) in series, as one sparse model: x_i' = -a_i x_i + g_i a_i x_{i-1}.
SparseStateSpace lag_chain(const std::vector<double>& a, const std::vector<double>& g) {
  const auto n = static_cast<int>(a.size());
  std::vector<Eigen::Triplet<double>> ta, tb, tc;
  for (int i = 0; i < n; ++i) {
    ta.emplace_back(i, i, -a[static_cast<size_t>(i)]);
    const double in = g[static_cast<size_t>(i)] * a[static_cast<size_t>(i)];
    if (i == 0) {
      tb.emplace_back(0, 0, in);
    } else {
      ta.emplace_back(i, i - 1, in);
    }
  }
  tc.emplace_back(0, n - 1, 1.0);
  SparseMatrix am(n, n), bm(n, 1), cm(1, n);
  am.setFromTriplets(ta.begin(), ta.end());
  bm.setFromTriplets(tb.begin(), tb.end());
  cm.setFromTriplets(tc.begin(), tc.end());
  return SparseStateSpace(am, bm, cm, Matrix::Zero(1, 1));
}

TEST(Siso, ChainOfThousandLagsHasExactPolesAndTheProductDcGain) {
  // Poles exactly -a_i (one-state groups), DC gain prod g_i = 1.001^1000 (each factor's
  // gain to rounding: 1000 products, 1e-12 relative), 1000 factors, nothing hidden.
  const int n = 1000;
  std::vector<double> a, g;
  for (int i = 0; i < n; ++i) a.push_back(1.0 + i % 7), g.push_back(1.001);
  const Siso s = Siso::from_state_space(lag_chain(a, g));
  EXPECT_EQ(s.factors(), n);
  EXPECT_TRUE(s.hidden().empty());
  const std::vector<Complex> poles = s.zpk().all_poles();
  ASSERT_EQ(poles.size(), static_cast<size_t>(n));
  for (int k = 1; k <= 7; ++k)
    EXPECT_EQ(std::count(poles.begin(), poles.end(), Complex(-k, 0.0)), k <= n % 7 ? n / 7 + 1 : n / 7) << k;
  EXPECT_TRUE(s.zpk().zeros().empty());
  EXPECT_EQ(s.zpk().m(), 0);
  EXPECT_NEAR(*s.zpk().dc_gain(), std::pow(1.001, n), 1e-12 * std::pow(1.001, n));
  EXPECT_EQ(stability(s.zpk()), Stability::Stable);
  EXPECT_FALSE(s.tf().has_value());  // coefficients of prod (s + a_i) overflow
}

TEST(Siso, StepOfAChainOfLagsIsTheErlangDistribution) {
  // n equal lags a/(s + a): y(t) = P(n, a t) = 1 - e^{-at} sum_{k<n} (at)^k / k!. With
  // n = 80 the step goes through the sparse exponential action (more than 60 states);
  // with n = 8 through the dense matrix exponential. 1e-10 absolute: each is exact to
  // a few hundred roundings of the propagated state.
  for (int n : {8, 80}) {
    const double a = 10.0;
    const Siso s = Siso::from_state_space(lag_chain(std::vector<double>(static_cast<size_t>(n), a),
                                                    std::vector<double>(static_cast<size_t>(n), 1.0)));
    const double t_end = 2.0 * n / a;
    const Siso::Step st = s.step(t_end, 201);
    for (size_t k = 0; k < st.response.t.size(); k += 10) {
      const double x = a * st.response.t[k];
      double term = 1.0, sum = 0.0;
      for (int j = 0; j < n; ++j) sum += term, term *= x / (j + 1);
      EXPECT_NEAR(st.response.y(static_cast<Eigen::Index>(k), 0), 1.0 - std::exp(-x) * sum, 1e-10) << n << " " << k;
    }
    EXPECT_NEAR(*st.info.final_value, 1.0, 1e-12);
    ASSERT_TRUE(st.info.rise_time_s.has_value());
  }
}

TEST(Siso, IntegratorsInALoopAreExact) {
  // The loop of issue 13, item 1: PD (100 + 20 s/(0.001 s + 1)) on 1/(2 s^2), broken
  // at the plant input. The double pole at the origin is exactly 0 (from_tf gives the
  // integrators A(i, i) = 0 exactly, in their own groups), the DC gain infinite, and
  // a double integrator is not stable. The other pole is -1000 (the filter).
  const StateSpace pd = StateSpace::from_tf(tf("100 + 20*s/(0.001*s + 1)"));
  const StateSpace plant = StateSpace::from_tf(tf("1/(2*s^2)"));
  const Siso s = Siso::from_state_space(SparseStateSpace(series(plant, pd)));
  EXPECT_EQ(s.zpk().m(), -2);
  EXPECT_TRUE(roots_near(s.zpk().poles(), {Complex(-1000.0, 0.0)}, 1e-12));
  EXPECT_FALSE(s.zpk().dc_gain().has_value());
  EXPECT_EQ(stability(s.zpk()), Stability::Unstable);
  // k = the low-frequency gain of s^2 L: 100 / 2 = 50, to rounding.
  EXPECT_NEAR(s.zpk().k(), 50.0, 1e-12 * 50.0);
  // The zero of the PD: 100 (0.001 s + 1) + 20 s = 0 at s = -100/20.1.
  EXPECT_TRUE(roots_near(s.zpk().zeros(), {Complex(-100.0 / 20.1, 0.0)}, 1e-12));
}

TEST(Siso, CancellationAtTheBoundaryIsAHiddenMode) {
  // s/(s + 1) then 1/s: the zero of one factor and the pole of the next meet at s = 0
  // (m = 0): the transfer is 1/(s + 1), stable, and the integrator is hidden, exactly 0.
  const StateSpace first = StateSpace::from_tf(tf("s/(s+1)")), second = StateSpace::from_tf(tf("1/s"));
  const Siso s = Siso::from_state_space(SparseStateSpace(series(first, second)));
  EXPECT_EQ(s.factors(), 2);
  EXPECT_EQ(s.zpk().m(), 0);
  EXPECT_EQ(stability(s.zpk()), Stability::Stable);
  EXPECT_NEAR(*s.zpk().dc_gain(), 1.0, 1e-15);
  ASSERT_EQ(s.hidden().size(), 1u);
  EXPECT_EQ(s.hidden()[0], Complex(0.0, 0.0));
  // The same on z = 1: (z - 1)/(z - 0.5) then 0.5/(z - 1).
  const StateSpace d1 = StateSpace::from_tf(tf("(z-1)/(z-0.5)", 0.1)), d2 = StateSpace::from_tf(tf("0.5/(z-1)", 0.1));
  const Siso d = Siso::from_state_space(SparseStateSpace(series(d1, d2)));
  EXPECT_EQ(d.zpk().m(), 0);
  EXPECT_NEAR(*d.zpk().dc_gain(), 1.0, 1e-15);
  ASSERT_EQ(d.hidden().size(), 1u);
  EXPECT_EQ(d.hidden()[0], Complex(1.0, 0.0));
}

TEST(Siso, UnreachedAndUnseenGroupsAreHidden) {
  // x1' = -x1 + u (seen), x2' = -2 x2 + x1 (not seen), x3' = 0 (neither reached nor
  // seen: a free integrator). Transfer 1/(s + 1); hidden {-2, 0}; every mode listed.
  Matrix a(3, 3), b(3, 1), c(1, 3);
  a << -1, 0, 0, 1, -2, 0, 0, 0, 0;
  b << 1, 0, 0;
  c << 1, 0, 0;
  const Siso s = Siso::from_state_space(SparseStateSpace(StateSpace(a, b, c, Matrix::Zero(1, 1))));
  EXPECT_TRUE(roots_near(s.zpk().all_poles(), {Complex(-1.0, 0.0)}, 0.0));
  EXPECT_TRUE(roots_near(s.hidden(), {Complex(-2.0, 0.0), Complex(0.0, 0.0)}, 0.0));
  EXPECT_TRUE(roots_near(s.modes(), {Complex(-2.0, 0.0), Complex(-1.0, 0.0), Complex(0.0, 0.0)}, 0.0));
  EXPECT_EQ(stability(s.modes(), false), Stability::Marginal);
}

TEST(Siso, DiscreteClosedLoopWrittenAsAnExpressionCancelsItsPoleAtOne) {
  // Issue 13, item 1: L/(1 + L) with L = 0.1 (z - 0.9)/((z - 1)(z - 0.6)), written out,
  // keeps (z - 1)(z - 0.6) above and below. The roots at z = 1 are decided exactly
  // (Polynomial::without_root) and cancel: a hidden mode, not a pole at 0.99999999993.
  // The transfer is stable with DC gain 1 (1e-12) and its step figures exist.
  const std::string l = "0.1*(z-0.9)/((z-1)*(z-0.6))";
  const Siso s = Siso::from_tf(tf("(" + l + ")/(1 + " + l + ")", 0.001));
  EXPECT_EQ(s.zpk().m(), 0);
  ASSERT_EQ(s.hidden().size(), 1u);
  EXPECT_EQ(s.hidden()[0], Complex(1.0, 0.0));
  EXPECT_EQ(stability(s.zpk()), Stability::Stable);
  EXPECT_NEAR(*s.zpk().dc_gain(), 1.0, 1e-12);
  const Siso::Step st = s.step(0.5, 2);
  ASSERT_TRUE(st.info.rise_time_s && st.info.settling_time_s && st.info.final_value);
  EXPECT_NEAR(*st.info.final_value, 1.0, 1e-12);
  // The closed loop is z^2 - 1.5 z + 0.51 (+ the cancelled z - 0.6): slowest pole
  // 0.75 + sqrt(0.0525) = 0.979129..., so a 2 % settling of about 4 / (1 - 0.979) ms.
  EXPECT_GT(*st.info.settling_time_s, 0.05);
  EXPECT_LT(*st.info.settling_time_s, 0.4);
}

TEST(Siso, FromStateSpaceAgreesWithTheTransferFunction) {
  // Two formulations: the structural factorisation of a 3-block interconnection against
  // the TF of its dense realisation (StateSpace::to_tf) taken apart by roots. Poles,
  // zeros and k to 1e-9 relative (roots of degree <= 5 from a balanced companion
  // matrix).
  const StateSpace lead = StateSpace::from_tf(tf("(s/3 + 1)/(s/30 + 1)"));
  const StateSpace plant = StateSpace::from_tf(tf("5/(s^2 + 0.4*s + 4)"));
  const StateSpace lag = StateSpace::from_tf(tf("-2/(s/50 + 1)"));
  const StateSpace sys = series(series(lead, plant), lag);
  const Siso a = Siso::from_state_space(SparseStateSpace(sys));
  const Siso b = Siso::from_tf(sys.to_tf());
  EXPECT_TRUE(roots_near(a.zpk().all_poles(), b.zpk().all_poles(), 1e-9));
  EXPECT_TRUE(roots_near(a.zpk().all_zeros(), b.zpk().all_zeros(), 1e-9));
  EXPECT_NEAR(a.zpk().k(), b.zpk().k(), 1e-9 * std::abs(b.zpk().k()));
  EXPECT_NEAR(a.zpk().k(), -2.0 * 5.0 / 4.0, 1e-12 * 2.5);
}

// A random stable minimal n-state SISO system (dense A, shifted left).
StateSpace random_system(int n, unsigned seed, bool feedthrough) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> nd;
  Matrix a(n, n), b(n, 1), c(1, n), d = Matrix::Zero(1, 1);
  for (int i = 0; i < a.size(); ++i) a.data()[i] = nd(rng);
  for (int i = 0; i < n; ++i) b(i) = nd(rng), c(i) = nd(rng);
  if (feedthrough) d(0, 0) = nd(rng);
  return StateSpace(a - (std::sqrt(n) + 1.0) * Matrix::Identity(n, n), b, c, d);
}

// sigma_min / sigma_max of the system matrix [A - zI, b; c, d]: 0 at a zero.
double rosenbrock_residual(const StateSpace& s, Complex z) {
  const auto n = s.num_states();
  Eigen::MatrixXcd r(n + 1, n + 1);
  r.topLeftCorner(n, n) = s.a().cast<Complex>() - z * Eigen::MatrixXcd::Identity(n, n);
  r.topRightCorner(n, 1) = s.b().cast<Complex>();
  r.bottomLeftCorner(1, n) = s.c().cast<Complex>();
  r(n, n) = s.d()(0, 0);
  const Eigen::JacobiSVD<Eigen::MatrixXcd> svd(r);
  return svd.singularValues()(n) / svd.singularValues()(0);
}

TEST(Siso, ZerosByDeflationAreZerosOfTheSystemMatrix) {
  // Random systems of 3 to 30 states with and without feedthrough. Deflation: n or
  // n - 1 zeros, each making the system matrix singular to 1e-13 (rounding times the
  // conditioning of the orthogonal steps), and k = G(0) = d - c A^-1 b (another formula;
  // 1e-10 relative). Interpolation (the second formulation) agrees to 1e-7 up to 7
  // states; beyond, its polynomial roots drift (measured: 1e-9 residual at 15 states,
  // 3e-2 at 30), which is why Siso deflates.
  for (int n : {3, 7, 15, 30})
    for (bool ft : {false, true}) {
      const StateSpace s = random_system(n, static_cast<unsigned>(n * 2 + ft), ft);
      const std::vector<Complex> poles = s.poles();
      const Zpk b = zpk_by_deflation(s, poles);
      EXPECT_EQ(b.zeros().size(), static_cast<size_t>(ft ? n : n - 1)) << n;
      for (const Complex& z : b.zeros()) EXPECT_LT(rosenbrock_residual(s, z), 1e-13) << n << " " << ft << " " << z;
      const double dc = s.dc_gain()(0, 0);
      EXPECT_NEAR(b.k(), dc, 1e-10 * std::abs(dc)) << n << " " << ft;
      if (n <= 7) {
        const Zpk a = zpk_by_interpolation(s, poles);
        EXPECT_TRUE(roots_near(b.zeros(), a.zeros(), 1e-7)) << n << " " << ft;
        EXPECT_NEAR(b.k(), a.k(), 1e-10 * std::abs(a.k())) << n << " " << ft;
      }
    }
  // Relative degree 3: 1/((s+1)(s+2)(s+3)) has no zeros, and its k is 1/6.
  const StateSpace r3 = StateSpace::from_tf(tf("1/((s+1)*(s+2)*(s+3))"));
  const Zpk z3 = zpk_by_deflation(r3, r3.poles());
  EXPECT_TRUE(z3.zeros().empty());
  EXPECT_EQ(z3.m(), 0);
  EXPECT_NEAR(z3.k(), 1.0 / 6.0, 1e-14);
}

TEST(Siso, ZerosSurviveADeflationThatLeavesOnlyIntegrators) {
  // Found from Python (ss of a TF lost its zero; a loop's margins came out 15.7° instead
  // of 49.8°): when deflation leaves a reduced A of zero, the feedthrough was judged
  // against |A| = 0 and every d counted as zero. Exact zeros here: −4, −1.5; 1/s none.
  const StateSpace a = StateSpace::from_tf(tf("(s+4)/(s^2+2*s+10)"));
  const Zpk za = zpk_by_deflation(a, a.poles());
  ASSERT_EQ(za.zeros().size(), 1u);
  EXPECT_NEAR(std::abs(za.zeros()[0] - Complex(-4.0, 0.0)), 0.0, 1e-12);
  EXPECT_NEAR(za.k(), 0.4, 1e-12);  // G(0) = 4/10
  const StateSpace pi(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Constant(1, 1, 1.5),
                      Eigen::MatrixXd::Ones(1, 1));  // (s + 1.5)/s
  const Zpk zpi = zpk_by_deflation(pi, pi.poles());
  ASSERT_EQ(zpi.zeros().size(), 1u);
  EXPECT_NEAR(std::abs(zpi.zeros()[0] - Complex(-1.5, 0.0)), 0.0, 1e-12);
  const StateSpace integrator(Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Ones(1, 1),
                              Eigen::MatrixXd::Zero(1, 1));  // 1/s
  EXPECT_TRUE(zpk_by_deflation(integrator, integrator.poles()).zeros().empty());
}

TEST(Siso, BigFeedbackLoopIsOneFactor) {
  // A loop of 100 lags 1/(s/10 + 1) closed by -0.5: one strongly connected group of
  // 100 states. T = G/(1 + 0.5 G), G = (1 + s/10)^-100:
  // poles where (1 + s/10)^100 = -0.5, s = 10 ((0.5)^(1/100) e^{j (2k+1) pi/100} - 1),
  // no zeros, DC gain 1/1.5. 1e-9 relative on the poles (simple, well separated).
  const int n = 100;
  SparseStateSpace chain = lag_chain(std::vector<double>(n, 10.0), std::vector<double>(n, 1.0));
  SparseMatrix a = chain.a();
  a.coeffRef(0, n - 1) = -0.5 * 10.0;
  const Siso s = Siso::from_state_space(SparseStateSpace(a, chain.b(), chain.c(), chain.d()));
  EXPECT_EQ(s.factors(), 1);
  std::vector<Complex> want;
  for (int k = 0; k < n; ++k) want.push_back(10.0 * (std::pow(0.5, 1.0 / n) * std::polar(1.0, (2 * k + 1) * M_PI / n) - 1.0));
  EXPECT_TRUE(roots_near(s.zpk().all_poles(), want, 1e-9));
  EXPECT_TRUE(s.zpk().zeros().empty());
  EXPECT_NEAR(*s.zpk().dc_gain(), 1.0 / 1.5, 1e-9);
}

}  // namespace
}  // namespace dmbd::blocks
