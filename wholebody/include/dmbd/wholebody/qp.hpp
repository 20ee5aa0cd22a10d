#pragma once
// A dense convex quadratic program, solved by the Goldfarb–Idnani dual active-set method
// (D. Goldfarb, A. Idnani, "A numerically stable dual method for solving strictly
// convex quadratic programs", Math. Programming 27, 1983):
//
//   minimise ½ xᵀ G x + aᵀ x   subject to   C_eq x = b_eq,   C_in x ≥ b_in,
//
// G symmetric positive definite (n x n), C_eq (m_eq x n), C_in (m_in x n).
// Written by hand: Debian packages no small dense QP solver that runs without
// allocating per solve (eiquadprog, qpOASES, OSQP and quadprog are not in Debian 12;
// the whole-body controller solves one such problem every millisecond, issue 15).
//
// The method starts from the unconstrained minimum, adds the equalities, then adds the
// most violated inequality at a time, dropping active ones whose multipliers would turn
// negative; the factorisation J = L⁻ᵀ Q and the triangular R are kept up to date (a
// Householder reflection when a constraint enters, Givens rotations when one leaves).
// Storage is sized by the constructor; solve() allocates nothing.
#include <Eigen/Core>

namespace dmbd::wholebody {

enum class QpStatus {
  Optimal,
  Infeasible,          // the constraints cannot all hold (or the equalities are dependent)
  NotPositiveDefinite, // G is not symmetric positive definite
  IterationLimit,      // more active-set changes than allowed (a safeguard; not expected)
};

const char* to_string(QpStatus s);

class QpSolver {
 public:
  QpSolver(int n, int m_eq, int m_in);

  // Solves the problem; on Optimal, x() is the minimiser and the multipliers satisfy
  // G x + a = C_eqᵀ λ + C_inᵀ μ, μ ≥ 0, μ_i (C_in x − b_in)_i = 0.
  QpStatus solve(const Eigen::Ref<const Eigen::MatrixXd>& G, const Eigen::Ref<const Eigen::VectorXd>& a,
                 const Eigen::Ref<const Eigen::MatrixXd>& C_eq, const Eigen::Ref<const Eigen::VectorXd>& b_eq,
                 const Eigen::Ref<const Eigen::MatrixXd>& C_in, const Eigen::Ref<const Eigen::VectorXd>& b_in);

  const Eigen::VectorXd& x() const { return x_; }
  const Eigen::VectorXd& lambda_eq() const { return lambda_eq_; }  // m_eq
  const Eigen::VectorXd& mu_in() const { return mu_in_; }          // m_in, 0 for inactive
  double objective() const { return f_; }
  int iterations() const { return iterations_; }
  int active_inequalities() const;

  // Warm start, for a sequence of similar problems (a controller's ticks): solve() first
  // makes the inequalities active at the last Optimal solve hold with equality, in their
  // order, as the equalities are; when their multipliers come out ≥ 0 that is a state
  // of the dual method (the minimum on those constraints, dual feasible) and the method
  // goes on from it, adding what is still violated; otherwise it starts again from the
  // unconstrained minimum. When those constraints are exactly the active ones, the
  // minimum on them is found directly and checked (solved_directly()). The problem
  // being strictly convex, the answer is the same minimiser either way (to rounding).
  // Off by default.
  void set_warm_start(bool on);
  // Whether the last solve went on from the previous active set (false: started cold).
  bool warm_started() const { return warm_used_; }
  // Whether it did so by the short cut: the optimality conditions on the previous active
  // set solved directly, which certified the minimiser (nothing left to add or drop), so
  // the dual method's own factorisation was never formed.
  bool solved_directly() const { return direct_; }

 private:
  void start(const Eigen::Ref<const Eigen::VectorXd>& a, bool diagonal);
  bool solve_on_previous(const Eigen::Ref<const Eigen::VectorXd>& a, const Eigen::Ref<const Eigen::VectorXd>& b_eq,
                         const Eigen::Ref<const Eigen::VectorXd>& b_in);  // warm start's short cut
  void solve_upper_transposed(Eigen::Ref<Eigen::VectorXd> v) const;  // Uᵀ y = v
  void solve_upper(Eigen::Ref<Eigen::VectorXd> v) const;             // U x = v
  bool start_diagonal(const Eigen::Ref<const Eigen::MatrixXd>& G);  // G diagonal
  bool factor(const Eigen::Ref<const Eigen::MatrixXd>& G);  // G = Uᵀ U into U_
  void invert_upper_factor();  // J = U⁻¹
  bool add_equalities(const Eigen::Ref<const Eigen::VectorXd>& b_eq);
  QpStatus add_inequalities(const Eigen::Ref<const Eigen::VectorXd>& b_in);
  bool add_previous(const Eigen::Ref<const Eigen::VectorXd>& b_in);  // warm start; false: start cold
  void restart();                                      // back to start()'s state (saved)
  void remember_active_set(QpStatus status);
  int most_violated(const Eigen::Ref<const Eigen::VectorXd>& b_in, double& slack);
  // Working-set constraint k: k < m_eq the equality k, else the inequality k − m_eq.
  Eigen::Ref<const Eigen::VectorXd> normal(int k) const;
  void step_directions(const Eigen::Ref<const Eigen::VectorXd>& n);  // d, z, r for normal n
  void reflect_columns(int q, double tau);  // J's columns q.. times the Householder reflection in d_
  double partial_step(int& position) const;  // the dual step limit over active inequalities
  bool add_to_working_set(int k);            // with d_ of its normal; false if dependent
  void drop_from_working_set(int position);
  void finish(const Eigen::Ref<const Eigen::MatrixXd>& G, const Eigen::Ref<const Eigen::VectorXd>& a);

  int n_, m_eq_, m_in_;
  Eigen::MatrixXd CeqT_, CinT_;       // constraint normals as columns
  Eigen::MatrixXd U_;                 // G's Cholesky factor (upper)
  Eigen::MatrixXd L_;                 // Uᵀ, as factored (its strict upper triangle: G's)
  Eigen::VectorXd inv_diag_;          // 1 / U's diagonal
  Eigen::MatrixXd J_, R_;
  Eigen::VectorXd x_, d_, z_, r_, u_, lambda_eq_, mu_in_, Gx_;
  Eigen::VectorXd norm_in_;           // ‖C_in row i‖ of this solve
  Eigen::VectorXd slack_in_;          // C_in x − b_in (most_violated)
  Eigen::VectorXd house_;             // reflect_columns' workspace (n)
  Eigen::VectorXi working_;           // constraint index (as in normal()) per position
  Eigen::VectorXi previous_;          // the last Optimal solve's active inequalities, in order
  int previous_count_ = 0;
  bool warm_ = false, warm_used_ = false, direct_ = false;
  Eigen::MatrixXd J_start_;           // J and x after start(), kept for a restart
  Eigen::VectorXd x_start_;
  Eigen::MatrixXd Y_, S_;             // solve_on_previous: U⁻ᵀ C_Aᵀ and the factor of YᵀY
  Eigen::VectorXd y0_;                // solve_on_previous: −U⁻ᵀ a
  Eigen::Matrix<bool, Eigen::Dynamic, 1> is_active_;  // per inequality
  double f_ = 0;
  int q_ = 0;                         // working-set size
  int iterations_ = 0;
};

}  // namespace dmbd::wholebody
