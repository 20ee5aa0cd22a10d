// dmbd::blocks::Zpk: the zero-pole-gain form normalised at DC, its frequency response
// against closed forms and against the polynomial evaluation, its margins and
// bandwidth against closed forms and against the polynomial-root method of
// frequency.cpp (two formulations), and the stability verdict (issue 13, item 1).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/zpk.hpp"
#include "test_support.hpp"

namespace dmbd::blocks {
namespace {

using test::roots_near;

constexpr double kDeg = 180.0 / M_PI;

TransferFunction tf(const char* e, double ts = 0.0) { return TransferFunction::parse(e, {}, ts); }

// n equal lags 1/(tau s + 1).
Zpk lag_chain(int n, double tau) { return Zpk(1.0, 0, {}, std::vector<Complex>(static_cast<size_t>(n), {-1.0 / tau, 0.0})); }

TEST(Zpk, BoundaryRootsAreCountedExactly) {
  // 10/(s (s+1) (s/5+1)): one pole at the origin, k = 10 (the DC gain of s L).
  const Zpk a = Zpk::from_tf(tf("10/(s*(s+1)*(s/5+1))"));
  EXPECT_EQ(a.m(), -1);
  EXPECT_EQ(a.k(), 10.0);  // 50/5, exact in double
  EXPECT_TRUE(roots_near(a.poles(), {-1.0, -5.0}, 1e-14));
  EXPECT_FALSE(a.dc_gain().has_value());
  // The discrete loop of issue 13: 0.1 (z - 0.9)/((z - 1)(z - 0.6)): the pole at z = 1
  // is m = -1 and k = 0.1 (1 - 0.9)/(1 - 0.6) = 0.025 (a few ulps).
  const Zpk d = Zpk::from_tf(tf("0.1*(z-0.9)/((z-1)*(z-0.6))", 0.001));
  EXPECT_EQ(d.m(), -1);
  EXPECT_NEAR(d.k(), 0.025, 1e-16);
  EXPECT_EQ(d.all_poles().back(), Complex(1.0, 0.0));  // exactly 1, not 1.0000000000000002
  // A common factor (z - 1) cancels exactly: L/(1 + L) written out is stable, DC gain 1.
  const Zpk t = Zpk::from_tf(tf("0.1*(z-0.9)*(z-1)*(z-0.6)/((z-1)*(z-0.6)*((z-1)*(z-0.6) + 0.1*(z-0.9)))", 0.001));
  EXPECT_EQ(t.m(), 0);
  EXPECT_NEAR(*t.dc_gain(), 1.0, 1e-12);
  EXPECT_EQ(stability(t), Stability::Stable);
  // A zero at DC: gain 0 exactly.
  EXPECT_EQ(*Zpk::from_tf(tf("s/(s+1)")).dc_gain(), 0.0);
  EXPECT_THROW(Zpk(1.0, 0, {}, {Complex(0.0, 0.0)}), InputError);  // boundary roots belong in m
}

TEST(Zpk, ResponseOfAChainOfThousandLagsIsTheClosedForm) {
  // |H(jw)| = (1 + (w tau)^2)^(-n/2), phase -n atan(w tau): -3010 dB at the corner and
  // -20043 dB a decade above, far beyond what any polynomial evaluation can represent.
  // Tolerance 1e-12 relative: a sum of 1000 logarithms, each to rounding.
  const int n = 1000;
  const double tau = 0.01;
  const Zpk g = lag_chain(n, tau);
  for (double w : {0.1, 10.0, 100.0, 1000.0, 1e5}) {
    const Bode b = bode(g, {w});
    const double mag = -10.0 * n * std::log10(1.0 + w * w * tau * tau), ph = -n * std::atan(w * tau) * kDeg;
    EXPECT_NEAR(b.mag_db[0], mag, 1e-12 * std::abs(mag) + 1e-12) << w;
    EXPECT_NEAR(b.phase_deg[0], ph, 1e-12 * std::abs(ph) + 1e-12) << w;
  }
}

// Loops over the features of frequency.cpp's tests: lags, leads, resonances, right
// half-plane zeros, integrators, delays, negative gain, discrete with a pole at z = 1.
const std::vector<TransferFunction>& loops() {
  static const std::vector<TransferFunction> all = {
      tf("10/(s*(s+1)*(s/5+1))"),
      tf("20*(s+1)/(s^2*(s/20+1))"),
      tf("(40 + 2*s)/(s*(s/30 + 1)*(s/300 + 1))"),
      tf("4*(1 - s/2)/((s+1)*(s/5+1))"),
      tf("3*2500/(s^2 + 2*0.05*50*s + 2500)"),
      tf("-2/(s+1)"),
      tf("5*(1 - s*0.1 + (s*0.2)^2/12)/((1 + s*0.1 + (s*0.2)^2/12)*(s+1))"),
      tf("0.1*(z-0.9)/((z-1)*(z-0.6))", 0.001),
      tf("0.05*(z+1)/((z-1)*(z-0.6))", 0.01),
      tf("2*(z + 0.5)/((z - 0.9)*(z - 0.5))", 0.001),
  };
  return all;
}

TEST(Zpk, ResponseEqualsThePolynomialEvaluation) {
  // bode(Zpk) sums factor logarithms; bode(TF) evaluates num/den and unwraps with its
  // phase model. 1e-9 relative in magnitude and 1e-9 deg: roots from a balanced
  // companion matrix (backward stable) at orders <= 5, evaluated away from them.
  for (const TransferFunction& g : loops()) {
    const std::vector<double> w = default_frequency_grid(g, 60);
    const Bode a = bode(Zpk::from_tf(g), w), b = bode(g, w);
    for (size_t k = 0; k < w.size(); ++k) {
      EXPECT_NEAR(a.mag_db[k], b.mag_db[k], 1e-9 * std::max(1.0, std::abs(b.mag_db[k]))) << w[k];
      EXPECT_NEAR(a.phase_deg[k], b.phase_deg[k], 1e-9 * std::max(1.0, std::abs(b.phase_deg[k]))) << w[k];
    }
  }
}

TEST(ZpkMargins, AgreeWithThePolynomialRootMethod) {
  // Two formulations: certified isolation on the factors against the real roots of
  // |N|^2 - |D|^2 and Im N D* (frequency.cpp). Every crossing, 1e-8 relative in
  // frequency and 1e-8 dB / deg (both refined to rounding on the response).
  for (const TransferFunction& g : loops()) {
    const Margins a = margins(Zpk::from_tf(g)), b = margins(g);
    ASSERT_EQ(a.gain_crossovers.size(), b.gain_crossovers.size()) << g.num().descending().size();
    ASSERT_EQ(a.phase_crossovers.size(), b.phase_crossovers.size()) << g.num().descending().size();
    for (size_t k = 0; k < a.gain_crossovers.size(); ++k) {
      EXPECT_NEAR(a.gain_crossovers[k].w_rad_s, b.gain_crossovers[k].w_rad_s, 1e-8 * b.gain_crossovers[k].w_rad_s);
      EXPECT_NEAR(a.gain_crossovers[k].margin, b.gain_crossovers[k].margin, 1e-8);
    }
    for (size_t k = 0; k < a.phase_crossovers.size(); ++k) {
      EXPECT_NEAR(a.phase_crossovers[k].w_rad_s, b.phase_crossovers[k].w_rad_s, 1e-8 * b.phase_crossovers[k].w_rad_s);
      EXPECT_NEAR(a.phase_crossovers[k].margin, b.phase_crossovers[k].margin, 1e-8);
    }
  }
}

TEST(ZpkMargins, TypeOneLoopClosedForm) {
  // L = K/(s (s + 1)): |L| = 1 at w^2 = (sqrt(1 + 4 K^2) - 1)/2, PM = 90 - atan(w) deg;
  // the phase tends to -180 deg without reaching it: no phase crossover, and none at
  // DC, where L is infinite. 1e-12 relative.
  const double k = 4.0;
  const Margins m = margins(Zpk(k, -1, {}, {Complex(-1.0, 0.0)}));
  const double w = std::sqrt((std::sqrt(1.0 + 4.0 * k * k) - 1.0) / 2.0);
  ASSERT_TRUE(m.gain_crossover_rad_s && m.phase_margin_deg);
  EXPECT_NEAR(*m.gain_crossover_rad_s, w, 1e-12 * w);
  EXPECT_NEAR(*m.phase_margin_deg, 90.0 - std::atan(w) * kDeg, 1e-10);
  EXPECT_TRUE(m.phase_crossovers.empty());
  EXPECT_FALSE(m.gain_margin_db.has_value());
}

TEST(ZpkMargins, DiscreteIntegratorHasNoCrossoverAtDc) {
  // Issue 13: 0.1 (z - 0.9)/((z - 1)(z - 0.6)) at 1 ms reported a 0 Hz phase crossover
  // with -279 dB. L is infinite there. The only phase crossover is Nyquist, where
  // L(-1) = 0.1 (-1.9)/((-2)(-1.6)) = -0.059375: GM = -20 log10 0.059375. 1e-10 dB.
  const Zpk l = Zpk::from_tf(tf("0.1*(z-0.9)/((z-1)*(z-0.6))", 0.001));
  for (const Margins& m : {margins(l), margins(tf("0.1*(z-0.9)/((z-1)*(z-0.6))", 0.001))}) {
    ASSERT_EQ(m.phase_crossovers.size(), 1u);
    EXPECT_NEAR(m.phase_crossovers[0].w_rad_s, M_PI / 0.001, 1e-9 * M_PI / 0.001);
    EXPECT_NEAR(*m.gain_margin_db, -20.0 * std::log10(0.059375), 1e-10);
    ASSERT_EQ(m.gain_crossovers.size(), 1u);
  }
  EXPECT_EQ(stability(l), Stability::Marginal);
  EXPECT_FALSE(l.dc_gain().has_value());
}

TEST(ZpkMargins, ChainOfThousandLagsHasTheClosedFormCrossovers) {
  // -n atan(w tau) = -(2k + 1) pi at w_k tau = tan((2k + 1) pi / n), k = 0 .. n/4 - 1,
  // where GM = -20 log10 |L| = -20 n log10 cos((2k + 1) pi / n). |L| < 1 at every
  // w > 0: no gain crossover. 1e-10 relative in frequency, 1e-9 dB.
  const int n = 1000;
  const double tau = 0.01;
  const Margins m = margins(lag_chain(n, tau));
  ASSERT_EQ(m.phase_crossovers.size(), static_cast<size_t>(n / 4));
  for (int k = 0; k < n / 4; ++k) {
    const double th = (2.0 * k + 1.0) * M_PI / n;
    const Crossing& c = m.phase_crossovers[static_cast<size_t>(k)];
    EXPECT_NEAR(c.w_rad_s, std::tan(th) / tau, 1e-10 * std::tan(th) / tau) << k;
    EXPECT_NEAR(c.margin, -20.0 * n * std::log10(std::cos(th)), 1e-9 * std::max(1.0, c.margin)) << k;
  }
  EXPECT_TRUE(m.gain_crossovers.empty());
}

TEST(ZpkBandwidth, ClosedForms) {
  // n lags: (1 + (w tau)^2)^(-n/2) = 10^(-3/20) at w tau = sqrt(10^(0.3/n) - 1).
  // 1e-12 relative.
  for (int n : {1, 7, 1000}) {
    const double want = std::sqrt(std::pow(10.0, 0.3 / n) - 1.0) / 0.01;
    EXPECT_NEAR(*bandwidth(lag_chain(n, 0.01)), want, 1e-12 * want) << n;
  }
  // An integrator (infinite DC gain) and a zero at DC have none.
  EXPECT_FALSE(bandwidth(Zpk(1.0, -1, {}, {})).has_value());
  EXPECT_FALSE(bandwidth(Zpk(1.0, 1, {}, {Complex(-1.0, 0.0)})).has_value());
  // Against the polynomial method on the loops with a finite non-zero DC gain: 1e-9.
  for (const TransferFunction& g : loops()) {
    const auto a = bandwidth(Zpk::from_tf(g)), b = bandwidth(g);
    ASSERT_EQ(a.has_value(), b.has_value());
    if (a) {
      EXPECT_NEAR(*a, *b, 1e-9 * *b);
    }
  }
}

TEST(ZpkStability, Verdicts) {
  const auto c = [](std::vector<Complex> p) { return stability(p, false); };
  EXPECT_EQ(c({{-1, 0}, {-2, 3}, {-2, -3}}), Stability::Stable);
  EXPECT_EQ(c({{0, 0}, {-1, 0}}), Stability::Marginal);            // type 1
  EXPECT_EQ(c({{0, 0}, {0, 0}}), Stability::Unstable);             // double integrator
  EXPECT_EQ(c({{0, 2}, {0, -2}, {-1, 0}}), Stability::Marginal);    // undamped pair
  EXPECT_EQ(c({{0, 2}, {0, -2}, {0, 2}, {0, -2}}), Stability::Unstable);
  EXPECT_EQ(c({{1e-3, 0}}), Stability::Unstable);
  // Within 1e-9 of the axis relative to |s|: on it (damping below 1e-9).
  EXPECT_EQ(c({{-1e-10, 5}, {-1e-10, -5}}), Stability::Marginal);
  const auto d = [](std::vector<Complex> p) { return stability(p, true); };
  EXPECT_EQ(d({{0.5, 0}, {1, 0}}), Stability::Marginal);
  EXPECT_EQ(d({{-1, 0}}), Stability::Marginal);
  EXPECT_EQ(d({{1, 0}, {1, 0}}), Stability::Unstable);
  EXPECT_EQ(d({{0.999, 0}}), Stability::Stable);
  EXPECT_EQ(d({{1.001, 0}}), Stability::Unstable);
}

TEST(Zpk, ToTfRoundTripAndOverflow) {
  // Back to coefficients: 1e-12 relative to the largest coefficient.
  for (const TransferFunction& g : loops()) EXPECT_TRUE(test::tf_near(*Zpk::from_tf(g).to_tf(), g, 1e-12));
  // (s + 100)^1000 has coefficients beyond 1e308: no TF.
  EXPECT_FALSE(lag_chain(1000, 0.01).to_tf().has_value());
}

}  // namespace
}  // namespace dmbd::blocks
