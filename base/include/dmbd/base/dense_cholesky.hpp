#pragma once
// A dense symmetric positive definite solve, A x = b, by the Cholesky factor A = L Lᵀ in
// place: the plant's step matrix (model/, tens of coordinates) and the whole-body QP's
// Hessian (wholebody/, 16 variables on DRACO). Written by hand because Eigen's LLT and
// triangular solves on these sizes run their blocked, panel-splitting paths: 29.3 k
// instructions a step for DRACO's 26 coordinates against 3 k multiply-adds of
// arithmetic. Every inner loop is a multiply-add over a contiguous column (left-looking
// factorisation, column-oriented solves), which the compiler vectorises (with an AVX2
// clone: vector_clones.hpp). Column-major storage with leading dimension lda; plain
// pointers, so that base/ needs no Eigen.
#include <cstddef>

namespace dmbd::base {

// Overwrites the lower triangle (diagonal included) of the n x n matrix at a with L and
// inv_diag[0, n) with 1 / L's diagonal; the strict upper triangle is neither read nor
// written. False when a pivot is not positive and finite (A not positive definite to
// rounding), as Eigen's LLT fails.
bool cholesky_in_place(double* a, std::ptrdiff_t lda, std::ptrdiff_t n, double* inv_diag);

// b := (L Lᵀ)⁻¹ b with L and inv_diag from cholesky_in_place.
void cholesky_solve_in_place(const double* l, std::ptrdiff_t lda, std::ptrdiff_t n, const double* inv_diag, double* b);

}  // namespace dmbd::base
