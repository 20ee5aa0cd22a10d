// dmbd::blocks elements: gain, PD (with and without filter), PID, Butterworth
// low-pass (including the paper's Q filter of eq. frc_ctrl), integrator.
#include <gtest/gtest.h>

#include <cmath>

#include "dmbd/blocks/elements.hpp"
#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/frequency.hpp"
#include "test_support.hpp"

namespace dmbd::blocks {
namespace {

using test::coeffs_near;
using test::complex_near;
using test::tf_near;

const std::vector<Complex> kPoints{{0.0, 0.1}, {0.0, 2.0}, {0.7, -3.0}, {-0.2, 40.0}};

TEST(Elements, GainBlock) {
  const TransferFunction g = gain_block(-2.5);
  EXPECT_EQ(g.order(), 0);
  EXPECT_EQ(*g.dc_gain(), -2.5);                              // exact
  EXPECT_EQ(g.evaluate(Complex(3.0, 4.0)), Complex(-2.5));    // exact
}

TEST(Elements, PdWithoutFilter) {
  // P + D s (the paper's C = P + D s, eq. frc_ctrl): numerator D s + P, denominator 1.
  const TransferFunction c = pd(3.0, 0.5);
  EXPECT_EQ(c.num().coeffs(), (std::vector<double>{3.0, 0.5}));  // exact
  EXPECT_EQ(c.den().coeffs(), (std::vector<double>{1.0}));
  EXPECT_FALSE(c.is_proper());
  // Same as parsing the paper's expression (exact: small binary fractions).
  const TransferFunction parsed = TransferFunction::parse("P + D*s", {{"P", 3.0}, {"D", 0.5}});
  EXPECT_EQ(parsed.num(), c.num());
  EXPECT_EQ(parsed.den(), c.den());
}

TEST(Elements, PdWithFilter) {
  // P + D s/(tau s + 1) = (P + (P tau + D) s)/(tau s + 1)
  //                     = ((P + D/tau) s + P/tau) / (s + 1/tau) after normalisation.
  const double p = 3.0, d = 0.5, tau = 0.01;
  const TransferFunction c = pd(p, d, tau);
  EXPECT_TRUE(c.is_proper());
  // A couple of roundings: 1e-14 relative.
  EXPECT_TRUE(coeffs_near(c.num(), {p / tau, p + d / tau}, 1e-14));
  EXPECT_TRUE(coeffs_near(c.den(), {1.0 / tau, 1.0}, 1e-14));
  for (const Complex s : kPoints)
    // Against the defining formula (1e-14 relative: a few operations).
    EXPECT_TRUE(complex_near(c.evaluate(s), p + d * s / (tau * s + 1.0), 1e-14)) << "s = " << s;
  // High-frequency gain P + D/tau, DC gain P (1e-12 relative).
  EXPECT_NEAR(*c.dc_gain(), p, 1e-12 * p);
  EXPECT_THROW(pd(1.0, 1.0, -0.1), InputError);
}

TEST(Elements, PidCoefficients) {
  // P + I/s + D s/(tau s + 1) = (I + (P + I tau) s + (P tau + D) s^2) / (s (tau s + 1)).
  const double p = 2.0, i = 5.0, d = 0.25, tau = 0.02;
  const TransferFunction c = pid(p, i, d, tau);
  const TransferFunction want(Polynomial({i, p + i * tau, p * tau + d}), Polynomial({0.0, 1.0, tau}));
  // Same construction formula: 1e-15 relative.
  EXPECT_TRUE(tf_near(c, want, 1e-15));
  // Normalised: denominator s^2 + s/tau exactly (1/tau rounding: 1e-15 relative).
  EXPECT_TRUE(coeffs_near(c.den(), {0.0, 1.0 / tau, 1.0}, 1e-15));
  for (const Complex s : kPoints)
    // Against the sum of the three terms (1e-13 relative: cancellation-free terms).
    EXPECT_TRUE(complex_near(c.evaluate(s), p + i / s + d * s / (tau * s + 1.0), 1e-13)) << "s = " << s;
  EXPECT_FALSE(c.dc_gain().has_value());  // integral action: infinite DC gain
  EXPECT_TRUE(c.is_proper());
  // Cross-check with the TF algebra: gain + integrator + filtered derivative.
  const TransferFunction sum = TransferFunction(p) + integrator(i) + pd(0.0, d, tau);
  for (const Complex s : kPoints) EXPECT_TRUE(complex_near(sum.evaluate(s), c.evaluate(s), 1e-13)) << "s = " << s;
  // A PI (d = 0) needs no filter.
  EXPECT_NO_THROW(pid(1.0, 1.0, 0.0, 0.0));
  EXPECT_THROW(pid(1.0, 1.0, 0.1, 0.0), InputError);  // improper without a filter
  EXPECT_THROW(pid(1.0, 1.0, 0.1, -1.0), InputError);
}

TEST(Elements, ButterworthUnitCircleProperties) {
  const double wc = 50.0;
  for (int n = 1; n <= 8; ++n) {
    SCOPED_TRACE("order " + std::to_string(n));
    const TransferFunction b = butterworth_lowpass(n, wc);
    EXPECT_EQ(b.order(), n);
    EXPECT_EQ(b.num().degree(), 0);
    // |H(j wc)| = 1/sqrt(2) for every order (|H|^2 = 1/(1 + (w/wc)^{2n})): 1e-12
    // relative (expanded polynomial of degree 8 with coefficients up to ~1e13).
    EXPECT_NEAR(std::abs(b.evaluate(Complex(0.0, wc))), 1.0 / std::sqrt(2.0), 1e-12);
    // Unit DC gain (1e-12 relative).
    EXPECT_NEAR(*b.dc_gain(), 1.0, 1e-12);
    // Maximally flat: |H(jw)|^2 = 1/(1 + (w/wc)^{2n}) at other frequencies (1e-11).
    for (const double r : {0.3, 0.9, 2.0, 5.0}) {
      const double want = 1.0 / std::sqrt(1.0 + std::pow(r, 2 * n));
      EXPECT_NEAR(std::abs(b.evaluate(Complex(0.0, r * wc))), want, 1e-11 * std::max(want, 1e-3)) << "w/wc = " << r;
    }
    // Poles on the circle |s| = wc, in the open left half-plane, at the angles
    // pi/2 + (2k+1) pi/(2n) (root finding of the expanded polynomial: 1e-9 relative).
    std::vector<Complex> want;
    for (int k = 0; k < n; ++k) want.push_back(std::polar(wc, M_PI / 2.0 + (2.0 * k + 1.0) * M_PI / (2.0 * n)));
    const std::vector<Complex> poles = b.poles();
    EXPECT_TRUE(test::roots_near(poles, want, 1e-9));
    for (const Complex& p : poles) {
      EXPECT_NEAR(std::abs(p), wc, 1e-9 * wc) << p;
      EXPECT_LT(p.real(), 0.0) << p;
    }
    EXPECT_TRUE(b.is_stable());
  }
  EXPECT_THROW(butterworth_lowpass(0, wc), InputError);
  EXPECT_THROW(butterworth_lowpass(2, 0.0), InputError);
  EXPECT_THROW(butterworth_lowpass(2, -1.0), InputError);
}

TEST(Elements, ButterworthOrderTwoIsThePaperQ) {
  // Eq. frc_ctrl: Q = 1/((s/wc)^2 + sqrt(2) s/wc + 1), wc = 2 pi 60 rad/s.
  const double wc = 2.0 * M_PI * 60.0;
  const TransferFunction q = TransferFunction::parse("1/((s/wc)^2 + sqrt(2)*s/wc + 1)", {{"wc", wc}});
  const TransferFunction b = butterworth_lowpass(2, wc);
  // Product of the conjugate pole pair vs parsed coefficients: 1e-14 relative.
  EXPECT_TRUE(tf_near(b, q, 1e-14));
  for (const Complex s : kPoints) EXPECT_TRUE(complex_near(b.evaluate(s * 100.0), q.evaluate(s * 100.0), 1e-13));
  // And order 1 is wc/(s + wc) exactly in form (1e-15 relative).
  EXPECT_TRUE(tf_near(butterworth_lowpass(1, wc), TransferFunction(Polynomial({wc}), Polynomial({wc, 1.0})), 1e-15));
  // Order 3: (s + wc)(s^2 + wc s + wc^2) (1e-14 relative).
  const TransferFunction b3 = butterworth_lowpass(3, 2.0);
  EXPECT_TRUE(tf_near(b3, TransferFunction::parse("8/((s+2)*(s^2+2*s+4))"), 1e-14));
}

TEST(Elements, Integrator) {
  const TransferFunction i = integrator(4.0);
  EXPECT_EQ(i.num().coeffs(), (std::vector<double>{4.0}));  // exact
  EXPECT_EQ(i.den().coeffs(), (std::vector<double>{0.0, 1.0}));
  EXPECT_FALSE(i.dc_gain().has_value());
  // -90 deg everywhere, 20 log10(4/w) dB (1e-12 absolute).
  const Bode b = bode(i, {0.1, 4.0, 100.0});
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_NEAR(b.phase_deg[k], -90.0, 1e-12);
    EXPECT_NEAR(b.mag_db[k], 20.0 * std::log10(4.0 / b.w_rad_s[k]), 1e-12);
  }
  EXPECT_EQ(integrator().num().coeffs(), (std::vector<double>{1.0}));  // default k = 1
}

}  // namespace
}  // namespace dmbd::blocks
