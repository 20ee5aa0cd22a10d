// The dynamically consistent pseudo-inverse and null-space projector (projection.hpp).
#include "dmbd/wholebody/projection.hpp"

#include <cassert>

namespace dmbd::wholebody {

DynamicallyConsistentInverse::DynamicallyConsistentInverse(int task_dim, int nv, double threshold)
    : threshold_(threshold),
      llt_(nv),
      eig_(task_dim),
      AinvJt_(nv, task_dim),
      JAJt_(task_dim, task_dim),
      Lambda_(task_dim, task_dim),
      VD_(task_dim, task_dim),
      Jbar_(nv, task_dim),
      N_(nv, nv),
      inv_eigen_(task_dim) {}

void DynamicallyConsistentInverse::compute(const Eigen::Ref<const Eigen::MatrixXd>& A,
                                           const Eigen::Ref<const Eigen::MatrixXd>& J) {
  assert(A.rows() == N_.rows() && J.rows() == JAJt_.rows() && J.cols() == A.cols());
  llt_.compute(A);
  AinvJt_ = J.transpose();
  llt_.solveInPlace(AinvJt_);
  JAJt_.noalias() = J * AinvJt_;
  // Λ = (J A⁻¹ Jᵀ)⁻¹ on the eigenvalues above threshold · the largest (a pseudo-inverse
  // at a singular configuration).
  eig_.compute(JAJt_);
  const Eigen::VectorXd& lambda = eig_.eigenvalues();  // ascending
  const double cut = threshold_ * std::max(lambda[lambda.size() - 1], 0.0);
  rank_ = 0;
  for (Eigen::Index k = 0; k < lambda.size(); ++k) {
    const bool keep = lambda[k] > cut && lambda[k] > 0.0;
    inv_eigen_[k] = keep ? 1.0 / lambda[k] : 0.0;
    rank_ += keep ? 1 : 0;
  }
  const auto& V = eig_.eigenvectors();
  VD_.noalias() = V * inv_eigen_.asDiagonal();
  Lambda_.noalias() = VD_ * V.transpose();
  Jbar_.noalias() = AinvJt_ * Lambda_;
  N_.setIdentity();
  N_.noalias() -= Jbar_ * J;
}

void DynamicallyConsistentInverse::solve_A(const Eigen::Ref<const Eigen::VectorXd>& y,
                                           Eigen::Ref<Eigen::VectorXd> x) const {
  x = y;
  llt_.solveInPlace(x);
}

}  // namespace dmbd::wholebody
