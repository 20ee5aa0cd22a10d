#pragma once
// State feedback by pole placement (python-control's and MATLAB's place).
#include <vector>

#include "dmbd/blocks/state_space.hpp"

namespace dmbd::blocks {

// The gain of u = -K x that gives A - B K the eigenvalues `poles`, and what it achieved.
struct PolePlacement {
  Matrix k;                        // m x n
  std::vector<Complex> achieved;   // the eigenvalues of A - B K, sorted as sort_roots
  double eigenvector_condition;    // 2-norm condition number of A - BK's eigenvector matrix (their sensitivity)
  int sweeps;                      // sweeps of the eigenvector update (0 with one input)
};

// One input (m = 1): the gain is unique, and it is found by deflation with unitary
// transformations (pole_placement.cpp: each pole's closed-loop eigenvector from a null
// space, the pole split off, the same problem one order smaller), in the spirit of
// Miminis and Paige (Int. J. Control 35, 1982) and Petkov, Christov and Konstantinov
// (IEEE TAC 29, 1984). No controllability matrix is formed: Ackermann's formula inverts
// it, and its condition grows exponentially with the order (measured, docs/python.md: a
// 10th-order chain of integrators gets its exact integer gain to 1.3e-11 here, 3e-8 by
// SciPy's place_poles; on random systems the placed poles' median error is 2 times
// smaller than Ackermann's and SciPy's at order 10, 6 and 2.5 times at order 14). Poles
// may repeat.
//
// Several inputs: the gain is not unique; Kautsky, Nichols and Van Dooren's robust method
// ("method 0", Int. J. Control 41, 1985) in complex arithmetic: B = [U0 U1] [Z; 0] (QR);
// each pole p_j may have an eigenvector x_j in S_j, the null space of U1'(A - p_j I)
// (m dimensions); the x_j are chosen, one at a time over repeated sweeps, as the unit
// vector of S_j most orthogonal to the others, which makes X = [x_1 ... x_n] well
// conditioned (the placed poles as insensitive as the sweeps can make them); then
// K = Z^-1 U0'(A - X diag(p) X^-1). A real pole gets a real x_j, a complex pair conjugate
// vectors, so K is real. Like SciPy's place_poles (which python-control's place calls),
// a pole may repeat at most rank B times.
//
// InputError for inconsistent sizes, entries that are not finite, the wrong number of
// poles, complex poles without their conjugate (relative 1e-10), B without full column
// rank, (A, B) not controllable, or (several inputs) a pole repeated more than rank B times.
PolePlacement place(const Matrix& a, const Matrix& b, const std::vector<Complex>& poles);

}  // namespace dmbd::blocks
