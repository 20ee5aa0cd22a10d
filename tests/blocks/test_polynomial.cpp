// dmbd::blocks::Polynomial: construction, arithmetic, evaluation, division, roots,
// from_roots, compose, negated_argument, pow.
#include <gtest/gtest.h>

#include <cmath>

#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/polynomial.hpp"
#include "test_support.hpp"

namespace dmbd::blocks {
namespace {

using test::poly_near;
using test::complex_near;
using test::roots_near;

TEST(Polynomial, ConstructionStripsLeadingZerosAndOrders) {
  const Polynomial p{1.0, 2.0, 3.0, 0.0, 0.0};  // 1 + 2x + 3x^2 with stripped zeros
  // Exact: construction only moves coefficients around.
  EXPECT_EQ(p.degree(), 2);
  EXPECT_EQ(p.descending(), (std::vector<double>{3.0, 2.0, 1.0}));
  EXPECT_EQ(Polynomial::from_descending({3.0, 2.0, 1.0}), p);
  EXPECT_EQ(p.leading(), 3.0);
  EXPECT_EQ(p[5], 0.0);  // out-of-range coefficients read as 0
  EXPECT_EQ(p[-1], 0.0);

  const Polynomial z{0.0, 0.0};
  EXPECT_TRUE(z.is_zero());
  EXPECT_EQ(z.degree(), -1);
  EXPECT_EQ(Polynomial::monomial(3, 2.0).coeffs(), (std::vector<double>{0.0, 0.0, 0.0, 2.0}));
  EXPECT_EQ(Polynomial::constant(4.0).degree(), 0);
  EXPECT_EQ(Polynomial({0.0, 0.0, 1.0, 1.0}).zero_roots(), 2);
}

TEST(Polynomial, Arithmetic) {
  const Polynomial a{1.0, 2.0};       // 1 + 2x
  const Polynomial b{-1.0, 0.0, 3.0};  // -1 + 3x^2
  // Small integers: all results are exact in binary floating point (tolerance 0).
  EXPECT_EQ((a + b).coeffs(), (std::vector<double>{0.0, 2.0, 3.0}));
  EXPECT_EQ((a - b).coeffs(), (std::vector<double>{2.0, 2.0, -3.0}));
  EXPECT_EQ((a * b).coeffs(), (std::vector<double>{-1.0, -2.0, 3.0, 6.0}));
  EXPECT_EQ((2.0 * a).coeffs(), (std::vector<double>{2.0, 4.0}));
  EXPECT_EQ((-a).coeffs(), (std::vector<double>{-1.0, -2.0}));
  // Cancellation of the leading term reduces the degree; x - x is the zero polynomial.
  EXPECT_EQ((b - Polynomial({0.0, 0.0, 3.0})).degree(), 0);
  EXPECT_TRUE((a - a).is_zero());
  EXPECT_TRUE((a * Polynomial()).is_zero());
  EXPECT_EQ(Polynomial({2.0, 4.0}).monic().coeffs(), (std::vector<double>{0.5, 1.0}));
}

TEST(Polynomial, EvaluationAtRealAndComplexPoints) {
  const Polynomial p{5.0, -3.0, 0.0, 2.0};  // 2x^3 - 3x + 5
  auto direct = [](Complex x) { return 2.0 * x * x * x - 3.0 * x + 5.0; };
  // Exact at a small integer point (Horner on integers).
  EXPECT_EQ(p(2.0), 15.0);
  for (const Complex x : {Complex(0.3, -1.7), Complex(-2.0, 0.5), Complex(0.0, 4.0), Complex(1e3, 1e3)}) {
    // Horner vs the expanded formula: both a few roundings, 1e-14 relative.
    EXPECT_TRUE(complex_near(p(x), direct(x), 1e-14)) << "x = " << x;
  }
  // p(jw) of s^2 + 2 s + 5 at w = 2: (5 - 4) + 4j exactly.
  const Polynomial q{5.0, 2.0, 1.0};
  EXPECT_EQ(q(Complex(0.0, 2.0)), Complex(1.0, 4.0));  // exact: small integers
}

TEST(Polynomial, Derivative) {
  const Polynomial p{1.0, -4.0, 0.5, 2.0, -1.0};
  // d/dx: integer multiples of binary fractions, exact.
  EXPECT_EQ(p.derivative().coeffs(), (std::vector<double>{-4.0, 1.0, 6.0, -4.0}));
  EXPECT_TRUE(Polynomial::constant(7.0).derivative().is_zero());
  // Cross-check with a central difference at x = 0.7 (step 1e-5: truncation ~1e-10,
  // rounding ~1e-11 on values of order 1).
  const double x = 0.7, h = 1e-5;
  EXPECT_NEAR(p.derivative()(x), (p(x + h) - p(x - h)) / (2 * h), 1e-8);
}

TEST(Polynomial, DivideSatisfiesEuclid) {
  const Polynomial a{-7.0, 3.0, 0.0, 5.0, 2.0, 1.0};  // degree 5
  const Polynomial b{2.0, -1.0, 3.0};                 // degree 2
  const auto [q, r] = Polynomial::divide(a, b);
  EXPECT_EQ(q.degree(), 3);
  EXPECT_LT(r.degree(), b.degree());
  // q*b + r == a up to rounding of a 3-step synthetic division: 1e-14 relative to max|a|.
  EXPECT_TRUE(poly_near(q * b + r, a, 1e-14));

  // Exact division: (x^2 - 1) / (x - 1) = x + 1, remainder 0.
  const auto [q2, r2] = Polynomial::divide(Polynomial({-1.0, 0.0, 1.0}), Polynomial({-1.0, 1.0}));
  EXPECT_EQ(q2.coeffs(), (std::vector<double>{1.0, 1.0}));  // exact: integers
  EXPECT_TRUE(r2.is_zero());

  // Lower degree numerator: quotient 0, remainder a.
  const auto [q3, r3] = Polynomial::divide(b, a);
  EXPECT_TRUE(q3.is_zero());
  EXPECT_EQ(r3, b);

  EXPECT_THROW(Polynomial::divide(a, Polynomial()), InputError);
}

TEST(Polynomial, RootsDistinctReal) {
  // (x-1)(x-2)(x+3) = x^3 - 7x + 6.
  const Polynomial p{6.0, -7.0, 0.0, 1.0};
  // Simple, well separated roots: companion eigenvalues + Newton polish give ~eps.
  EXPECT_TRUE(roots_near(p.roots(), {-3.0, 1.0, 2.0}, 1e-13));
  // Sorted by real part (header contract).
  const auto r = p.roots();
  EXPECT_NEAR(r[0].real(), -3.0, 1e-13);  // smallest real part first; same accuracy as above
  EXPECT_NEAR(r[2].real(), 2.0, 1e-13);
  for (const Complex& z : r) EXPECT_EQ(z.imag(), 0.0);  // near-real singletons are made exactly real
}

TEST(Polynomial, RootsComplexPairs) {
  // (x^2 + 2x + 5)(x^2 - 0.5x + 4) roots -1 +- 2j and 0.25 +- j sqrt(3.9375).
  const Polynomial p = Polynomial({5.0, 2.0, 1.0}) * Polynomial({4.0, -0.5, 1.0});
  const double w2 = std::sqrt(4.0 - 0.0625);
  const auto r = p.roots();
  // Simple roots: ~eps accuracy, 1e-12 relative leaves room for the conditioning.
  EXPECT_TRUE(roots_near(r, {{-1.0, 2.0}, {-1.0, -2.0}, {0.25, w2}, {0.25, -w2}}, 1e-12));
  // Conjugate pairs are exact conjugates (header contract): equality, tolerance 0.
  ASSERT_EQ(r.size(), 4u);
  EXPECT_EQ(r[0], std::conj(r[1]));
  EXPECT_EQ(r[2], std::conj(r[3]));
}

TEST(Polynomial, DoubleRoot) {
  // (x - 3)^2 (x + 1): a double root is only determined to ~sqrt(eps) ~ 1.5e-8 relative;
  // the brief asks ~1e-7 relative.
  const Polynomial p = Polynomial({-3.0, 1.0}).pow(2) * Polynomial({1.0, 1.0});
  EXPECT_TRUE(roots_near(p.roots(), {-1.0, 3.0, 3.0}, 1e-7));
  // A double complex pair (x^2 + 1)^2: +-j each twice, same sqrt(eps) conditioning.
  EXPECT_TRUE(roots_near(Polynomial({1.0, 0.0, 1.0}).pow(2).roots(),
                         {{0.0, 1.0}, {0.0, 1.0}, {0.0, -1.0}, {0.0, -1.0}}, 1e-7));
}

TEST(Polynomial, RootsAtZero) {
  // x^3 (x - 2)(x + 5): exact zeros come from trailing zero coefficients (tolerance 0).
  const Polynomial p = Polynomial::monomial(3) * Polynomial({-2.0, 1.0}) * Polynomial({5.0, 1.0});
  const auto r = p.roots();
  ASSERT_EQ(r.size(), 5u);
  int zeros = 0;
  for (const Complex& z : r) zeros += z == Complex(0.0);
  EXPECT_EQ(zeros, 3);
  // The others are simple: ~eps.
  EXPECT_TRUE(roots_near(r, {0.0, 0.0, 0.0, 2.0, -5.0}, 1e-13));
  // Pure monomial: all roots exactly zero.
  const auto m = Polynomial::monomial(4, 3.0).roots();
  ASSERT_EQ(m.size(), 4u);
  for (const Complex& z : m) EXPECT_EQ(z, Complex(0.0));  // exact by construction
}

TEST(Polynomial, RootsOfHighishOrder) {
  // (x+1)(x+2)...(x+8): a mild Wilkinson-type polynomial (coefficients up to 1.1e5).
  // The root condition numbers here are ~1e3..1e4, so with Newton polishing 1e-10
  // relative is comfortably above the attainable accuracy (~1e-12).
  Polynomial p = Polynomial::constant(1.0);
  std::vector<Complex> want;
  for (int k = 1; k <= 8; ++k) {
    p = p * Polynomial({static_cast<double>(k), 1.0});
    want.emplace_back(-k, 0.0);
  }
  EXPECT_EQ(p[0], 40320.0);  // 8! exactly: integer products below 2^53
  EXPECT_TRUE(roots_near(p.roots(), want, 1e-10));
  // Badly scaled roots (1e-3 .. 1e3): the balanced companion matrix handles them;
  // relative accuracy per root 1e-10.
  const std::vector<Complex> spread{-1e-3, -0.1, {-10.0, 30.0}, {-10.0, -30.0}, -1e3};
  EXPECT_TRUE(roots_near(Polynomial::from_roots(spread).roots(), spread, 1e-10));
  // And for the small root, an absolute check relative to itself: 1e-10 * 1e-3.
  const auto r = Polynomial::from_roots(spread).roots();
  double nearest = 1.0;
  for (const Complex& z : r) nearest = std::min(nearest, std::abs(z + 1e-3));
  EXPECT_LT(nearest, 1e-13);  // relative 1e-10 of the 1e-3 root
}

TEST(Polynomial, FromRootsRoundTrip) {
  const std::vector<Complex> roots{-0.5, {-1.0, 3.0}, {-1.0, -3.0}, 2.0, 0.0};
  const Polynomial p = Polynomial::from_roots(roots, 2.0);
  EXPECT_EQ(p.degree(), 5);
  EXPECT_EQ(p.leading(), 2.0);  // exact: the leading coefficient is leading * 1
  // Hand expansion: 2 x (x + 0.5)(x - 2)(x^2 + 2x + 10).
  const Polynomial hand = 2.0 * Polynomial({0.0, 1.0}) * Polynomial({0.5, 1.0}) * Polynomial({-2.0, 1.0}) *
                          Polynomial({10.0, 2.0, 1.0});
  // Products of small binary fractions: a few roundings at most, 1e-15 relative.
  EXPECT_TRUE(poly_near(p, hand, 1e-15));
  // And back: simple roots to ~eps.
  EXPECT_TRUE(roots_near(p.roots(), roots, 1e-12));
  // Roots not closed under conjugation give a complex polynomial: InputError.
  EXPECT_THROW(Polynomial::from_roots({Complex(1.0, 1.0)}), InputError);
  EXPECT_THROW(Polynomial::from_roots({Complex(1.0, 1.0), Complex(1.0, -0.9)}), InputError);
  // The empty product is the constant `leading`.
  EXPECT_EQ(Polynomial::from_roots({}, 3.0), Polynomial::constant(3.0));
}

TEST(Polynomial, Compose) {
  const Polynomial p{1.0, -2.0, 0.0, 1.0};  // x^3 - 2x + 1
  const Polynomial inner{3.0, 0.5, 2.0};    // 2x^2 + 0.5x + 3
  const Polynomial c = p.compose(inner);
  EXPECT_EQ(c.degree(), 6);
  // Leading coefficient 1 * 2^3 = 8 exactly.
  EXPECT_EQ(c.leading(), 8.0);
  for (const Complex x : {Complex(0.4, 0.0), Complex(-1.3, 0.7), Complex(0.0, 2.0)}) {
    // p(inner(x)) two ways; values up to ~1e3, a dozen roundings: 1e-13 relative.
    EXPECT_TRUE(complex_near(c(x), p(inner(x)), 1e-13)) << "x = " << x;
  }
  // Composition with x is the identity (exact).
  EXPECT_EQ(p.compose(Polynomial({0.0, 1.0})), p);
}

TEST(Polynomial, NegatedArgument) {
  const Polynomial p{1.0, 2.0, 3.0, 4.0};
  // Sign flips only: exact.
  EXPECT_EQ(p.negated_argument().coeffs(), (std::vector<double>{1.0, -2.0, 3.0, -4.0}));
  // Cross-check against compose with -x (exact: integer arithmetic).
  EXPECT_EQ(p.negated_argument(), p.compose(Polynomial({0.0, -1.0})));
  // p(-x) at x = 0.3 + 0.2j equals p at -x: Horner either way, 1e-15 relative.
  const Complex x(0.3, 0.2);
  EXPECT_TRUE(complex_near(p.negated_argument()(x), p(-x), 1e-15));
}

TEST(Polynomial, Pow) {
  // (x + 1)^5 = binomial coefficients 1 5 10 10 5 1 exactly (integers).
  EXPECT_EQ(Polynomial({1.0, 1.0}).pow(5).coeffs(), (std::vector<double>{1.0, 5.0, 10.0, 10.0, 5.0, 1.0}));
  EXPECT_EQ(Polynomial({2.0, 1.0}).pow(0), Polynomial::constant(1.0));  // p^0 = 1, exact
  // p^3 equals p*p*p (repeated squaring vs repeated product; exact in integers).
  const Polynomial p{-1.0, 3.0, 2.0};
  EXPECT_EQ(p.pow(3), p * p * p);
  // Evaluate (0.5 - 0.25x)^7 at x = 1.5: (0.125)^7, exact power of two.
  EXPECT_EQ(Polynomial({0.5, -0.25}).pow(7)(1.5), std::pow(0.125, 7));
  EXPECT_THROW(p.pow(-1), InputError);
}

TEST(Polynomial, Trimmed) {
  const Polynomial p{1.0, 2.0, 1e-17};
  // Leading coefficient 1e-17 <= 1e-15 * 2 is dropped; exact otherwise.
  EXPECT_EQ(p.trimmed(1e-15).coeffs(), (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(p.trimmed(1e-20).degree(), 2);
}

}  // namespace
}  // namespace dmbd::blocks
