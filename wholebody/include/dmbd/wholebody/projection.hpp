#pragma once
// The dynamically consistent pseudo-inverse and its null-space projector (Khatib 1987):
//   Λ = (J A⁻¹ Jᵀ)⁻¹, J̄ = A⁻¹ Jᵀ Λ, N = I − J̄ J.
// J̄ is the inverse of J weighted by the mass matrix (J J̄ = I for a J of full row rank);
// a torque Nᵀ τ₀ produces no acceleration of the task (J A⁻¹ Nᵀ = 0).
// Near a singularity Λ is formed from the eigen-decomposition of J A⁻¹ Jᵀ with
// eigenvalues below `threshold` times the largest left out (the rows the robot cannot
// move are dropped, not amplified). Allocation-free after construction.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>

namespace dmbd::wholebody {

class DynamicallyConsistentInverse {
 public:
  DynamicallyConsistentInverse(int task_dim, int nv, double threshold = 1e-9);

  // Factorises A (symmetric positive definite), then forms Λ, J̄ and N for J (m x nv).
  void compute(const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::MatrixXd>& J);

  const Eigen::MatrixXd& A_inv_Jt() const { return AinvJt_; }   // A⁻¹ Jᵀ (nv x m)
  const Eigen::MatrixXd& Lambda() const { return Lambda_; }     // m x m
  const Eigen::MatrixXd& Jbar() const { return Jbar_; }         // nv x m
  const Eigen::MatrixXd& N() const { return N_; }               // nv x nv
  int rank() const { return rank_; }                            // eigenvalues kept
  // x = A⁻¹ y, with the factorisation of the last compute().
  void solve_A(const Eigen::Ref<const Eigen::VectorXd>& y, Eigen::Ref<Eigen::VectorXd> x) const;

 private:
  double threshold_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig_;
  Eigen::MatrixXd AinvJt_, JAJt_, Lambda_, VD_, Jbar_, N_;
  Eigen::VectorXd inv_eigen_;
  int rank_ = 0;
};

}  // namespace dmbd::wholebody
