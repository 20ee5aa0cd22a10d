#pragma once
// The stability verdict of a transfer decided from its input exactly as given (its
// double coefficients, its factors, its matrices), by certified root and eigenvalue
// enclosures (root_enclosure.hpp): never by a tolerance on the roots (docs/analyze.md,
// "Certified verdicts").
#include <optional>
#include <vector>

#include "dmbd/blocks/polynomial.hpp"
#include "dmbd/blocks/root_enclosure.hpp"
#include "dmbd/blocks/state_space.hpp"
#include "dmbd/blocks/transfer_function.hpp"
#include "dmbd/blocks/zpk.hpp"

namespace dmbd::blocks {

// The verdict over the poles of several parts (polynomials, matrices), gathered:
// - a pole is on the boundary only structurally: exactly at s = 0 (z = 1) (a factor s,
//   z - 1, coefficients whose value there is exactly zero, a 1 x 1 block equal to 0 (1)),
//   or a factor whose roots lie on it exactly (a s^2 + c with a c > 0; z + 1;
//   a z^2 + b z + a with b^2 < 4 a^2);
// - every other pole is in a certified disc (enclose_roots, enclose_eigenvalues).
// Unstable: a disc group proven outside, or a boundary pole repeated. Undecided: some
// group's discs straddle the boundary (none proven outside). Marginal: simple boundary
// poles only. Stable: every group proven inside.
class VerdictBuilder {
 public:
  // Poles in s (discrete false) or in z (discrete true); nothing added yet.
  explicit VerdictBuilder(bool discrete) : discrete_(discrete) {}
  // The roots of p, `multiplicity` times.
  void add_polynomial(const Polynomial& p, int multiplicity = 1);
  // The eigenvalues of a dense block: a 1 x 1 block exactly; a companion matrix up to a
  // permutation and power-of-two scalings (what StateSpace::from_tf realises, balanced)
  // by its characteristic polynomial, formed exactly; any other by enclose_eigenvalues.
  void add_matrix(const Matrix& a);
  // Poles exactly at s = 0 (z = 1) so far.
  int at_boundary_point() const { return at_x0_; }
  // The verdict, `cancelled` of the poles at the boundary point not counted (cancelled
  // by zeros there, or hidden).
  Stability verdict(int cancelled = 0) const;

 private:
  void add_clusters(const std::vector<RootCluster>& clusters);
  bool discrete_;
  int at_x0_ = 0;
  bool outside_ = false, straddles_ = false, repeated_edge_ = false;
  std::vector<Polynomial> edge_factors_;  // monic factors with roots exactly on the boundary
};

// The verdict of the poles of den = prod factors^multiplicity, `cancelled` of its roots
// at the boundary point (s = 0, z = 1) cancelled against zeros there.
Stability certified_stability(const FactorList& den, bool discrete, int cancelled = 0);
// The transfer's poles (zeros at the boundary point cancel poles there, as Zpk::from_tf).
Stability certified_stability(const TransferFunction& g);

// The characteristic polynomial of a companion matrix up to a permutation of its states
// and power-of-two scalings (StateSpace::from_tf's realisation, balanced), formed
// exactly: one row r full, every other row one nonzero entry off the diagonal, those
// entries chaining every state from r (x_{k+1}' = s_k x_k). In that order the matrix is
// [a_0 .. a_{n-1}; subdiagonal s_1 .. s_{n-1}], whose characteristic polynomial is
// x^n - sum_k a_k (s_1 .. s_k) x^{n-1-k}: exact when every product s_1 .. s_k is a power
// of two. nullopt for any other matrix.
std::optional<Polynomial> companion_polynomial(const Matrix& a);

// Certified enclosures of the eigenvalues of a dense real matrix: with A V = V D from an
// eigensolver and X ~ V^-1, V^-1 A V = (XV)^-1 (X A V) = M + Delta, M = fl(X A V), where
// ||Delta||_inf is bounded from ||I - XV||_inf < 1/2 and the rounding bounds of the two
// products; the row Gershgorin discs of M widened by that bound contain the eigenvalues,
// a connected union of m of them exactly m. When XV is too far from I (a defective or
// nearly defective matrix) one cluster of infinite radius.
std::vector<RootCluster> enclose_eigenvalues(const Matrix& a);

}  // namespace dmbd::blocks
