#pragma once
// Certified enclosures of the roots of a polynomial with exact (double) coefficients,
// and the stability verdict they decide: every root is in a disc whose radius is a
// proven bound, so a verdict is never a guess (docs/analyze.md, "Certified verdicts").
#include <vector>

#include "dmbd/blocks/polynomial.hpp"

namespace dmbd::blocks {

// A connected group of discs that holds exactly size() roots of the polynomial,
// counted with multiplicity (Gershgorin's theorem on the Weierstrass matrix, below).
struct RootCluster {
  std::vector<Complex> centers;  // the refined approximations (doubles, exact)
  std::vector<double> radii;     // proven radii: every root is within one of the discs
  // The number of roots (and discs) in the cluster.
  int size() const { return static_cast<int>(centers.size()); }
};

// Where a cluster lies relative to the stability boundary (Re s = 0, |z| = 1).
enum class Side { Inside, Outside, Straddles };

// The roots of p (degree >= 1) in clusters. Method: the companion eigenvalues, refined
// together by Aberth's iteration with p evaluated in double-double arithmetic; then,
// with z_i the approximations and W_i = p(z_i) / (a_n prod_{j != i} (z_i - z_j)) (the
// Weierstrass corrections), p is the characteristic polynomial of diag(z) - 1 W', whose
// column Gershgorin discs |z - z_i| <= n |W_i| contain every root, a connected union of
// m discs exactly m of them. |p(z_i)| is bounded above by the double-double value plus
// a proven bound on its rounding error, the product below with its rounding: the radii
// are upper bounds. Exact zero coefficients a_0 = ... = a_{k-1} = 0 give a cluster of k
// roots at exactly 0 (radius 0).
std::vector<RootCluster> enclose_roots(const Polynomial& p);

// Inside: every disc strictly in Re s < 0 (|z| < 1); Outside: every disc strictly in
// Re s > 0 (|z| > 1); Straddles otherwise. The comparisons are exact (the rounding of
// |z| bounded).
Side side_of(const RootCluster& c, bool discrete);

// A root-at-x0 multiplicity that is exact: the number of trailing zero coefficients for
// x0 = 0, and for x0 = 1 how many times p(1) (and then the quotient's value at 1)
// sums to exactly zero (error-free summation). No tolerance: a polynomial whose root is
// 1 - 5e-7 has none.
int exact_roots_at(const Polynomial& p, double x0);
// p divided by (x - x0)^m (synthetic division; the remainders, zero or rounding-level
// by the caller's knowledge, are dropped).
Polynomial deflated(const Polynomial& p, double x0, int m);

}  // namespace dmbd::blocks
