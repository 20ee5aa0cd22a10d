// dmbd::blocks frequency responses: Bode magnitude/phase conventions, discrete
// responses, the Hessenberg state-space evaluation, margins and bandwidth.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>

#include "dmbd/blocks/delay.hpp"
#include "dmbd/blocks/discretize.hpp"
#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/frequency.hpp"
#include "dmbd/blocks/zpk.hpp"
#include "test_support.hpp"

namespace dmbd::blocks {
namespace {

using test::complex_near;

constexpr double kDeg = 180.0 / M_PI;

// The paper's force-loop Q filter, eq. frc_ctrl, with the 60 Hz cutoff of the text.
const double kWc = 2.0 * M_PI * 60.0;
TransferFunction paper_q() {
  return TransferFunction::parse("1/((s/wc)^2 + sqrt(2)*s/wc + 1)", {{"wc", kWc}});
}

TEST(Frequency, Logspace) {
  const std::vector<double> w = logspace(0.1, 1000.0, 5);
  ASSERT_EQ(w.size(), 5u);
  // Endpoints are exact; interior points are 10^k to 1 ulp-ish (1e-14 relative).
  EXPECT_EQ(w.front(), 0.1);
  EXPECT_EQ(w.back(), 1000.0);
  EXPECT_NEAR(w[1], 1.0, 1e-14);
  EXPECT_NEAR(w[2], 10.0, 1e-13);
  EXPECT_EQ(logspace(3.0, 4.0, 1), std::vector<double>{3.0});
  EXPECT_THROW(logspace(0.0, 1.0, 10), InputError);
  EXPECT_THROW(logspace(2.0, 1.0, 10), InputError);
}

TEST(Frequency, DefaultGridCoversTheDynamics) {
  const TransferFunction g = TransferFunction::parse("(s+10)/((s+0.1)*(s+1000))");
  const std::vector<double> w = default_frequency_grid(g, 50);
  ASSERT_EQ(w.size(), 50u);
  // Two decades beyond the slowest (0.1) and fastest (1000) roots: 1e-12 relative.
  EXPECT_NEAR(w.front(), 1e-3, 1e-15);
  EXPECT_NEAR(w.back(), 1e5, 1e-7);
  // Discrete: ends at Nyquist exactly (pi/ts, 1e-12 relative).
  const TransferFunction d = TransferFunction::parse("0.5/(z-0.5)", {}, 0.01);
  EXPECT_NEAR(default_frequency_grid(d).back(), M_PI / 0.01, 1e-12 * M_PI / 0.01);
}

TEST(Frequency, PaperButterworthAtCutoff) {
  // |Q(j wc)| = 1/|j^2 + sqrt2 j + 1| = 1/sqrt2 -> 20 log10(1/sqrt2) = -3.0103 dB,
  // phase -90 deg (eq. frc_ctrl). Tolerance 1e-9 absolute (brief), attainable ~1e-14.
  const Bode b = bode(paper_q(), {kWc});
  EXPECT_NEAR(b.mag_db[0], 20.0 * std::log10(1.0 / std::sqrt(2.0)), 1e-9);
  EXPECT_NEAR(b.mag_db[0], -3.0103, 1e-4);  // the rounded textbook value, 4 decimals
  EXPECT_NEAR(b.phase_deg[0], -90.0, 1e-9);
  // Well below / above: 0 dB, 0 deg and -40 dB/decade, -180 deg asymptotes.
  const Bode far = bode(paper_q(), {kWc * 1e-4, kWc * 1e4});
  EXPECT_NEAR(far.mag_db[0], 0.0, 1e-6);     // 10 log10(1 + 1e-16): exactly ~0
  EXPECT_NEAR(far.phase_deg[0], 0.0, 1e-2);  // -atan(sqrt2 1e-4) = -0.0081 deg
  EXPECT_NEAR(far.mag_db[1], -160.0, 1e-6);  // -40 dB/dec over 4 decades
  EXPECT_NEAR(far.phase_deg[1], -180.0, 1e-2);
}

TEST(Frequency, FirstOrderLagClosedForm) {
  const double a = 5.0;
  const TransferFunction g = TransferFunction(Polynomial({a}), Polynomial({a, 1.0}));
  const std::vector<double> w = logspace(0.01, 1e4, 31);
  const Bode b = bode(g, w);
  for (size_t k = 0; k < w.size(); ++k) {
    const double r = w[k] / a;
    // |a/(jw + a)| = 1/sqrt(1 + r^2), arg = -atan(r): 1e-12 absolute in dB and degrees.
    EXPECT_NEAR(b.mag_db[k], -10.0 * std::log10(1.0 + r * r), 1e-12) << "w = " << w[k];
    EXPECT_NEAR(b.phase_deg[k], -std::atan(r) * kDeg, 1e-12) << "w = " << w[k];
    // Raw response: 1e-15 relative (one complex division).
    EXPECT_TRUE(complex_near(b.response[k], a / Complex(a, w[k]), 1e-15));
  }
}

TEST(Frequency, DoubleIntegratorPhaseIsMinus180Everywhere) {
  const TransferFunction g = TransferFunction::parse("1/s^2");
  const std::vector<double> w = logspace(1e-3, 1e3, 13);
  const Bode b = bode(g, w);
  for (size_t k = 0; k < w.size(); ++k) {
    EXPECT_NEAR(b.phase_deg[k], -180.0, 1e-12) << "w = " << w[k];  // exact up to rounding
    EXPECT_NEAR(b.mag_db[k], -40.0 * std::log10(w[k]), 1e-11) << "w = " << w[k];
  }
}

TEST(Frequency, NonMinimumPhaseAllPassGoesTo180) {
  // (1 - s)/(s + 1): |H| = 1, phase = -2 atan(w): 0 at DC, -90 at 1, -> -180.
  const TransferFunction g = TransferFunction::parse("(1-s)/(s+1)");
  const std::vector<double> w = logspace(1e-3, 1e3, 25);
  const Bode b = bode(g, w);
  for (size_t k = 0; k < w.size(); ++k) {
    EXPECT_NEAR(b.mag_db[k], 0.0, 1e-12);                                 // all-pass, rounding only
    EXPECT_NEAR(b.phase_deg[k], -2.0 * std::atan(w[k]) * kDeg, 1e-10) << "w = " << w[k];  // 1e-10 deg
  }
  EXPECT_NEAR(b.phase_deg.front(), 0.0, 0.2);     // -2 atan(1e-3) = -0.115 deg
  EXPECT_NEAR(b.phase_deg.back(), -180.0, 0.2);   // -180 + 0.115 deg
  EXPECT_NEAR(bode(g, {1.0}).phase_deg[0], -90.0, 1e-12);
}

TEST(Frequency, NegativeGainStartsAtMinus180) {
  // -1/(s+1): K < 0 subtracts 180 deg (header convention): -180 - atan(w).
  const Bode b = bode(TransferFunction::parse("-1/(s+1)"), {1e-4, 1.0, 1e4});
  EXPECT_NEAR(b.phase_deg[0], -180.0 - std::atan(1e-4) * kDeg, 1e-10);  // 1e-10 deg
  EXPECT_NEAR(b.phase_deg[1], -225.0, 1e-10);
  EXPECT_NEAR(b.phase_deg[2], -270.0 + std::atan(1e-4) * kDeg, 1e-10);
}

TEST(Frequency, LightlyDampedResonancePhaseIsContinuous) {
  const double wn = 10.0, zeta = 0.01;
  const TransferFunction g(Polynomial({wn * wn}), Polynomial({wn * wn, 2.0 * zeta * wn, 1.0}));
  // -90 deg exactly at wn (the denominator is purely imaginary there): 1e-9 absolute.
  EXPECT_NEAR(bode(g, {wn}).phase_deg[0], -90.0, 1e-9);
  // Peak magnitude at wn: 1/(2 zeta) -> 20 log10(50) dB (1e-9 dB).
  EXPECT_NEAR(bode(g, {wn}).mag_db[0], 20.0 * std::log10(1.0 / (2.0 * zeta)), 1e-9);
  // A coarse grid that steps right over the resonance (7 points per decade): the phase
  // is the exact factor phase -atan2(2 zeta w wn, wn^2 - w^2) in [-180, 0], with no
  // 360-degree jumps, monotonically decreasing.
  const std::vector<double> w = logspace(0.1, 1000.0, 29);
  const Bode b = bode(g, w);
  for (size_t k = 0; k < w.size(); ++k) {
    const double want = -std::atan2(2.0 * zeta * w[k] * wn, wn * wn - w[k] * w[k]) * kDeg;
    EXPECT_NEAR(b.phase_deg[k], want, 1e-9) << "w = " << w[k];  // 1e-9 deg absolute
    if (k > 0) {
      EXPECT_LE(b.phase_deg[k], b.phase_deg[k - 1] + 1e-12) << "w = " << w[k];  // monotone (rounding slack)
      EXPECT_LT(std::abs(b.phase_deg[k] - b.phase_deg[k - 1]), 180.0) << "jump at w = " << w[k];
    }
  }
}

TEST(Frequency, DiscreteResponseOnTheUnitCircle) {
  const double ts = 0.1;
  const TransferFunction g = TransferFunction::parse("0.5/(z - 0.5)", {}, ts);
  const std::vector<double> w = {0.01, 1.0, 10.0, 30.0, 31.0};  // Nyquist = 31.4 rad/s
  const std::vector<Complex> h = frequency_response(g, w);
  const Bode b = bode(g, w);
  for (size_t k = 0; k < w.size(); ++k) {
    const Complex z = std::polar(1.0, w[k] * ts);
    // One complex division: 1e-15 relative.
    EXPECT_TRUE(complex_near(h[k], 0.5 / (z - 0.5), 1e-15)) << "w = " << w[k];
    // Phase in (-180, 0]: the principal argument, 1e-12 deg.
    EXPECT_NEAR(b.phase_deg[k], std::arg(0.5 / (z - 0.5)) * kDeg, 1e-12) << "w = " << w[k];
  }
  // A discrete integrator T/(z - 1): T e^{-j wT/2} / (2 j sin(wT/2)), phase -90 - wT/2.
  const TransferFunction integ = TransferFunction::parse("0.1/(z-1)", {}, ts);
  const Bode bi = bode(integ, {1.0, 20.0});
  EXPECT_NEAR(bi.phase_deg[0], -90.0 - 0.05 * kDeg, 1e-10);  // 1e-10 deg
  EXPECT_NEAR(bi.phase_deg[1], -90.0 - 1.0 * kDeg, 1e-10);
  EXPECT_NEAR(bi.mag_db[0], 20.0 * std::log10(0.1 / (2.0 * std::sin(0.05))), 1e-10);
}

TEST(Frequency, DiscretePhaseIsUnwrappedThroughPolesAtTheOrigin) {
  // z^-3: phase -3 w T exactly (no wrapping into (-180, 180]): -540 deg at Nyquist.
  const double ts = 0.1;
  const std::vector<double> w = {1.0, 10.0, 20.0, 30.0, M_PI / ts};
  const Bode b = bode(sample_delay(3, ts), w);
  for (size_t k = 0; k < w.size(); ++k) {
    EXPECT_NEAR(b.phase_deg[k], -3.0 * w[k] * ts * kDeg, 1e-9) << "w = " << w[k];  // 1e-9 deg
    EXPECT_NEAR(b.mag_db[k], 0.0, 1e-12);                                            // |z^-3| = 1
  }
  // ZOH of 1/s^2 = T^2 (z + 1) / (2 (z - 1)^2): phase = w T/2 - 2 (90 + w T/2) = -180 - w T/2.
  const TransferFunction gz = c2d(TransferFunction::parse("1/s^2"), ts, C2dMethod::Zoh);
  const Bode bz = bode(gz, {0.1, 1.0, 10.0, 30.0});
  for (size_t k = 0; k < bz.w_rad_s.size(); ++k)
    EXPECT_NEAR(bz.phase_deg[k], -180.0 - bz.w_rad_s[k] * ts / 2.0 * kDeg, 1e-9) << "w = " << bz.w_rad_s[k];
}

TEST(Frequency, PhaseIsABranchOfArgAndContinuousOnADenseGrid) {
  // For a mix of systems (RHP poles and zeros, negative gain, integrators, poles at
  // z = 0 and z = 1, zeros outside the unit circle) the Bode phase is a branch of
  // arg(response) (1e-9 deg) and has no 360-degree jumps: with 2000 log-spaced points
  // (0.5-0.9 % per step) the largest physical change per step is ~35 deg (at the
  // zeta = 0.025 zero pair), so any step above 90 deg is a wrapping error. Its end
  // points follow the factor-wise convention of the header.
  struct Case {
    const char* text;
    double ts;
    double phase_at_low, phase_at_high;  // expected limits (deg), tolerance below
  };
  for (const Case c : {Case{"(s-2)*(s^2+0.1*s+4)/((s+1)*(s-3)*(s^2+0.5*s+25))", 0.0, 0.0, -90.0},
                       Case{"-3*(s+1)/(s^2*(s-1))", 0.0, -180.0, 0.0},
                       Case{"(z+2)*(z^2-0.5*z+0.9)/(z*(z+0.5)*(z^2-1.6*z+0.8))", 0.01, 0.0, -360.0},
                       Case{"-(z-1.5)/((z-1)*(z+0.9))", 0.1, -90.0, -360.0},
                       Case{"(z-1)^2/(z^3*(z-0.2))", 0.1, 180.0, -360.0}}) {
    SCOPED_TRACE(c.text);
    const TransferFunction g = TransferFunction::parse(c.text, {}, c.ts);
    const double lo = c.ts > 0 ? 1e-3 : 1e-4, hi = c.ts > 0 ? 0.9999 * M_PI / c.ts : 1e4;
    const std::vector<double> w = logspace(lo, hi, 2000);
    const Bode b = bode(g, w);
    for (size_t k = 0; k < w.size(); ++k) {
      const double a = std::arg(b.response[k]) * kDeg;
      EXPECT_NEAR(std::remainder(b.phase_deg[k] - a, 360.0), 0.0, 1e-9) << "w = " << w[k];
      if (k > 0) {
        EXPECT_LT(std::abs(b.phase_deg[k] - b.phase_deg[k - 1]), 90.0) << "w = " << w[k];
      }
    }
    // The end points are within 1 deg of the limits (the grid stops short of 0 and of
    // infinity / Nyquist).
    EXPECT_NEAR(b.phase_deg.front(), c.phase_at_low, 1.0);
    EXPECT_NEAR(b.phase_deg.back(), c.phase_at_high, 1.0);
  }
}

TEST(Frequency, HighOrderBodeStaysFiniteWhereItsPowersOfWOverflow) {
  // 1/(s+1)^40 at w = 1e10: (jw)^40 = 1e400 overflows a double, so num/den evaluated
  // in s gives 0 (-inf dB). The response evaluated in 1/s above w = 1 keeps
  // |G| = (1 + w^2)^-20 and arg G = -40 atan w. Tolerance: the expanded coefficients'
  // rounding, amplified by at most ((1 + w)^2/(1 + w^2))^20 <= 2^20 at w = 1, gives
  // 1e-10 relative in |G|: 1e-8 dB and 1e-7 deg.
  const TransferFunction g = TransferFunction::parse("1/(s+1)^40");
  const std::vector<double> w{1e-3, 0.5, 1.0, 2.0, 1e3, 1e10, 1e150};
  const Bode b = bode(g, w);
  for (size_t k = 0; k < w.size(); ++k) {
    const double x = w[k] * w[k];
    const double expected_mag = std::isfinite(x) ? -400.0 * std::log10(1.0 + x) : -800.0 * std::log10(w[k]);
    EXPECT_NEAR(b.mag_db[k], expected_mag, 1e-8 * std::max(1.0, std::abs(expected_mag))) << w[k];
    EXPECT_NEAR(b.phase_deg[k], -40.0 * std::atan(w[k]) * kDeg, 1e-7) << w[k];
  }
  // The response itself underflows to 0 there, as the true value does.
  EXPECT_EQ(b.response.back(), Complex(0.0));
  // Discrete, 1/(z + 0.5)^40 on the unit circle (|z| = 1 needs no scaling):
  // |G| = |e^{jw ts} + 0.5|^-40 away from z = -1, where the coefficients cancel
  // (1e-9 relative in dB).
  const double ts = 0.01;
  const TransferFunction gz = TransferFunction::parse("1/(z+0.5)^40", {}, ts);
  const Bode bz = bode(gz, {1.0, 50.0, 100.0});
  for (size_t k = 0; k < bz.w_rad_s.size(); ++k) {
    const double expected = -800.0 * std::log10(std::abs(std::polar(1.0, bz.w_rad_s[k] * ts) + 0.5));
    EXPECT_NEAR(bz.mag_db[k], expected, 1e-9 * std::abs(expected)) << bz.w_rad_s[k];
  }
}

TEST(Frequency, BodePhaseIsTheFactorModelAtHighOrder) {
  // 24 poles and 16 zeros spread over four decades, damping 0.05-0.9, a quarter of
  // them in the right half-plane: bode() takes the branch from an approximate factor
  // phase (a polynomial arctangent per root), bode(Zpk) sums each factor's exact
  // phase. Equal to 1e-6 deg and 1e-6 dB at 3000 frequencies (the expanded
  // coefficients carry rounding that the 40th-order evaluation amplifies).
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> decade(-1.0, 3.0), damping(0.05, 0.9), unit(0.0, 1.0);
  std::vector<Complex> poles, zeros;
  auto add_pair = [&](std::vector<Complex>& to) {
    const double wn = std::pow(10.0, decade(rng)), z = unit(rng) < 0.25 ? -damping(rng) : damping(rng);
    to.push_back({-z * wn, wn * std::sqrt(1.0 - z * z)});
    to.push_back(std::conj(to.back()));
  };
  for (int k = 0; k < 12; ++k) add_pair(poles);
  for (int k = 0; k < 8; ++k) add_pair(zeros);
  const Zpk exact(1.0, 0, zeros, poles);
  const TransferFunction g = *exact.to_tf();
  const std::vector<double> w = logspace(1e-3, 1e5, 3000);
  const Bode a = bode(exact, w), b = bode(g, w);
  for (size_t k = 0; k < w.size(); ++k) {
    ASSERT_NEAR(a.phase_deg[k], b.phase_deg[k], 1e-6) << "w = " << w[k];
    ASSERT_NEAR(a.mag_db[k], b.mag_db[k], 1e-6) << "w = " << w[k];
  }
}

TEST(Frequency, StateSpaceHessenbergMatchesTransferFunction) {
  // A 10-state system with known poles and zeros, realised and then scrambled by a
  // random similarity so that A is dense.
  const TransferFunction g(Polynomial::from_roots({-0.3, 2.0, {-1.0, 4.0}, {-1.0, -4.0}, -7.0, -20.0}, 3.0),
                           Polynomial::from_roots({-0.5, -1.5, {-0.2, 2.0}, {-0.2, -2.0}, -4.0, {-3.0, 9.0},
                                                   {-3.0, -9.0}, -30.0, -60.0, -0.05}));
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Matrix t = Matrix::Identity(10, 10);
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) t(i, j) += 0.3 * u(rng);
  const StateSpace ss = StateSpace::from_tf(g).transformed(t);
  const std::vector<double> w = logspace(0.01, 1000.0, 40);
  const std::vector<Eigen::MatrixXcd> hs = frequency_response(ss, w);
  const std::vector<Complex> ht = frequency_response(g, w);
  ASSERT_EQ(hs.size(), w.size());
  for (size_t k = 0; k < w.size(); ++k) {
    ASSERT_EQ(hs[k].rows(), 1);
    ASSERT_EQ(hs[k].cols(), 1);
    // Hessenberg solve vs polynomial evaluation of the TF: 1e-9 relative (brief).
    EXPECT_TRUE(complex_near(hs[k](0, 0), ht[k], 1e-9)) << "w = " << w[k];
  }
}

TEST(Frequency, StateSpaceHessenbergMatchesDirectSolveMimo) {
  // A random dense 10-state, 3-input, 2-output system (continuous and discrete): the
  // Hessenberg evaluation equals an independent LU solve C (xI - A)^-1 B + D.
  std::mt19937 rng(99);
  std::normal_distribution<double> n01(0.0, 1.0);
  Matrix a(10, 10), b(10, 3), c(2, 10), d(2, 3);
  for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] = n01(rng);
  for (Eigen::Index i = 0; i < b.size(); ++i) b.data()[i] = n01(rng);
  for (Eigen::Index i = 0; i < c.size(); ++i) c.data()[i] = n01(rng);
  for (Eigen::Index i = 0; i < d.size(); ++i) d.data()[i] = n01(rng);
  for (const double ts : {0.0, 0.05}) {
    const StateSpace ss(ts > 0 ? Matrix(0.2 * a) : Matrix(a - 5.0 * Matrix::Identity(10, 10)), b, c, d, ts);
    const std::vector<double> w = {0.1, 1.0, 3.0, 10.0, 50.0};
    const auto h = frequency_response(ss, w);
    for (size_t k = 0; k < w.size(); ++k) {
      const Complex x = ts > 0 ? std::polar(1.0, w[k] * ts) : Complex(0.0, w[k]);
      const Eigen::MatrixXcd want = ss.evaluate(x);
      // Norm-wise relative 1e-9 (brief), attainable ~1e-13.
      EXPECT_LT((h[k] - want).norm(), 1e-9 * want.norm()) << "ts = " << ts << ", w = " << w[k];
    }
  }
}

// ---------------------------------------------------------------------------------------
// Margins.

TEST(Margins, ThirdOrderLoopKnownCrossovers) {
  // L = 10/(s (s+1)(s+5)): phase -90 - atan(w) - atan(w/5) = -180 at w^2 = 5; there
  // |L| = 10/(sqrt5 sqrt6 sqrt30) = 1/3 -> GM = 20 log10 3 = 9.54 dB.
  const TransferFunction l = TransferFunction::parse("10/(s*(s+1)*(s+5))");
  const Margins m = margins(l);
  ASSERT_TRUE(m.gain_margin_db && m.phase_crossover_rad_s);
  // Polynomial roots refined by Newton on L: 1e-10 relative.
  EXPECT_NEAR(*m.phase_crossover_rad_s, std::sqrt(5.0), 1e-10 * std::sqrt(5.0));
  EXPECT_NEAR(*m.gain_margin_db, 20.0 * std::log10(3.0), 1e-9);  // 1e-9 dB absolute
  ASSERT_EQ(m.phase_crossovers.size(), 1u);
  ASSERT_EQ(m.gain_crossovers.size(), 1u);
  ASSERT_TRUE(m.phase_margin_deg && m.gain_crossover_rad_s);
  const double wg = *m.gain_crossover_rad_s;
  const Complex lg = l.evaluate(Complex(0.0, wg));
  // |L(j wg)| = 1 by evaluation (1e-12 relative after Newton refinement).
  EXPECT_NEAR(std::abs(lg), 1.0, 1e-12);
  // PM = 180 + angle(L) (the angle is in (-180, -90) here: no wrapping), 1e-9 deg.
  EXPECT_NEAR(*m.phase_margin_deg, 180.0 + std::arg(lg) * kDeg, 1e-9);
  // Independently: wg^2 = x solves x (x + 1)(x + 25) = 100; bisection in the test.
  double lo = 0.0, hi = 10.0;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (mid * (mid + 1.0) * (mid + 25.0) < 100.0 ? lo : hi) = mid;
  }
  EXPECT_NEAR(wg, std::sqrt(lo), 1e-12);  // bisection to rounding, then sqrt: 1e-12 absolute
  // PM from the closed form 90 - atan(wg) - atan(wg/5) (1e-9 deg).
  EXPECT_NEAR(*m.phase_margin_deg, 90.0 - (std::atan(wg) + std::atan(wg / 5.0)) * kDeg, 1e-9);
  EXPECT_GT(*m.phase_margin_deg, 0.0);  // a stable closed loop
}

TEST(Margins, UnstableLoopHasNegativeMargins) {
  // L = 50/(s (s+1)(s+5)): same phase crossover sqrt5, |L| = 5/3 -> GM = -4.437 dB.
  const Margins m = margins(TransferFunction::parse("50/(s*(s+1)*(s+5))"));
  ASSERT_TRUE(m.gain_margin_db && m.phase_margin_deg);
  EXPECT_NEAR(*m.gain_margin_db, -20.0 * std::log10(5.0 / 3.0), 1e-9);  // 1e-9 dB absolute
  EXPECT_NEAR(*m.phase_crossover_rad_s, std::sqrt(5.0), 1e-10 * std::sqrt(5.0));  // 1e-10 relative
  EXPECT_LT(*m.phase_margin_deg, 0.0);
  EXPECT_GT(*m.phase_margin_deg, -180.0);
}

TEST(Margins, SecondOrderLoopClosedFormPhaseMargin) {
  // L = k/(s (s+1)): |L| = 1 at wc^2 = (sqrt(1 + 4k^2) - 1)/2, PM = 90 - atan(wc);
  // the phase never reaches -180: no gain margin.
  for (const double k : {0.5, 4.0, 100.0}) {
    const TransferFunction l(Polynomial({k}), Polynomial({0.0, 1.0, 1.0}));
    const Margins m = margins(l);
    const double wc = std::sqrt((std::sqrt(1.0 + 4.0 * k * k) - 1.0) / 2.0);
    ASSERT_TRUE(m.phase_margin_deg.has_value()) << "k = " << k;
    EXPECT_NEAR(*m.gain_crossover_rad_s, wc, 1e-12 * wc) << "k = " << k;                       // 1e-12 relative
    EXPECT_NEAR(*m.phase_margin_deg, 90.0 - std::atan(wc) * kDeg, 1e-9) << "k = " << k;  // 1e-9 deg
    EXPECT_FALSE(m.gain_margin_db.has_value()) << "k = " << k;
    EXPECT_TRUE(m.phase_crossovers.empty()) << "k = " << k;
  }
}

TEST(Margins, NoGainCrossover) {
  // L = 0.1/(s+1): |L| < 1 everywhere: no phase margin; phase never -180: no GM.
  const Margins m = margins(TransferFunction::parse("0.1/(s+1)"));
  EXPECT_FALSE(m.phase_margin_deg.has_value());
  EXPECT_FALSE(m.gain_margin_db.has_value());
  EXPECT_TRUE(m.gain_crossovers.empty());
}

TEST(Margins, MultipleCrossoversPickTheSmallest) {
  // L = 200 (s+1)^2 / (s^3 (s+10)^2): phase -270 + 2 atan(w) - 2 atan(w/10) rises to
  // -160 deg at w = sqrt(10) and falls back, so it crosses -180 deg twice. Every
  // reported crossover must satisfy its defining equation.
  const TransferFunction l = TransferFunction::parse("200*(s+1)^2/(s^3*(s+10)^2)");
  const Margins m = margins(l);
  ASSERT_FALSE(m.gain_crossovers.empty());
  ASSERT_EQ(m.phase_crossovers.size(), 2u);
  for (const Crossing& c : m.gain_crossovers) {
    const Complex v = l.evaluate(Complex(0.0, c.w_rad_s));
    EXPECT_NEAR(std::abs(v), 1.0, 1e-10) << "gain crossover at " << c.w_rad_s;  // 1e-10 relative
  }
  for (const Crossing& c : m.phase_crossovers) {
    const Complex v = l.evaluate(Complex(0.0, c.w_rad_s));
    // Real negative: the imaginary part vanishes relative to |L| (1e-9).
    EXPECT_LT(v.real(), 0.0) << c.w_rad_s;
    EXPECT_LT(std::abs(v.imag()), 1e-9 * std::abs(v)) << c.w_rad_s;
    EXPECT_NEAR(c.margin, -20.0 * std::log10(std::abs(v)), 1e-9);  // 1e-9 dB
  }
  // Sorted by frequency, and the reported margin is the one of smallest magnitude.
  for (size_t k = 1; k < m.phase_crossovers.size(); ++k)
    EXPECT_LT(m.phase_crossovers[k - 1].w_rad_s, m.phase_crossovers[k].w_rad_s);
  double smallest = 1e300;
  for (const Crossing& c : m.phase_crossovers) smallest = std::min(smallest, std::abs(c.margin));
  EXPECT_EQ(std::abs(*m.gain_margin_db), smallest);  // the same number is reported (exact)
}

TEST(Margins, DiscreteTustinLoopMatchesContinuousExactly) {
  // Tustin maps jw_c to e^{j w_d T} with w_c = (2/T) tan(w_d T/2): the loop values are
  // identical, so GM and PM are identical and the crossover frequencies are warped.
  const TransferFunction l = TransferFunction::parse("10/(s*(s+1)*(s+5))");
  const double ts = 0.01;
  const TransferFunction ld = c2d(l, ts, C2dMethod::Tustin);
  const Margins mc = margins(l), md = margins(ld);
  ASSERT_TRUE(md.gain_margin_db && md.phase_margin_deg);
  // Same numbers up to the roundings of the substitution: 1e-9 dB / deg absolute.
  EXPECT_NEAR(*md.gain_margin_db, *mc.gain_margin_db, 1e-9);
  EXPECT_NEAR(*md.phase_margin_deg, *mc.phase_margin_deg, 1e-9);
  auto warp = [&](double wc) { return 2.0 / ts * std::atan(wc * ts / 2.0); };
  EXPECT_NEAR(*md.phase_crossover_rad_s, warp(std::sqrt(5.0)), 1e-9);  // 1e-9 rad/s
  EXPECT_NEAR(*md.gain_crossover_rad_s, warp(*mc.gain_crossover_rad_s), 1e-9);
  // Direct evaluation at the reported crossovers: |L| = 1 and angle = -180 deg (1e-9).
  const Complex lg = ld.evaluate(std::polar(1.0, *md.gain_crossover_rad_s * ts));
  EXPECT_NEAR(std::abs(lg), 1.0, 1e-9);
  EXPECT_NEAR(*md.phase_margin_deg, 180.0 + std::arg(lg) * kDeg, 1e-9);
  const Complex lp = ld.evaluate(std::polar(1.0, *md.phase_crossover_rad_s * ts));
  EXPECT_NEAR(std::abs(std::arg(lp)) * kDeg, 180.0, 1e-9);
  EXPECT_NEAR(*md.gain_margin_db, -20.0 * std::log10(std::abs(lp)), 1e-9);
}

// L(e^{j theta}) of a discrete TF evaluated in long double (64-bit mantissa) from its
// double coefficients: a reference for loops whose poles cluster near z = 1, where the
// double-precision Horner evaluation of the expanded polynomials loses ~1e-8 relative.
std::complex<long double> evaluate_ld(const TransferFunction& g, long double theta) {
  const std::complex<long double> z = std::polar(1.0L, theta);
  auto horner = [&](const Polynomial& p) {
    std::complex<long double> v = 0.0L;
    for (auto it = p.coeffs().rbegin(); it != p.coeffs().rend(); ++it) v = v * z + static_cast<long double>(*it);
    return v;
  };
  return horner(g.num()) / horner(g.den());
}

TEST(Margins, DiscreteZohLoopAtSmallTsApproachesContinuous) {
  // ZOH adds about w T/2 of phase lag: at T = 1 ms that is 0.035-0.064 deg at these
  // crossovers, moving GM by ~0.03 dB. Tolerances 0.1 deg / 0.1 dB / 0.5 % in w.
  const TransferFunction l = TransferFunction::parse("10/(s*(s+1)*(s+5))");
  const double ts = 1e-3;
  const TransferFunction ld = c2d(l, ts, C2dMethod::Zoh);
  const Margins mc = margins(l), md = margins(ld);
  ASSERT_TRUE(md.gain_margin_db && md.phase_margin_deg);
  EXPECT_NEAR(*md.gain_margin_db, *mc.gain_margin_db, 0.1);
  EXPECT_NEAR(*md.phase_margin_deg, *mc.phase_margin_deg, 0.1);
  EXPECT_NEAR(*md.phase_crossover_rad_s, *mc.phase_crossover_rad_s, 5e-3 * *mc.phase_crossover_rad_s);
  EXPECT_NEAR(*md.gain_crossover_rad_s, *mc.gain_crossover_rad_s, 5e-3 * *mc.gain_crossover_rad_s);
  // The sign of the change: the extra lag reduces both margins.
  EXPECT_LT(*md.phase_margin_deg, *mc.phase_margin_deg);
  EXPECT_LT(*md.gain_margin_db, *mc.gain_margin_db);
  // The reported crossovers satisfy their definitions when L is evaluated accurately:
  // the long-double reference is good to ~3e-10 here (|den| ~ 1e-8 against O(1)
  // coefficients), so 1e-9 on |L| - 1 and on Im L / |L|.
  const auto lg = evaluate_ld(ld, static_cast<long double>(*md.gain_crossover_rad_s) * ts);
  EXPECT_NEAR(static_cast<double>(std::abs(lg)), 1.0, 1e-9);
  const auto lp = evaluate_ld(ld, static_cast<long double>(*md.phase_crossover_rad_s) * ts);
  EXPECT_LT(static_cast<double>(lp.real()), 0.0);
  EXPECT_LT(static_cast<double>(std::abs(lp.imag() / std::abs(lp))), 1e-9);
  // The reported values are computed with double evaluation of the same ill-conditioned
  // polynomials (condition ~1e9 here): 1e-6 dB / deg absolute.
  EXPECT_NEAR(*md.gain_margin_db, -20.0 * std::log10(static_cast<double>(std::abs(lp))), 1e-6);
  EXPECT_NEAR(*md.phase_margin_deg, 180.0 + static_cast<double>(std::arg(lg)) * kDeg, 1e-6);
}

TEST(Margins, DiscreteZohLoopMatchesDirectEvaluation) {
  // At T = 10 ms the double evaluation of the discrete loop is accurate to ~1e-11, so
  // the reported crossovers are checked against it directly: |L| = 1 and
  // angle = -180 deg to 1e-9, margins equal to the evaluated ones to 1e-9.
  const TransferFunction l = TransferFunction::parse("10/(s*(s+1)*(s+5))");
  const double ts = 0.01;
  const TransferFunction ld = c2d(l, ts, C2dMethod::Zoh);
  const Margins mc = margins(l), md = margins(ld);
  ASSERT_TRUE(md.gain_margin_db && md.phase_margin_deg);
  const Complex lg = ld.evaluate(std::polar(1.0, *md.gain_crossover_rad_s * ts));
  EXPECT_NEAR(std::abs(lg), 1.0, 1e-9);
  EXPECT_NEAR(*md.phase_margin_deg, 180.0 + std::arg(lg) * kDeg, 1e-9);
  const Complex lp = ld.evaluate(std::polar(1.0, *md.phase_crossover_rad_s * ts));
  EXPECT_NEAR(std::abs(std::arg(lp)) * kDeg, 180.0, 1e-9);
  EXPECT_NEAR(*md.gain_margin_db, -20.0 * std::log10(std::abs(lp)), 1e-9);
  // Still close to the continuous margins: the half-sample lag w T/2 is 0.35 deg at
  // the gain crossover and 0.64 deg at the phase crossover (GM moves ~0.26 dB).
  // Tolerances: 1 deg and 0.5 dB.
  EXPECT_NEAR(*md.phase_margin_deg, *mc.phase_margin_deg, 1.0);
  EXPECT_NEAR(*md.gain_margin_db, *mc.gain_margin_db, 0.5);
}

TEST(Margins, DiscreteLoopAtVerySmallTsStaysClose) {
  // At T = 0.1 ms the discrete loop's poles sit within 5e-4 of z = 1, the expanded
  // z-polynomials are conditioned ~1e12, and the margins (computed by evaluating them
  // in double) carry ~1e-5 relative error. Tustin is mathematically exact here, so the
  // deviation from the continuous margins measures that error: 1e-3 dB / 1e-2 deg.
  const TransferFunction l = TransferFunction::parse("10/(s*(s+1)*(s+5))");
  const Margins mc = margins(l);
  const Margins md = margins(c2d(l, 1e-4, C2dMethod::Tustin));
  ASSERT_TRUE(md.gain_margin_db && md.phase_margin_deg);
  EXPECT_NEAR(*md.gain_margin_db, *mc.gain_margin_db, 1e-3);
  EXPECT_NEAR(*md.phase_margin_deg, *mc.phase_margin_deg, 1e-2);
  // The crossover frequency is the warped continuous one up to the perturbation that
  // rounding the discrete coefficients causes at this conditioning (observed 2e-9
  // relative): 1e-7 relative.
  EXPECT_NEAR(*md.phase_crossover_rad_s, 2.0 / 1e-4 * std::atan(std::sqrt(5.0) * 1e-4 / 2.0), 1e-7 * std::sqrt(5.0));
}

// ---------------------------------------------------------------------------------------
// Bandwidth.

TEST(Bandwidth, FirstOrderLagClosedForm) {
  // |a/(jw + a)|^2 = 10^(-3/10) -> w = a sqrt(10^0.3 - 1) (the -3 dB definition, not
  // -3.0103 dB, so slightly below a). 1e-12 relative: a Newton-refined root.
  for (const double a : {0.1, 2.0, 500.0}) {
    const auto bw = bandwidth(TransferFunction(Polynomial({a}), Polynomial({a, 1.0})));
    ASSERT_TRUE(bw.has_value());
    const double want = a * std::sqrt(std::pow(10.0, 0.3) - 1.0);
    EXPECT_NEAR(*bw, want, 1e-12 * want) << "a = " << a;
  }
  // With a gain: 7/(s+2) has the same bandwidth as 2/(s+2) (relative to |G(0)|).
  EXPECT_NEAR(*bandwidth(TransferFunction::parse("7/(s+2)")), 2.0 * std::sqrt(std::pow(10.0, 0.3) - 1.0), 1e-12);
}

TEST(Bandwidth, ButterworthSecondOrderClosedForm) {
  // |Q(jw)|^2 = 1/(1 + (w/wc)^4) = 10^-0.3 -> w = wc (10^0.3 - 1)^(1/4), close to wc.
  const auto bw = bandwidth(paper_q());
  ASSERT_TRUE(bw.has_value());
  const double want = kWc * std::pow(std::pow(10.0, 0.3) - 1.0, 0.25);
  EXPECT_NEAR(*bw, want, 1e-12 * want);     // 1e-12 relative
  EXPECT_NEAR(*bw, kWc, 2e-3 * kWc);        // (10^0.3 - 1)^(1/4) = 0.9988: within 0.2 % of wc
  // With the exact half-power drop the bandwidth is wc itself (1e-12 relative).
  EXPECT_NEAR(*bandwidth(paper_q(), 20.0 * std::log10(1.0 / std::sqrt(2.0))), kWc, 1e-12 * kWc);
}

TEST(Bandwidth, EmptyCases) {
  EXPECT_FALSE(bandwidth(TransferFunction::parse("1/s")).has_value());      // infinite DC gain
  EXPECT_FALSE(bandwidth(TransferFunction::parse("s/(s+1)")).has_value());  // zero DC gain
  // (s+1.2)/(s+1) falls from 1.2 to 1 (-1.6 dB): never 3 dB down.
  EXPECT_FALSE(bandwidth(TransferFunction::parse("(s+1.2)/(s+1)")).has_value());
}

TEST(Bandwidth, DiscreteTustinWarpsExactly) {
  // Tustin of a/(s+a): the discrete -3 dB point is the warped continuous one,
  // w_d = (2/T) atan(w_c T/2) (1e-10 relative).
  const double a = 20.0, ts = 0.01;
  const auto bw = bandwidth(c2d(TransferFunction(Polynomial({a}), Polynomial({a, 1.0})), ts, C2dMethod::Tustin));
  ASSERT_TRUE(bw.has_value());
  const double wc = a * std::sqrt(std::pow(10.0, 0.3) - 1.0);
  EXPECT_NEAR(*bw, 2.0 / ts * std::atan(wc * ts / 2.0), 1e-10 * wc);
}

}  // namespace
}  // namespace dmbd::blocks
