#pragma once
// The dynamically consistent pseudo-inverse and its null-space projector (Khatib 1987):
//   Λ = (J A⁻¹ Jᵀ)⁻¹, J̄ = A⁻¹ Jᵀ Λ, N = I − J̄ J.
// J̄ is the inverse of J weighted by the mass matrix (J J̄ = I for a J of full row rank);
// a torque Nᵀ τ₀ produces no acceleration of the task (J A⁻¹ Nᵀ = 0).
// Near a singularity Λ is formed from the eigen-decomposition of J A⁻¹ Jᵀ with
// eigenvalues below `threshold` times the largest left out (the rows the robot cannot
// move are dropped, not amplified). Away from one, Λ comes from a Cholesky factor of
// J A⁻¹ Jᵀ when its condition number is certified below 1/threshold (then no
// eigenvalue would be dropped and both ways give the same Λ): see compute_lambda() in
// projection.cpp. Allocation-free after construction.
#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace dmbd::wholebody {

class DynamicallyConsistentInverse {
 public:
  // null_space: form N (false when only Λ and J̄ are wanted, as for the lowest task).
  DynamicallyConsistentInverse(int task_dim, int nv, double threshold = 1e-9, bool null_space = true);

  // Factorises A (symmetric positive definite), then forms Λ, J̄ and N for J (m x nv).
  void compute(const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::MatrixXd>& J);
  // The same with A already factorised (one factor shared by several tasks per tick);
  // `A_factor` must outlive the use of solve_A().
  void compute(const Eigen::LLT<Eigen::MatrixXd>& A_factor, const Eigen::Ref<const Eigen::MatrixXd>& J);
  // The same for a diagonal A = diag(l)², given its Cholesky factor's diagonal l > 0 (the
  // prioritised IK's weights): A⁻¹Jᵀ by scaling rows, no triangular solves, the same
  // arithmetic as the factored path to the bit. `A_sqrt` must outlive the use of solve_A().
  void compute_diagonal(const Eigen::VectorXd& A_sqrt, const Eigen::Ref<const Eigen::MatrixXd>& J);

  const Eigen::MatrixXd& A_inv_Jt() const { return AinvJt_; }   // A⁻¹ Jᵀ (nv x m)
  const Eigen::MatrixXd& Lambda() const { return Lambda_; }     // m x m
  const Eigen::MatrixXd& Jbar() const { return Jbar_; }         // nv x m
  const Eigen::MatrixXd& N() const { return N_; }               // nv x nv (empty without null_space)
  int rank() const { return rank_; }                            // eigenvalues kept
  bool used_eigen() const { return used_eigen_; }               // Λ by eigen-decomposition
  // x = A⁻¹ y, with the factorisation of the last compute().
  void solve_A(const Eigen::Ref<const Eigen::VectorXd>& y, Eigen::Ref<Eigen::VectorXd> x) const;

 private:
  void finish(const Eigen::Ref<const Eigen::MatrixXd>& J);  // Λ, J̄ and N from AinvJt_
  void compute_lambda();  // Λ from JAJt_ (which it overwrites)
  bool lambda_by_cholesky();
  void lambda_by_eigen();

  double threshold_;
  bool null_space_;
  Eigen::LLT<Eigen::MatrixXd> llt_, task_llt_;
  const Eigen::LLT<Eigen::MatrixXd>* factor_ = &llt_;  // A's factor of the last compute()
  const Eigen::VectorXd* diagonal_factor_ = nullptr;    // or its diagonal (compute_diagonal)
  Eigen::MatrixXd AinvJt_, JAJt_, Lambda_, VD_, Jbar_, N_;
  Eigen::VectorXd inv_eigen_;
  int rank_ = 0;
  bool used_eigen_ = false;
};

}  // namespace dmbd::wholebody
