#pragma once
// A complex Schur form M = U T U* with chosen eigenvalues moved to the leading diagonal
// positions: the invariant subspace of those eigenvalues is then spanned by the leading
// columns of U. What the Riccati solvers (riccati.cpp) take their stabilising solution from.
#include <functional>

#include "dmbd/blocks/schur_exponential.hpp"

namespace dmbd::blocks {

struct OrderedSchur {
  ComplexMatrix u;   // unitary
  ComplexMatrix t;   // upper triangular, the selected eigenvalues first
  int selected = 0;  // how many eigenvalues `first` selected (they lead T's diagonal)
};

// Eigen's ComplexSchur, then the selected eigenvalues moved up by swaps of adjacent
// diagonal entries (each a 2 x 2 unitary rotation, as LAPACK's ztrexc). Eigen has a Schur
// form but no reordering, which is why the swaps are written here. InputError when the
// Schur iteration does not converge or M is not finite.
OrderedSchur ordered_schur(const ComplexMatrix& m, const std::function<bool(Complex)>& first);

}  // namespace dmbd::blocks
