// Certified root and eigenvalue enclosures and the verdicts they decide
// (root_enclosure.hpp, certified_stability.hpp). Golden values: roots placed by
// construction, the exact value of the coefficients at 1 (Python fractions).
#include <gtest/gtest.h>

#include <cmath>

#include "dmbd/blocks/certified_stability.hpp"
#include "dmbd/blocks/root_enclosure.hpp"
#include "dmbd/blocks/state_space.hpp"

namespace {

using namespace dmbd::blocks;

// Every true root lies in some disc, and the discs are small for simple roots.
TEST(RootEnclosure, DiscsHoldTheRootsAndAreTight) {
  // (x - 1/4)(x - 1/2)(x + 3): exact double coefficients, exact roots.
  const Polynomial p = Polynomial({0.375, -2.125, 2.25, 1.0});
  const auto clusters = enclose_roots(p);
  ASSERT_EQ(clusters.size(), 3u);
  for (double root : {0.25, 0.5, -3.0}) {
    bool held = false;
    for (const RootCluster& c : clusters)
      for (int k = 0; k < c.size(); ++k)
        held = held || std::abs(c.centers[static_cast<size_t>(k)] - root) <= c.radii[static_cast<size_t>(k)];
    EXPECT_TRUE(held) << root;
  }
  for (const RootCluster& c : clusters) EXPECT_LE(c.radii[0], 1e-14);
}

// A double root is one cluster of two.
TEST(RootEnclosure, ARepeatedRootIsOneClusterOfItsMultiplicity) {
  const auto clusters = enclose_roots(Polynomial({0.25, -1.0, 1.0}));  // (x - 1/2)^2
  ASSERT_EQ(clusters.size(), 1u);
  EXPECT_EQ(clusters[0].size(), 2);
  EXPECT_EQ(side_of(clusters[0], true), Side::Inside);
}

TEST(RootEnclosure, ExactRootsAtTheBoundaryPointHaveNoTolerance) {
  EXPECT_EQ(exact_roots_at(Polynomial({0.0, 0.0, 1.0, 2.0}), 0.0), 2);
  EXPECT_EQ(exact_roots_at(Polynomial({0.5, -1.5, 1.0}), 1.0), 1);  // (x - 1)(x - 1/2)
  // z^2 - 1.9999989999994998 z + 0.9999990000004998: the sum is 9.999778782798785e-13.
  EXPECT_EQ(exact_roots_at(Polynomial({0.9999990000004998, -1.9999989999994998, 1.0}), 1.0), 0);
}

// Issue 28 row 1b in the library: 5e-7 inside is stable; a factor on the circle by its
// form is marginal, repeated unstable; 5e-301 from the axis is undecided.
TEST(CertifiedStability, VerdictsFromCoefficientsAndFactors) {
  EXPECT_EQ(certified_stability({{Polynomial({0.9999990000004998, -1.9999989999994998, 1.0}), 1}}, true), Stability::Stable);
  EXPECT_EQ(certified_stability({{Polynomial({-1.0, 1.0}), 1}, {Polynomial({0.5, 1.0}), 1}}, false), Stability::Unstable);
  EXPECT_EQ(certified_stability({{Polynomial({1.0, 0.0, 1.0}), 1}, {Polynomial({1.0, 1.0}), 3}}, false), Stability::Marginal);
  EXPECT_EQ(certified_stability({{Polynomial({1.0, 0.0, 1.0}), 2}}, false), Stability::Unstable);
  EXPECT_EQ(certified_stability({{Polynomial({1.0, 1e-300, 1.0}), 1}}, false), Stability::Undecided);
  EXPECT_EQ(certified_stability({{Polynomial({0.0, 1.0}), 1}, {Polynomial({2.0, 1.0}), 1}}, false), Stability::Marginal);
  EXPECT_EQ(certified_stability({{Polynomial({0.0, 1.0}), 2}}, false), Stability::Unstable);
  EXPECT_EQ(certified_stability({{Polynomial({-1.0, 1.0}), 1}}, true, 1), Stability::Stable);  // cancelled
}

// A companion matrix (permuted, power-of-two scaled) gives its polynomial exactly; a
// general matrix's eigenvalues are enclosed.
TEST(CertifiedStability, MatricesByTheirStructure) {
  Matrix cycle(3, 3);
  cycle << 0, 0, 4, 0.5, 0, 0, 0, 2, 0;  // one entry per row: no full row, not a companion
  EXPECT_FALSE(companion_polynomial(cycle).has_value());
  Matrix comp(2, 2);
  comp << -3, -2, 1, 0;  // x^2 + 3 x + 2
  const auto p = companion_polynomial(comp);
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(*p, Polynomial({2.0, 3.0, 1.0}));
  Matrix scaled(2, 2);
  scaled << -3, -4, 0.5, 0;  // the same, states scaled by 2
  EXPECT_EQ(*companion_polynomial(scaled), Polynomial({2.0, 3.0, 1.0}));
  Matrix general(2, 2);
  general << -1, 2, -3, -1.5;
  const auto clusters = enclose_eigenvalues(general);
  int n = 0;
  for (const RootCluster& cl : clusters) {
    n += cl.size();
    EXPECT_EQ(side_of(cl, false), Side::Inside);
  }
  EXPECT_EQ(n, 2);
  VerdictBuilder v(false);
  v.add_matrix(general);
  v.add_matrix(Matrix::Zero(1, 1));  // an integrator, exactly
  EXPECT_EQ(v.verdict(), Stability::Marginal);
}

}  // namespace
