#include "ordered_schur.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "dmbd/base/error.hpp"

namespace dmbd::blocks {

namespace {

// Exchanges the diagonal entries j and j + 1 of the upper triangular t, keeping
// M = U T U*: the rotation's first column is the eigenvector of the 2 x 2 block
// [t11 t12; 0 t22] for t22, so that the rotated block is [t22 x; 0 t11].
void swap_adjacent(ComplexMatrix& t, ComplexMatrix& u, Eigen::Index j) {
  const Complex t11 = t(j, j), t22 = t(j + 1, j + 1);
  Eigen::Vector2cd v(t(j, j + 1), t22 - t11);
  const double norm = v.norm();
  if (norm == 0.0) return;  // equal eigenvalues, no coupling: nothing to exchange
  v /= norm;
  Eigen::Matrix2cd g;
  g << v(0), -std::conj(v(1)), v(1), std::conj(v(0));
  t.middleRows(j, 2) = (g.adjoint() * t.middleRows(j, 2)).eval();
  t.middleCols(j, 2) = (t.middleCols(j, 2) * g).eval();
  u.middleCols(j, 2) = (u.middleCols(j, 2) * g).eval();
  t(j + 1, j) = 0.0;
  t(j, j) = t22;
  t(j + 1, j + 1) = t11;
}

}  // namespace

OrderedSchur ordered_schur(const ComplexMatrix& m, const std::function<bool(Complex)>& first) {
  if (!m.allFinite()) throw InputError("the matrix to be put in Schur form has entries that are not finite");
  const Eigen::ComplexSchur<ComplexMatrix> schur(m);
  if (schur.info() != Eigen::Success) throw InputError("the Schur iteration did not converge");
  OrderedSchur out{schur.matrixU(), schur.matrixT(), 0};
  // Selected eigenvalues bubble up, one at a time, to just below those already placed.
  for (Eigen::Index k = 0; k < out.t.rows(); ++k) {
    if (!first(out.t(k, k))) continue;
    for (Eigen::Index j = k - 1; j >= out.selected; --j) swap_adjacent(out.t, out.u, j);
    ++out.selected;
  }
  return out;
}

}  // namespace dmbd::blocks
