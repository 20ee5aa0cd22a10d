#pragma once
// The inverse of a small symmetric positive definite S from its Cholesky factor.
#include <Eigen/Core>

namespace dmbd::wholebody {

// S⁻¹ from S = L Lᵀ (L in the lower triangle of `factor`, as Eigen's LLT keeps it):
// W = L⁻¹ by forward substitution a column at a time, then S⁻¹ = Wᵀ W entry by entry
// (W's columns below the diagonal are contiguous), mirrored. Written out because
// Eigen's LLT solve against the identity runs its blocked level-3 triangular path twice
// on these few rows (the tasks' 3 to 10, the floating base's 6): about 2.5x the
// instructions. W is workspace of S's size.
template <class Factor, class Work, class Inverse>
void spd_inverse_from_factor(const Factor& factor, Work& W, Inverse& inverse) {
  const Eigen::Index m = factor.rows();
  W.setZero();
  for (Eigen::Index j = 0; j < m; ++j) {
    W(j, j) = 1.0 / factor(j, j);
    for (Eigen::Index i = j + 1; i < m; ++i) {
      double sum = 0.0;
      for (Eigen::Index k = j; k < i; ++k) sum += factor(i, k) * W(k, j);
      W(i, j) = -sum / factor(i, i);
    }
  }
  for (Eigen::Index j = 0; j < m; ++j)
    for (Eigen::Index i = j; i < m; ++i) {
      const double v = W.col(i).tail(m - i).dot(W.col(j).tail(m - i));
      inverse(i, j) = v;
      inverse(j, i) = v;
    }
}

}  // namespace dmbd::wholebody
