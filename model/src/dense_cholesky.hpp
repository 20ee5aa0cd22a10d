#pragma once
// A dense symmetric positive definite solve, A x = b, by the Cholesky factor A = L Lᵀ
// in place, for the plant's step matrix (tens of coordinates). Written by hand because
// Eigen's LLT and triangular solves on these sizes run their blocked, panel-splitting
// paths: 29.3 k instructions a step for DRACO's 26 coordinates against 3 k
// multiply-adds of arithmetic. Here every inner loop is a multiply-add over a
// contiguous column (left-looking factorisation, column-oriented solves), which the
// compiler vectorises (with an AVX2 clone: dmbd/base/vector_clones.hpp). Private to model/.
#include <Eigen/Core>

namespace dmbd::model::detail {

// Overwrites A's lower triangle (diagonal included) with L and inv_diag (sized by the
// caller) with 1 / L's diagonal; the upper triangle is read as A's (not referenced).
// False when a pivot is not positive and finite (A not positive definite to rounding),
// as Eigen's LLT fails.
bool cholesky_in_place(Eigen::MatrixXd& A, Eigen::VectorXd& inv_diag);

// b := (L Lᵀ)⁻¹ b with L and inv_diag from cholesky_in_place.
void cholesky_solve_in_place(const Eigen::MatrixXd& L, const Eigen::VectorXd& inv_diag, Eigen::Ref<Eigen::VectorXd> b);

}  // namespace dmbd::model::detail
