// dmbd::blocks c2d / d2c: closed forms for first-order systems, TF vs state-space
// formulations, pre-warping, ZOH step invariance, round trips and bad inputs.
#include <gtest/gtest.h>

#include <cmath>

#include "dmbd/blocks/discretize.hpp"
#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/time_response.hpp"
#include "test_support.hpp"

namespace dmbd::blocks {
namespace {

using test::coeffs_near;
using test::complex_near;
using test::roots_near;
using test::tf_near;

TransferFunction lag(double a) { return TransferFunction(Polynomial({a}), Polynomial({a, 1.0})); }

// Points e^{j theta} on the unit circle, theta from 1 % to 99 % of Nyquist.
std::vector<Complex> circle_points() {
  std::vector<Complex> z;
  for (double f : {0.01, 0.1, 0.37, 0.8, 0.99}) z.push_back(std::polar(1.0, f * M_PI));
  return z;
}

TEST(Discretize, MethodNames) {
  EXPECT_EQ(parse_c2d_method("zoh"), C2dMethod::Zoh);
  EXPECT_EQ(parse_c2d_method("tustin"), C2dMethod::Tustin);
  EXPECT_EQ(parse_c2d_method("bilinear"), C2dMethod::Tustin);
  EXPECT_EQ(parse_c2d_method("backward-euler"), C2dMethod::BackwardEuler);
  EXPECT_EQ(parse_c2d_method("euler"), C2dMethod::BackwardEuler);
  EXPECT_THROW(parse_c2d_method("foh"), InputError);
  EXPECT_STREQ(to_string(C2dMethod::Zoh), "zoh");
  EXPECT_STREQ(to_string(C2dMethod::Tustin), "tustin");
  EXPECT_EQ(parse_c2d_method(to_string(C2dMethod::BackwardEuler)), C2dMethod::BackwardEuler);
}

TEST(Discretize, TustinFirstOrderLagClosedForm) {
  // a/(s+a) with s = (2/T)(z-1)/(z+1):  H(z) = b0 (z + 1) / (z + a1),
  // b0 = aT/(2+aT), a1 = (aT-2)/(2+aT).
  for (const double a : {0.5, 3.0, 200.0}) {
    for (const double ts : {1e-3, 0.05}) {
      const double at = a * ts;
      const double b0 = at / (2.0 + at), a1 = (at - 2.0) / (2.0 + at);
      const TransferFunction hd = c2d(lag(a), ts, C2dMethod::Tustin);
      EXPECT_EQ(hd.ts(), ts);
      // A handful of roundings in the substitution and normalisation: 1e-14 relative.
      EXPECT_TRUE(coeffs_near(hd.num(), {b0, b0}, 1e-14)) << "a = " << a << ", ts = " << ts;
      EXPECT_TRUE(coeffs_near(hd.den(), {a1, 1.0}, 1e-14)) << "a = " << a << ", ts = " << ts;
    }
  }
}

TEST(Discretize, TustinTfSubstitutionEqualsStateSpace) {
  const double ts = 0.01;
  for (const char* text : {"(s+3)/(s^2+2*s+5)", "(2*s^2 - s + 4)/((s+1)*(s^2+0.3*s+9))", "100/(s^2+14*s+100)",
                           "(s-1)*(s+20)/((s+2)*(s+5)*(s+50))", "(2*s^2+s+1)/(s^2+3*s+2)"}) {
    SCOPED_TRACE(text);
    const TransferFunction g = TransferFunction::parse(text);
    for (const double w0 : {0.0, 40.0}) {
      const TransferFunction via_tf = c2d(g, ts, C2dMethod::Tustin, w0);
      const StateSpace via_ss = c2d(StateSpace::from_tf(g), ts, C2dMethod::Tustin, w0);
      EXPECT_EQ(via_ss.ts(), ts);
      // Two independent formulations: coefficients to 1e-12 of the largest (the
      // discrete denominators are O(1) with roots near z = 1).
      EXPECT_TRUE(tf_near(via_ss.to_tf(), via_tf, 1e-10));
      for (const Complex z : circle_points())
        // Values on the unit circle: 1e-10 relative (conditioning of roots near 1).
        EXPECT_TRUE(complex_near(via_ss.evaluate(z)(0, 0), via_tf.evaluate(z), 1e-10)) << "z = " << z;
      // Poles: c2d_pole maps each continuous pole exactly (1e-10 relative).
      std::vector<Complex> mapped;
      for (const Complex p : g.poles()) mapped.push_back(c2d_pole(p, ts, C2dMethod::Tustin, w0));
      EXPECT_TRUE(roots_near(via_tf.poles(), mapped, 1e-10));
    }
  }
}

TEST(Discretize, TustinIsTheBilinearMapOfTheResponse) {
  // H(e^{jwT}) = G(j (2/T) tan(wT/2)) for every w: the frequency warping of Tustin.
  const double ts = 0.02;
  const TransferFunction g = TransferFunction::parse("(s+3)/(s^2+2*s+5)");
  const TransferFunction hd = c2d(g, ts, C2dMethod::Tustin);
  for (const double w : {0.1, 1.0, 10.0, 100.0, 150.0}) {
    const Complex z = std::polar(1.0, w * ts);
    const Complex s(0.0, 2.0 / ts * std::tan(w * ts / 2.0));
    // A few roundings in each: 1e-12 relative.
    EXPECT_TRUE(complex_near(hd.evaluate(z), g.evaluate(s), 1e-12)) << "w = " << w;
  }
}

TEST(Discretize, PrewarpedTustinIsExactAtThePrewarpFrequency) {
  // The paper's 60 Hz Butterworth Q (eq. frc_ctrl) at 1 kHz: pre-warped at wc, the
  // discrete filter has exactly the continuous response there (-3.01 dB, -90 deg).
  const double wc = 2.0 * M_PI * 60.0, ts = 1e-3;
  const TransferFunction q = TransferFunction::parse("1/((s/wc)^2 + sqrt(2)*s/wc + 1)", {{"wc", wc}});
  for (const double w0 : {wc, 0.5 * wc, 2500.0}) {
    const TransferFunction qd = c2d(q, ts, C2dMethod::Tustin, w0);
    const Complex zd = std::polar(1.0, w0 * ts);
    // Exact by construction; rounding in tan and the substitution: 1e-12 relative.
    EXPECT_TRUE(complex_near(qd.evaluate(zd), q.evaluate(Complex(0.0, w0)), 1e-12)) << "w0 = " << w0;
    // State-space path, same property.
    const StateSpace qs = c2d(StateSpace::from_tf(q), ts, C2dMethod::Tustin, w0);
    EXPECT_TRUE(complex_near(qs.evaluate(zd)(0, 0), q.evaluate(Complex(0.0, w0)), 1e-12)) << "w0 = " << w0;
  }
  // Without pre-warping it is not exact at wc (warping error ~ (wc T)^2/12 ~ 1%):
  // the check above could fail.
  const TransferFunction plain = c2d(q, ts, C2dMethod::Tustin);
  EXPECT_GT(test::rel_diff(plain.evaluate(std::polar(1.0, wc * ts)), q.evaluate(Complex(0.0, wc))), 1e-3);
}

TEST(Discretize, ZohFirstOrderClosedForm) {
  for (const double a : {0.5, 3.0, 200.0}) {
    const double ts = 0.01;
    const double p = std::exp(-a * ts);
    // 1/(s+a) -> ((1 - e^{-aT})/a) / (z - e^{-aT}); expm accuracy ~1e-15, 1e-13 relative.
    const TransferFunction h1 = c2d(TransferFunction(Polynomial({1.0}), Polynomial({a, 1.0})), ts, C2dMethod::Zoh);
    EXPECT_TRUE(coeffs_near(h1.den(), {-p, 1.0}, 1e-13)) << "a = " << a;
    EXPECT_EQ(h1.num().degree(), 0);
    EXPECT_NEAR(h1.num()[0], (1.0 - p) / a, 1e-13 * (1.0 - p) / a) << "a = " << a;  // 1e-13 relative
    // a/(s+a) -> (1 - e^{-aT}) / (z - e^{-aT}).
    const TransferFunction h2 = c2d(lag(a), ts, C2dMethod::Zoh);
    EXPECT_NEAR(h2.num()[0], 1.0 - p, 1e-13 * (1.0 - p)) << "a = " << a;  // 1e-13 relative
    // State-space path directly: A_d = e^{-aT} (1e-14 relative).
    const StateSpace s = c2d(StateSpace::from_tf(lag(a)), ts, C2dMethod::Zoh);
    EXPECT_NEAR(s.a()(0, 0), p, 1e-14 * p);
  }
}

TEST(Discretize, ZohPolesAreMappedExactly) {
  const double ts = 0.05;
  const TransferFunction g = TransferFunction::parse("(s+3)/((s+1)*(s^2+2*s+26))");
  const TransferFunction hd = c2d(g, ts, C2dMethod::Zoh);
  std::vector<Complex> mapped;
  for (const Complex p : g.poles()) mapped.push_back(c2d_pole(p, ts, C2dMethod::Zoh));
  // e^{p T}: 1e-12 relative (eigenvalues of expm, roots near z = 1).
  EXPECT_TRUE(roots_near(hd.poles(), mapped, 1e-12));
  // c2d_pole closed forms (1e-15: one libm call).
  EXPECT_TRUE(complex_near(c2d_pole({-1.0, 5.0}, ts, C2dMethod::Zoh), std::exp(Complex(-ts, 5.0 * ts)), 1e-15));
  EXPECT_TRUE(complex_near(c2d_pole(-2.0, ts, C2dMethod::Tustin), (1.0 - ts) / (1.0 + ts), 1e-15));
  EXPECT_TRUE(complex_near(c2d_pole(-2.0, ts, C2dMethod::BackwardEuler), 1.0 / (1.0 + 2.0 * ts), 1e-15));
  // DC gain is preserved by ZOH (1e-12 relative).
  EXPECT_NEAR(*hd.dc_gain(), *g.dc_gain(), 1e-12 * std::abs(*g.dc_gain()));
}

TEST(Discretize, ZohStepEqualsContinuousStepAtSamples) {
  // Step invariance: the ZOH equivalent's step response equals the continuous step
  // response at t = k T (the input is constant between samples).
  const double ts = 0.1, t_end = 5.0;
  const int n = static_cast<int>(std::lround(t_end / ts)) + 1;
  const StateSpace g = StateSpace::from_tf(TransferFunction::parse("(s+3)/((s+1)*(s^2+0.8*s+16))"));
  const StateSpace gd = c2d(g, ts, C2dMethod::Zoh);
  const TimeResponse yc = step(g, t_end, n);
  const TimeResponse yd = step(gd, t_end, n);
  ASSERT_EQ(yc.t.size(), yd.t.size());
  ASSERT_EQ(yd.t.size(), static_cast<size_t>(n));
  double peak = 0.0;
  for (int k = 0; k < n; ++k) peak = std::max(peak, std::abs(yc.y(k, 0)));
  for (int k = 0; k < n; ++k) {
    EXPECT_NEAR(yd.t[static_cast<size_t>(k)], yc.t[static_cast<size_t>(k)], 1e-12);  // same instants
    // Same recurrence from two expm calls: ~1e-14 of the peak; 1e-12 relative to the peak.
    EXPECT_NEAR(yd.y(k, 0), yc.y(k, 0), 1e-12 * peak) << "k = " << k;
  }
  // And a TF-path ZOH gives the same discrete system (coefficients 1e-10 relative).
  EXPECT_TRUE(tf_near(c2d(TransferFunction::parse("(s+3)/((s+1)*(s^2+0.8*s+16))"), ts, C2dMethod::Zoh),
                      gd.to_tf(), 1e-10));
}

TEST(Discretize, BackwardEulerFirstOrderClosedForm) {
  // 1/(s+a) with s = (z-1)/(T z): T z / ((1 + aT) z - 1) = (T/(1+aT)) z / (z - 1/(1+aT)).
  for (const double a : {0.5, 3.0, 200.0}) {
    const double ts = 0.01;
    const TransferFunction h = c2d(TransferFunction(Polynomial({1.0}), Polynomial({a, 1.0})), ts,
                                   C2dMethod::BackwardEuler);
    // Substitution and one normalisation: 1e-14 relative.
    EXPECT_TRUE(coeffs_near(h.num(), {0.0, ts / (1.0 + a * ts)}, 1e-14)) << "a = " << a;
    EXPECT_TRUE(coeffs_near(h.den(), {-1.0 / (1.0 + a * ts), 1.0}, 1e-14)) << "a = " << a;
    // The state-space formulation agrees (1e-12 relative on the unit circle).
    const StateSpace s = c2d(StateSpace::from_tf(TransferFunction(Polynomial({1.0}), Polynomial({a, 1.0}))), ts,
                             C2dMethod::BackwardEuler);
    for (const Complex z : circle_points())
      EXPECT_TRUE(complex_near(s.evaluate(z)(0, 0), h.evaluate(z), 1e-12)) << "z = " << z;
  }
}

TEST(Discretize, BackwardEulerTfEqualsStateSpaceHigherOrder) {
  const double ts = 0.005;
  const TransferFunction g = TransferFunction::parse("(2*s^2 - s + 4)/((s+1)*(s^2+0.3*s+9))");
  const TransferFunction via_tf = c2d(g, ts, C2dMethod::BackwardEuler);
  const StateSpace via_ss = c2d(StateSpace::from_tf(g), ts, C2dMethod::BackwardEuler);
  for (const Complex z : circle_points())
    // Poles cluster near z = 1 at this ts; 1e-9 relative.
    EXPECT_TRUE(complex_near(via_ss.evaluate(z)(0, 0), via_tf.evaluate(z), 1e-9)) << "z = " << z;
}

TEST(Discretize, D2cInvertsC2d) {
  const double ts = 0.05;
  for (const char* text : {"1/(s+1)", "(s+3)/(s^2+2*s+5)", "(2*s^2 - s + 4)/((s+1)*(s^2+0.3*s+9))", "3 + 1/(s+2)"}) {
    SCOPED_TRACE(text);
    const TransferFunction g = TransferFunction::parse(text);
    const StateSpace gs = StateSpace::from_tf(g);
    for (const C2dMethod m : {C2dMethod::Tustin, C2dMethod::Zoh, C2dMethod::BackwardEuler}) {
      SCOPED_TRACE(to_string(m));
      // TF path round trip: coefficients relative to the largest, 1e-9 (brief).
      const TransferFunction back = d2c(c2d(g, ts, m), m);
      EXPECT_EQ(back.ts(), 0.0);
      EXPECT_TRUE(tf_near(back, g, 1e-9));
      // State-space path round trip: same response at test points (1e-9 relative).
      const StateSpace back_ss = d2c(c2d(gs, ts, m), m);
      EXPECT_FALSE(back_ss.is_discrete());
      for (const Complex s : {Complex(0.0, 0.5), Complex(0.0, 3.0), Complex(1.0, 10.0)})
        EXPECT_TRUE(complex_near(back_ss.evaluate(s)(0, 0), g.evaluate(s), 1e-9)) << "s = " << s;
    }
    // Pre-warped Tustin round trip (same pre-warp both ways): 1e-9.
    EXPECT_TRUE(tf_near(d2c(c2d(g, ts, C2dMethod::Tustin, 20.0), C2dMethod::Tustin, 20.0), g, 1e-9));
  }
}

TEST(Discretize, D2cZohOfIntegratingSystemsStateSpacePath) {
  // The ZOH equivalent of a plant with integrators (poles at z = 1): the state-space
  // d2c (matrix logarithm) recovers the continuous response (1e-9 relative).
  const double ts = 0.1;
  for (const char* text : {"1/s", "1/(s*(s+1))", "1/s^2", "(s+1)/s^2"}) {
    SCOPED_TRACE(text);
    const TransferFunction g = TransferFunction::parse(text);
    const StateSpace back = d2c(c2d(StateSpace::from_tf(g), ts, C2dMethod::Zoh), C2dMethod::Zoh);
    for (const Complex s : {Complex(0.0, 0.5), Complex(0.0, 3.0), Complex(1.0, 10.0)})
      EXPECT_TRUE(complex_near(back.evaluate(s)(0, 0), g.evaluate(s), 1e-9)) << "s = " << s;
  }
}

// Regression (fixed): the TF path d2c(TF, Zoh) = d2c(from_tf(.)).to_tf()
// goes through StateSpace::to_tf, which returns a garbage numerator when the
// recovered poles at s = 0 come out as ~1e-14 instead of exactly 0 (see
// StateSpace.ToTfOfIntegratingSystemsInGeneralCoordinates). E.g.
// d2c(c2d(1/s^2, 0.1, zoh), zoh) gives numerator {0.59, 0, -8.8e27}. Guards the fix.
TEST(Discretize, D2cZohOfIntegratingSystemsTfPath) {
  const double ts = 0.1;
  for (const char* text : {"1/s", "1/(s*(s+1))", "1/s^2", "(s+1)/s^2"}) {
    SCOPED_TRACE(text);
    const TransferFunction g = TransferFunction::parse(text);
    // Round trip to 1e-9 of the largest coefficient (as D2cInvertsC2d).
    EXPECT_TRUE(tf_near(d2c(c2d(g, ts, C2dMethod::Zoh), C2dMethod::Zoh), g, 1e-9));
  }
}

TEST(Discretize, BadInputsThrow) {
  const TransferFunction g = TransferFunction::parse("1/(s+1)");
  const StateSpace gs = StateSpace::from_tf(g);
  // ts <= 0 (and non-finite).
  for (const double ts : {0.0, -0.1, std::nan(""), HUGE_VAL}) {
    EXPECT_THROW(c2d(g, ts, C2dMethod::Zoh), InputError) << ts;
    EXPECT_THROW(c2d(gs, ts, C2dMethod::Tustin), InputError) << ts;
    EXPECT_THROW(c2d_pole(-1.0, ts, C2dMethod::Zoh), InputError) << ts;
  }
  // Pre-warp at or above Nyquist (pi/ts = 314.16 rad/s at ts = 0.01).
  EXPECT_THROW(c2d(g, 0.01, C2dMethod::Tustin, M_PI / 0.01), InputError);
  EXPECT_THROW(c2d(g, 0.01, C2dMethod::Tustin, 400.0), InputError);
  EXPECT_THROW(c2d(gs, 0.01, C2dMethod::Tustin, 400.0), InputError);
  EXPECT_NO_THROW(c2d(g, 0.01, C2dMethod::Tustin, 300.0));
  // Negative pre-warp, and pre-warp with another method.
  EXPECT_THROW(c2d(g, 0.01, C2dMethod::Tustin, -1.0), InputError);
  EXPECT_THROW(c2d(g, 0.01, C2dMethod::Zoh, 10.0), InputError);
  // Already discrete.
  const TransferFunction gd = c2d(g, 0.01, C2dMethod::Zoh);
  EXPECT_THROW(c2d(gd, 0.01, C2dMethod::Zoh), InputError);
  EXPECT_THROW(c2d(StateSpace::from_tf(gd), 0.01, C2dMethod::Tustin), InputError);
  // Improper.
  EXPECT_THROW(c2d(TransferFunction::parse("s^2/(s+1)"), 0.01, C2dMethod::Tustin), InputError);
  // d2c of a continuous system.
  EXPECT_THROW(d2c(g, C2dMethod::Tustin), InputError);
  EXPECT_THROW(d2c(gs, C2dMethod::Zoh), InputError);
  // d2c ZOH with a pole on the negative real axis or at z = 0.
  const TransferFunction neg = TransferFunction::parse("1/(z+0.5)", {}, 0.1);
  EXPECT_THROW(d2c(neg, C2dMethod::Zoh), InputError);
  EXPECT_THROW(d2c(StateSpace::from_tf(neg), C2dMethod::Zoh), InputError);
  EXPECT_THROW(d2c(TransferFunction::parse("1/z", {}, 0.1), C2dMethod::Zoh), InputError);
  // d2c Tustin with a pole at z = -1.
  EXPECT_THROW(d2c(StateSpace::from_tf(TransferFunction::parse("1/(z+1)", {}, 0.1)), C2dMethod::Tustin),
               InputError);
}

}  // namespace
}  // namespace dmbd::blocks
