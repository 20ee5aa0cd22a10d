// The dynamically consistent pseudo-inverse and null-space projector (projection.hpp).
#include "dmbd/wholebody/projection.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include <Eigen/Jacobi>

#include "spd_inverse.hpp"

namespace dmbd::wholebody {

namespace {

// Eigen-decomposition of the symmetric S by cyclic Jacobi rotations, in place: S ends
// diagonal (its diagonal the eigenvalues, unordered) and V holds the eigenvectors
// (S_in = V diag(S) Vᵀ). Allocation-free, unlike SelfAdjointEigenSolver<MatrixXd>, whose
// eigenvector extraction (Householder sequence) allocates a workspace on every call
// (Eigen 3.4). Rotations stop when every off-diagonal entry is below 2ε of the largest
// diagonal one (JacobiSVD's criterion); convergence is quadratic: a few sweeps for the
// small task dimensions here.
void jacobi_eigen(Eigen::MatrixXd& S, Eigen::MatrixXd& V) {
  const Eigen::Index m = S.rows();
  V.setIdentity();
  constexpr int kMaxSweeps = 100;
  const double tiny = std::numeric_limits<double>::min();
  const double precision = 2.0 * std::numeric_limits<double>::epsilon();
  for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
    const double limit = std::max(tiny, precision * S.diagonal().cwiseAbs().maxCoeff());
    bool rotated = false;
    for (Eigen::Index p = 0; p < m; ++p)
      for (Eigen::Index q = p + 1; q < m; ++q) {
        if (std::abs(S(p, q)) <= limit) continue;
        Eigen::JacobiRotation<double> j;
        j.makeJacobi(S, p, q);
        S.applyOnTheLeft(p, q, j.adjoint());
        S.applyOnTheRight(p, q, j);
        V.applyOnTheRight(p, q, j);
        rotated = true;
      }
    if (!rotated) return;
  }
}

}  // namespace

DynamicallyConsistentInverse::DynamicallyConsistentInverse(int task_dim, int nv, double threshold, bool null_space)
    : threshold_(threshold),
      null_space_(null_space),
      llt_(nv),
      task_llt_(task_dim),
      AinvJt_(nv, task_dim),
      JAJt_(task_dim, task_dim),
      Lambda_(task_dim, task_dim),
      VD_(task_dim, task_dim),
      Jbar_(nv, task_dim),
      N_(null_space ? nv : 0, null_space ? nv : 0),
      inv_eigen_(task_dim) {}

void DynamicallyConsistentInverse::compute(const Eigen::Ref<const Eigen::MatrixXd>& A,
                                           const Eigen::Ref<const Eigen::MatrixXd>& J) {
  assert(A.rows() == AinvJt_.rows());
  llt_.compute(A);
  compute(llt_, J);
}

void DynamicallyConsistentInverse::compute(const Eigen::LLT<Eigen::MatrixXd>& A_factor,
                                           const Eigen::Ref<const Eigen::MatrixXd>& J) {
  assert(A_factor.rows() == AinvJt_.rows() && J.rows() == JAJt_.rows() && J.cols() == AinvJt_.rows());
  factor_ = &A_factor;
  diagonal_factor_ = nullptr;
  AinvJt_ = J.transpose();
  A_factor.solveInPlace(AinvJt_);
  finish(J);
}

// A = L Lᵀ with L = diag(l): A⁻¹Jᵀ = L⁻ᵀ L⁻¹ Jᵀ, row i of Jᵀ times 1/l_i twice, as
// Eigen's triangular matrix solves do (a product with the diagonal's reciprocal).
void DynamicallyConsistentInverse::compute_diagonal(const Eigen::VectorXd& A_sqrt, const Eigen::Ref<const Eigen::MatrixXd>& J) {
  assert(A_sqrt.size() == AinvJt_.rows() && J.rows() == JAJt_.rows() && J.cols() == AinvJt_.rows());
  diagonal_factor_ = &A_sqrt;
  AinvJt_ = J.transpose();
  for (Eigen::Index i = 0; i < AinvJt_.rows(); ++i) {
    const double r = 1.0 / A_sqrt[i];
    AinvJt_.row(i) *= r;
    AinvJt_.row(i) *= r;
  }
  finish(J);
}

// Λ, J̄ = A⁻¹JᵀΛ and N = I − J̄J, with A⁻¹Jᵀ in AinvJt_.
// The products are coefficient by coefficient (lazyProduct): on these sizes (nv x m, m
// ≤ nv, nv 16 on DRACO) Eigen's blocked product spends more on packing its panels than
// on the arithmetic.
void DynamicallyConsistentInverse::finish(const Eigen::Ref<const Eigen::MatrixXd>& J) {
  JAJt_.noalias() = J.lazyProduct(AinvJt_);
  compute_lambda();
  Jbar_.noalias() = AinvJt_.lazyProduct(Lambda_);
  if (!null_space_) return;
  N_.setIdentity();
  N_.noalias() -= Jbar_.lazyProduct(J);
}

// Λ = (J A⁻¹ Jᵀ)⁻¹ when J A⁻¹ Jᵀ is certainly well conditioned, else its truncated
// pseudo-inverse on the eigenvalues above threshold · the largest.
void DynamicallyConsistentInverse::compute_lambda() {
  used_eigen_ = false;
  if (JAJt_.rows() == 0) {
    rank_ = 0;
    return;
  }
  if (lambda_by_cholesky()) return;
  used_eigen_ = true;
  lambda_by_eigen();
}

// The certificate: for S symmetric positive definite, λ_max(S) ≤ ‖S‖_F and
// 1/λ_min(S) = ‖S⁻¹‖₂ ≤ ‖S⁻¹‖_F, so κ₂(S) ≤ ‖S‖_F ‖S⁻¹‖_F. When that bound is below
// 1/threshold no eigenvalue is at or below threshold · λ_max: the truncated
// pseudo-inverse is the inverse, and the Cholesky factor gives it (a tenth of the
// eigen-decomposition's cost for the posture's 10 rows).
bool DynamicallyConsistentInverse::lambda_by_cholesky() {
  task_llt_.compute(JAJt_);
  if (task_llt_.info() != Eigen::Success) return false;
  spd_inverse_from_factor(task_llt_.matrixLLT(), VD_, Lambda_);  // VD_: free until lambda_by_eigen
  const double bound = JAJt_.norm() * Lambda_.norm();
  if (!(bound * threshold_ < 1.0)) return false;
  rank_ = static_cast<int>(JAJt_.rows());
  return true;
}

// J A⁻¹ Jᵀ = V diag(λ) Vᵀ, decomposed in place: JAJt_ ends diagonal, V is held in VD_;
// JAJt_ is then reused for V diag(1/λ).
void DynamicallyConsistentInverse::lambda_by_eigen() {
  Eigen::MatrixXd& V = VD_;
  jacobi_eigen(JAJt_, V);
  const auto lambda = JAJt_.diagonal();
  const double cut = threshold_ * std::max(lambda.maxCoeff(), 0.0);
  rank_ = 0;
  for (Eigen::Index k = 0; k < lambda.size(); ++k) {
    const bool keep = lambda[k] > cut && lambda[k] > 0.0;
    inv_eigen_[k] = keep ? 1.0 / lambda[k] : 0.0;
    rank_ += keep ? 1 : 0;
  }
  JAJt_.noalias() = V * inv_eigen_.asDiagonal();
  Lambda_.noalias() = JAJt_ * V.transpose();
}

void DynamicallyConsistentInverse::solve_A(const Eigen::Ref<const Eigen::VectorXd>& y,
                                           Eigen::Ref<Eigen::VectorXd> x) const {
  x = y;
  if (diagonal_factor_) {  // as the factored path's vector solves: two divisions
    x.array() /= diagonal_factor_->array();
    x.array() /= diagonal_factor_->array();
    return;
  }
  factor_->solveInPlace(x);
}

}  // namespace dmbd::wholebody
