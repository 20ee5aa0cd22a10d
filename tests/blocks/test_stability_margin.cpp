// dmbd::blocks stability margin min |1 + L|: the closed form of 1/(s(s+1)), an infimum
// at infinity, a static gain, a sharp minimum of a lightly damped closed loop against a
// brute-force search, and a discrete loop.
#include <gtest/gtest.h>

#include <cmath>

#include "dmbd/blocks/stability_margin.hpp"
#include "dmbd/blocks/transfer_function.hpp"

namespace dmbd::blocks {
namespace {

StabilityMargin of(const TransferFunction& g) {
  std::vector<Complex> features = g.poles();
  for (const Complex& z : g.zeros()) features.push_back(z);
  for (const Complex& p : feedback(g, TransferFunction(1.0, g.ts())).poles()) features.push_back(p);
  const double lead = g.num().degree() == g.den().degree() ? g.num().leading() / g.den().leading() : 0.0;
  return stability_margin(
      [&g](double w) { return g.evaluate(g.is_discrete() ? std::polar(1.0, w * g.ts()) : Complex(0.0, w)); }, features,
      g.ts(), lead);
}

TEST(StabilityMargin, IntegratorWithLagClosedForm) {
  // |1 + L|^2 = (u^2 - u + 1)/(u^2 + u), u = w^2: least at 2u^2 - 2u - 1 = 0.
  const double u = (1.0 + std::sqrt(3.0)) / 2.0;
  const double sm = std::sqrt((u * u - u + 1.0) / (u * u + u));
  const StabilityMargin m = of(TransferFunction::parse("1/(s*(s+1))"));
  EXPECT_NEAR(m.margin, sm, 1e-14);  // flat at the minimum: rounding
  EXPECT_NEAR(m.w_rad_s, std::sqrt(u), 1e-6);  // the golden search's 1e-12 in w, sqrt of it in value terms
  ASSERT_EQ(m.minima.size(), 1u);
}

TEST(StabilityMargin, InfimumAtInfinityAndStaticGain) {
  const StabilityMargin lag = of(TransferFunction::parse("1/(s+1)"));  // |1 + L| falls to 1
  EXPECT_EQ(lag.margin, 1.0);
  EXPECT_TRUE(std::isinf(lag.w_rad_s));
  const StabilityMargin k = of(TransferFunction(0.5));
  EXPECT_EQ(k.margin, 1.5);
  EXPECT_EQ(k.w_rad_s, 0.0);
  ASSERT_EQ(k.minima.size(), 1u);
}

TEST(StabilityMargin, SharpMinimumOfALightlyDampedLoop) {
  // 1 + L = (s^2 + 0.002 s + 100.5)/(s (s + 0.002) + ...): closed-loop poles with damping
  // 1e-4 at 10 rad/s; the minimum is a needle 2e-3 rad/s wide.
  const TransferFunction g = TransferFunction::parse("100/(s*(s+0.002))");
  const StabilityMargin m = of(g);
  double best = 1e300;
  for (int i = 0; i <= 200000; ++i) {
    const double w = 9.99 + 0.02 * i / 200000.0;
    best = std::min(best, std::abs(1.0 + g.evaluate(Complex(0.0, w))));
  }
  EXPECT_LE(m.margin, best * (1.0 + 1e-9));  // never worse than 200000 samples of the needle
  EXPECT_NEAR(m.w_rad_s, 10.0, 1e-3);
}

TEST(StabilityMargin, DiscreteLoop) {
  const TransferFunction g = TransferFunction::parse("0.5/(z-0.8)", {}, 0.01);
  const StabilityMargin m = of(g);
  // |1 + L| = |z - 0.3| / |z - 0.8| on |z| = 1 is least at z = -1: 1.3/1.8, the Nyquist end.
  EXPECT_NEAR(m.margin, 1.3 / 1.8, 1e-15);
  EXPECT_NEAR(m.w_rad_s, M_PI / 0.01, 1e-9);
}

}  // namespace
}  // namespace dmbd::blocks
