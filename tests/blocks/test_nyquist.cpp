// dmbd::blocks Nyquist data: the count from the criterion against the winding of the
// sampled curve, for stable and unstable loops, an integrator (indented contour) and a
// discrete loop; the points on the contour; the refusals.
#include <gtest/gtest.h>

#include <cmath>

#include "dmbd/base/error.hpp"
#include "dmbd/blocks/frequency.hpp"
#include "dmbd/blocks/nyquist.hpp"
#include "dmbd/blocks/transfer_function.hpp"

namespace dmbd::blocks {
namespace {

Nyquist of(const TransferFunction& g, const std::vector<double>& w) {
  const TransferFunction cl = feedback(g, TransferFunction(1.0, g.ts()));
  return nyquist([&g](Complex x) { return g.evaluate(x); }, g.poles(), cl.poles(), w, g.ts());
}

std::vector<double> dense(double hi) {
  std::vector<double> w{0.0};
  for (double v : logspace(1e-4, hi, 20000)) w.push_back(v);
  return w;
}

TEST(Nyquist, CountsMatchTheCurve) {
  struct Case {
    const char* g;
    int count;
  } cases[] = {{"4/(s+1)^3", 0}, {"10/(s+1)^3", 2}, {"2/(s-1)", -1}, {"0.5/(s-1)", 0}, {"1/(s*(s+1))", 0},
               {"3/(s*(s-1))", 1}};
  for (const Case& c : cases) {
    const Nyquist n = of(TransferFunction::parse(c.g), dense(1e4));
    EXPECT_EQ(n.count, c.count) << c.g;
    // The sampled half curve, 20000 points to 1e4 rad/s: within 0.01 of the count.
    EXPECT_NEAR(n.curve_encirclements, c.count, 0.01) << c.g;
  }
}

TEST(Nyquist, PointsAreTheLoopOnTheContour) {
  const TransferFunction g = TransferFunction::parse("(s+2)/(s^2+s+4)");
  const std::vector<double> w{0.0, 0.5, 1.0, 2.0, 10.0};
  const Nyquist n = of(g, w);
  ASSERT_EQ(n.contour.size(), w.size());
  for (size_t k = 0; k < w.size(); ++k) {
    EXPECT_EQ(n.contour[k], Complex(0.0, w[k]));  // no pole nearby: not indented
    EXPECT_EQ(n.response[k], g.evaluate(Complex(0.0, w[k])));
  }
}

TEST(Nyquist, IntegratorIsIndentedToTheRight) {
  const TransferFunction g = TransferFunction::parse("1/(s*(s+1))");
  const Nyquist n = of(g, {0.0, 5e-5, 1.0});
  EXPECT_NEAR(n.contour[0].real(), 1e-4, 1e-18);  // onto the circle of radius 1e-4, right of s = 0
  EXPECT_NEAR(std::abs(n.contour[1]), 1e-4, 1e-18);
  EXPECT_GT(n.contour[1].real(), 0.0);
  EXPECT_EQ(n.contour[2], Complex(0.0, 1.0));
  EXPECT_EQ(n.open_loop_unstable, 0);
  const TransferFunction cl = feedback(g);
  const Nyquist left = nyquist([&g](Complex x) { return g.evaluate(x); }, g.poles(), cl.poles(), {0.0, 1.0}, 0.0, 1e-4,
                               Indent::Left);
  EXPECT_EQ(left.open_loop_unstable, 1);  // the integrator inside the contour
  EXPECT_EQ(left.count, -1);
  EXPECT_LT(left.contour[0].real(), 0.0);
}

TEST(Nyquist, DiscreteLoopOnTheUnitCircle) {
  const double ts = 0.1;
  const TransferFunction g = TransferFunction::parse("1.5/(z*(z-0.5))", {}, ts);
  const std::vector<double> grid = logspace(1e-3, M_PI / ts, 4000);
  const Nyquist n = of(g, nyquist_frequencies(grid, ts));
  EXPECT_DOUBLE_EQ(std::arg(n.contour.back()), M_PI);  // up to Nyquist
  for (size_t k = 0; k < n.contour.size(); k += 97) EXPECT_NEAR(std::abs(n.contour[k]), 1.0, 1e-15);
  // z^2 - 0.5 z + 1.5: both roots outside the unit circle (|z|^2 = 1.5).
  EXPECT_EQ(n.closed_loop_unstable, 2);
  EXPECT_EQ(n.count, 2);
  EXPECT_NEAR(n.curve_encirclements, 2.0, 0.01);
}

TEST(Nyquist, Refusals) {
  const TransferFunction g = TransferFunction::parse("1/(s+1)");
  EXPECT_THROW(of(g, {}), InputError);
  EXPECT_THROW(of(g, {1.0, 0.5}), InputError);
  EXPECT_THROW(of(g, {-1.0, 0.5}), InputError);
  EXPECT_THROW(parse_indent("up"), InputError);
}

}  // namespace
}  // namespace dmbd::blocks
