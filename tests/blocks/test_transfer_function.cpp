// dmbd::blocks::TransferFunction: normalisation, poles/zeros, DC gain, properness,
// stability, minreal, interconnection against hand-derived polynomials, sample-time
// checks.
#include <gtest/gtest.h>

#include <cmath>

#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/transfer_function.hpp"
#include "test_support.hpp"

namespace dmbd::blocks {
namespace {

using test::coeffs_near;
using test::complex_near;
using test::roots_near;
using test::tf_near;

TEST(TransferFunction, NormalisesToMonicDenominator) {
  // (6s + 3) / (3s^2 + 9s + 6) = (2s + 1) / (s^2 + 3s + 2).
  const TransferFunction g(Polynomial({3.0, 6.0}), Polynomial({6.0, 9.0, 3.0}));
  EXPECT_EQ(g.den().leading(), 1.0);  // exactly 1 (header contract)
  // Division by 3 rounds: 1 ulp per coefficient, 1e-15 relative.
  EXPECT_TRUE(coeffs_near(g.den(), {2.0, 3.0, 1.0}, 1e-15));
  EXPECT_TRUE(coeffs_near(g.num(), {1.0, 2.0}, 1e-15));
  EXPECT_EQ(g.order(), 2);
  EXPECT_EQ(g.relative_degree(), 1);
  // A leading coefficient that does not divide exactly still gives an exact 1.
  const TransferFunction h(Polynomial({1.0}), Polynomial({1.0, 0.1}));
  EXPECT_EQ(h.den().leading(), 1.0);
  // 1/(0.1 s + 1) = 10/(s + 10): one rounding, 1e-15 relative.
  EXPECT_TRUE(coeffs_near(h.den(), {10.0, 1.0}, 1e-15));
  EXPECT_TRUE(coeffs_near(h.num(), {10.0}, 1e-15));
  // from_descending is highest power first.
  const TransferFunction f = TransferFunction::from_descending({1.0, 2.0}, {1.0, 3.0, 2.0});
  EXPECT_EQ(f.num().coeffs(), (std::vector<double>{2.0, 1.0}));  // exact: monic input
  EXPECT_EQ(f.den().coeffs(), (std::vector<double>{2.0, 3.0, 1.0}));
  // A constant gain.
  const TransferFunction k(2.5);
  EXPECT_EQ(k.order(), 0);
  EXPECT_EQ(k.evaluate(Complex(0.0, 7.0)), Complex(2.5));  // exact
}

TEST(TransferFunction, ConstructionErrors) {
  EXPECT_THROW(TransferFunction(Polynomial({1.0}), Polynomial()), InputError);
  EXPECT_THROW(TransferFunction(1.0, -0.1), InputError);
  EXPECT_THROW(TransferFunction(1.0, std::nan("")), InputError);
  EXPECT_THROW(TransferFunction(1.0, INFINITY), InputError);
  EXPECT_THROW(TransferFunction(Polynomial({NAN}), Polynomial({1.0})), InputError);
  EXPECT_THROW(TransferFunction(Polynomial({1.0}), Polynomial({1.0, INFINITY})), InputError);
}

TEST(TransferFunction, PolesAndZeros) {
  // (s - 2)(s + 3) / ((s + 1)(s^2 + 2s + 10)).
  const TransferFunction g(Polynomial::from_roots({2.0, -3.0}),
                           Polynomial::from_roots({-1.0, {-1.0, 3.0}, {-1.0, -3.0}}));
  // Simple roots: ~eps, 1e-12 relative.
  EXPECT_TRUE(roots_near(g.zeros(), {2.0, -3.0}, 1e-12));
  EXPECT_TRUE(roots_near(g.poles(), {-1.0, {-1.0, 3.0}, {-1.0, -3.0}}, 1e-12));
  EXPECT_TRUE(g.is_strictly_proper());
  EXPECT_TRUE(g.is_stable());  // poles in the open left half-plane
}

TEST(TransferFunction, DcGain) {
  // (2s + 6)/(s^2 + 3s + 2) at s = 0: 3, exact.
  EXPECT_EQ(*TransferFunction::from_descending({2.0, 6.0}, {1.0, 3.0, 2.0}).dc_gain(), 3.0);
  // 1/s: infinite.
  EXPECT_FALSE(TransferFunction::parse("1/s").dc_gain().has_value());
  // 1/(s^2 (s+1)) and (s+1)/s^2: infinite.
  EXPECT_FALSE(TransferFunction::parse("1/(s^2*(s+1))").dc_gain().has_value());
  EXPECT_FALSE(TransferFunction::parse("s/s^2").dc_gain().has_value());
  // s/(s+1): 0 exactly.
  EXPECT_EQ(*TransferFunction::parse("s/(s+1)").dc_gain(), 0.0);
  // s/(s (s+1)): the common root at 0 cancels, 1 exactly.
  const auto c = TransferFunction(Polynomial({0.0, 1.0}), Polynomial({0.0, 1.0, 1.0})).dc_gain();
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(*c, 1.0);
  // s^2 (s+3) / (s^2 (s+1)(s+2)) -> 3/2 after cancelling a double root at 0.
  const auto c2 = TransferFunction::parse("s^2*(s+3)/(s^2*(s+1)*(s+2))").dc_gain();
  ASSERT_TRUE(c2.has_value());
  EXPECT_NEAR(*c2, 1.5, 1e-15);  // integer arithmetic, one division: 1 ulp
  // The zero TF.
  EXPECT_EQ(*TransferFunction(0.0).dc_gain(), 0.0);
  // A zero transfer function over a pole at 0: still 0.
  EXPECT_EQ(*TransferFunction(Polynomial(), Polynomial({0.0, 1.0})).dc_gain(), 0.0);
}

TEST(TransferFunction, DcGainDiscrete) {
  const double ts = 0.01;
  // 0.5/(z - 0.5) at z = 1: 1.
  EXPECT_EQ(*TransferFunction::parse("0.5/(z-0.5)", {}, ts).dc_gain(), 1.0);  // exact binary fractions
  // Integrator ts z/(z-1): infinite.
  EXPECT_FALSE(TransferFunction::parse("0.01*z/(z-1)", {}, ts).dc_gain().has_value());
  // (z - 1)/((z - 1)(z - 0.5)) cancels at z = 1 -> 1/(1 - 0.5) = 2.
  const auto c = TransferFunction::parse("(z-1)/((z-1)*(z-0.5))", {}, ts).dc_gain();
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(*c, 2.0, 1e-14);  // synthetic division by (z - 1), a few roundings
  // A differentiator (z-1)/z: 0.
  EXPECT_EQ(*TransferFunction::parse("(z-1)/z", {}, ts).dc_gain(), 0.0);
}

TEST(TransferFunction, Properness) {
  const TransferFunction proper = TransferFunction::parse("(s+1)/(s+2)");
  EXPECT_TRUE(proper.is_proper());
  EXPECT_FALSE(proper.is_strictly_proper());
  EXPECT_EQ(proper.relative_degree(), 0);
  const TransferFunction improper = TransferFunction::parse("s^2/(s+1)");
  EXPECT_FALSE(improper.is_proper());
  EXPECT_EQ(improper.relative_degree(), -1);
  EXPECT_TRUE(TransferFunction::parse("1/(s+1)^3").is_strictly_proper());
  EXPECT_EQ(TransferFunction::parse("1/(s+1)^3").relative_degree(), 3);
}

TEST(TransferFunction, StabilityContinuous) {
  EXPECT_TRUE(TransferFunction::parse("1/(s^2 + 0.1*s + 4)").is_stable());
  EXPECT_FALSE(TransferFunction::parse("1/(s^2 + 4)").is_stable());        // marginal: poles on the axis
  EXPECT_FALSE(TransferFunction::parse("1/s").is_stable());                // pole at 0
  EXPECT_FALSE(TransferFunction::parse("1/(s^2 - 0.1*s + 4)").is_stable());  // RHP pair
  EXPECT_FALSE(TransferFunction::parse("1/((s+1)*(s-0.001))").is_stable());
  EXPECT_TRUE(TransferFunction::parse("(s-5)/(s+1)").is_stable());  // RHP zero does not matter
  EXPECT_TRUE(TransferFunction(3.0).is_stable());                   // no poles
}

TEST(TransferFunction, StabilityDiscrete) {
  const double ts = 0.1;
  EXPECT_TRUE(TransferFunction::parse("1/(z-0.5)", {}, ts).is_stable());
  EXPECT_TRUE(TransferFunction::parse("1/(z+0.99)", {}, ts).is_stable());
  EXPECT_FALSE(TransferFunction::parse("1/(z-1)", {}, ts).is_stable());    // on the unit circle
  EXPECT_FALSE(TransferFunction::parse("1/(z+1.1)", {}, ts).is_stable());
  // |z|^2 = 1.0001 (just outside the circle) vs |z|^2 = 0.85 (inside).
  EXPECT_FALSE(TransferFunction::parse("1/(z^2 - 1.2*z + 1.0001)", {}, ts).is_stable());
  EXPECT_TRUE(TransferFunction::parse("1/(z^2 - 1.2*z + 0.85)", {}, ts).is_stable());
  // A continuous-stable pole location -0.5 is stable in z too; 1.5 is not.
  EXPECT_TRUE(TransferFunction::parse("1/(z+0.5)", {}, ts).is_stable());
  EXPECT_FALSE(TransferFunction::parse("1/(z-1.5)", {}, ts).is_stable());
  // A discrete 1/(z - 0.5) is stable, the continuous 1/(s - 0.5) is not: is_stable
  // follows the sample time.
  EXPECT_FALSE(TransferFunction::parse("1/(s-0.5)").is_stable());
}

TEST(TransferFunction, Minreal) {
  // (s+1)(s+2) / ((s+1)(s+3)) -> (s+2)/(s+3).
  const TransferFunction g = TransferFunction::parse("(s+1)*(s+2)/((s+1)*(s+3))").minreal();
  // Roots to ~eps and re-expansion: 1e-12 relative.
  EXPECT_TRUE(tf_near(g, TransferFunction::parse("(s+2)/(s+3)"), 1e-12));
  // Gain preserved: 4 (s^2 + 2s + 5) / ((s^2 + 2s + 5)(s + 3)) -> 4/(s+3).
  const TransferFunction h = TransferFunction::parse("4*(s^2+2*s+5)/((s^2+2*s+5)*(s+3))").minreal();
  EXPECT_TRUE(tf_near(h, TransferFunction::parse("4/(s+3)"), 1e-12));
  // Nothing to cancel: unchanged (exact).
  const TransferFunction k = TransferFunction::parse("(s+1)/(s+2)");
  EXPECT_EQ(k.minreal().num(), k.num());
  EXPECT_EQ(k.minreal().den(), k.den());
  // A pair 1e-4 apart survives at the default tol 1e-7 and cancels at tol 1e-3.
  const TransferFunction near = TransferFunction::parse("(s+1.0001)/((s+1)*(s+5))");
  EXPECT_EQ(near.minreal().order(), 2);
  EXPECT_EQ(near.minreal(1e-3).order(), 1);
  // Discrete: keeps its sample time.
  const TransferFunction d = TransferFunction::parse("(z-0.5)/((z-0.5)*(z-0.25))", {}, 0.1).minreal();
  EXPECT_TRUE(tf_near(d, TransferFunction::parse("1/(z-0.25)", {}, 0.1), 1e-12));
  // The cancelled system has the same frequency response (away from the cancelled
  // root): 1e-12 relative.
  const Complex s(0.3, 2.0);
  EXPECT_TRUE(complex_near(g.evaluate(s), (s + 2.0) / (s + 3.0), 1e-12));
}

TEST(TransferFunction, SeriesAgainstHandProduct) {
  const TransferFunction a = TransferFunction::parse("(s+1)/(s^2+3*s+2)");  // (s+1)/((s+1)(s+2))
  const TransferFunction b = TransferFunction::parse("2*(s-3)/(s+5)");
  const TransferFunction g = a * b;
  // (s+1)*2(s-3) = 2s^2 - 4s - 6; (s^2+3s+2)(s+5) = s^3 + 8s^2 + 17s + 10. Exact (integers).
  EXPECT_EQ(g.num().coeffs(), (std::vector<double>{-6.0, -4.0, 2.0}));
  EXPECT_EQ(g.den().coeffs(), (std::vector<double>{10.0, 17.0, 8.0, 1.0}));
  // Division: a / b = (s+1)(s+5) / ((s^2+3s+2) * 2(s-3)).
  const TransferFunction q = a / b;
  // = (s^2 + 6s + 5) / (2s^3 - 14s - 12); normalised by the leading 2: exact halves.
  EXPECT_EQ(q.num().coeffs(), (std::vector<double>{2.5, 3.0, 0.5}));
  EXPECT_EQ(q.den().coeffs(), (std::vector<double>{-6.0, -7.0, 0.0, 1.0}));
  EXPECT_THROW(a / TransferFunction(0.0), InputError);
}

TEST(TransferFunction, ParallelAgainstHandSum) {
  const TransferFunction a = TransferFunction::parse("1/(s+1)");
  const TransferFunction b = TransferFunction::parse("2/(s+3)");
  // 1/(s+1) + 2/(s+3) = (3s + 5)/(s^2 + 4s + 3). Exact (integers).
  const TransferFunction g = a + b;
  EXPECT_EQ(g.num().coeffs(), (std::vector<double>{5.0, 3.0}));
  EXPECT_EQ(g.den().coeffs(), (std::vector<double>{3.0, 4.0, 1.0}));
  // 1/(s+1) - 2/(s+3) = (-s + 1)/(s^2 + 4s + 3).
  const TransferFunction h = a - b;
  EXPECT_EQ(h.num().coeffs(), (std::vector<double>{1.0, -1.0}));
  EXPECT_EQ(h.den().coeffs(), (std::vector<double>{3.0, 4.0, 1.0}));
  // Same denominator: no growth in order.
  EXPECT_EQ((a + a).order(), 1);
  EXPECT_EQ((a + a).num().coeffs(), (std::vector<double>{2.0}));  // exact
  // Parallel with a constant: 1/(s+1) + 1 = (s+2)/(s+1).
  EXPECT_EQ((a + TransferFunction(1.0)).num().coeffs(), (std::vector<double>{2.0, 1.0}));  // exact
  // Unary minus and pow.
  EXPECT_EQ((-a).num().coeffs(), (std::vector<double>{-1.0}));           // exact
  EXPECT_EQ(a.pow(2).den().coeffs(), (std::vector<double>{1.0, 2.0, 1.0}));  // exact
  EXPECT_EQ(a.pow(-1).num().coeffs(), (std::vector<double>{1.0, 1.0}));      // s + 1, exact
  EXPECT_EQ(a.pow(0).num().coeffs(), (std::vector<double>{1.0}));
}

TEST(TransferFunction, FeedbackAgainstHandDerivation) {
  // G = 1/(s+1), unity negative feedback: 1/(s+2). Exact.
  const TransferFunction g = TransferFunction::parse("1/(s+1)");
  const TransferFunction cl = feedback(g);
  EXPECT_EQ(cl.num().coeffs(), (std::vector<double>{1.0}));
  EXPECT_EQ(cl.den().coeffs(), (std::vector<double>{2.0, 1.0}));
  // Positive feedback: 1/s.
  const TransferFunction pos = feedback(g, TransferFunction(1.0), +1);
  EXPECT_EQ(pos.den().coeffs(), (std::vector<double>{0.0, 1.0}));  // exact
  // G = 10/(s(s+1)), H = 1/(s+5): G/(1 + G H) = 10 (s+5) / (s(s+1)(s+5) + 10)
  // = (10 s + 50) / (s^3 + 6 s^2 + 5 s + 10). Exact (integers).
  const TransferFunction g2 = TransferFunction::parse("10/(s*(s+1))");
  const TransferFunction h2 = TransferFunction::parse("1/(s+5)");
  const TransferFunction cl2 = feedback(g2, h2);
  EXPECT_EQ(cl2.num().coeffs(), (std::vector<double>{50.0, 10.0}));
  EXPECT_EQ(cl2.den().coeffs(), (std::vector<double>{10.0, 5.0, 6.0, 1.0}));
  // Cross-check with the algebraic formula at a point: G/(1+GH), 1e-14 relative.
  const Complex s(0.2, 1.3);
  EXPECT_TRUE(complex_near(cl2.evaluate(s), g2.evaluate(s) / (1.0 + g2.evaluate(s) * h2.evaluate(s)), 1e-14));
  // Non-proper feedback path with D terms: G = (s+2)/(s+1), H = 2 -> (s+2)/(3s+5).
  const TransferFunction cl3 = feedback(TransferFunction::parse("(s+2)/(s+1)"), TransferFunction(2.0));
  // Division by 3: 1 ulp, 1e-15 relative.
  EXPECT_TRUE(coeffs_near(cl3.num(), {2.0 / 3.0, 1.0 / 3.0}, 1e-15));
  EXPECT_TRUE(coeffs_near(cl3.den(), {5.0 / 3.0, 1.0}, 1e-15));
  // Algebraic loop: G = 1, H = 1, positive feedback: 1 - G H == 0.
  EXPECT_THROW(feedback(TransferFunction(1.0), TransferFunction(1.0), +1), InputError);
  // G = (s+1)/(s+2), H = (s+2)/(s+1), positive feedback: 1 - G H == 0 identically.
  EXPECT_THROW(feedback(TransferFunction::parse("(s+1)/(s+2)"), TransferFunction::parse("(s+2)/(s+1)"), +1),
               InputError);
}

TEST(TransferFunction, SampleTimeMismatchThrows) {
  const TransferFunction c = TransferFunction::parse("1/(s+1)");
  const TransferFunction d1 = TransferFunction::parse("1/(z-0.5)", {}, 0.1);
  const TransferFunction d2 = TransferFunction::parse("1/(z-0.5)", {}, 0.2);
  EXPECT_THROW(c * d1, InputError);
  EXPECT_THROW(d1 * d2, InputError);
  EXPECT_THROW(c + d1, InputError);
  EXPECT_THROW(d1 - d2, InputError);
  EXPECT_THROW(d1 / d2, InputError);
  EXPECT_THROW(feedback(d1, d2), InputError);
  EXPECT_THROW(feedback(d1, c), InputError);
  EXPECT_THROW(require_same_ts(0.1, 0.2, "test"), InputError);
  EXPECT_NO_THROW(require_same_ts(0.1, 0.1, "test"));
  // Same sample time: fine, and the result keeps it.
  EXPECT_EQ((d1 * d1).ts(), 0.1);
  EXPECT_EQ(feedback(d1, d1).ts(), 0.1);
  // A discrete TF times a constant created with the same ts.
  EXPECT_EQ((d1 * TransferFunction(2.0, 0.1)).num().coeffs(), (std::vector<double>{2.0}));  // exact
}

}  // namespace
}  // namespace dmbd::blocks
