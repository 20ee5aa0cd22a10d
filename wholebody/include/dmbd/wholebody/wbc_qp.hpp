#pragma once
// The dynamic layer of the paper's whole-body control (Sec. IV-B; Kim et al. 2019): a
// QP that corrects the accelerations the prioritised IK asks for (q̈_cmd) so that the
// floating base's equations of motion hold with reaction forces the contacts can give.
// One point contact per foot (3 force components each), a fixed problem size (a foot in
// the air keeps its variables with F_max = 0 and a small slack weight, as the authors'
// controller blends them in lift and landing).
//
//   variables  z = [Δq̈ (nv), F (3 n_c), s (3 n_c)]
//   minimise   w_q‖Δq̈‖² + Σ_c (w_t,c (F_x² + F_y²) + w_n,c F_z² + w_s,c ‖s_c‖²)
//   subject to S_b [A (q̈_cmd + Δq̈) + b + g − J_cᵀ F] = 0           (floating-base rows)
//              J_c (q̈_cmd + Δq̈) + J̇_c v = s                          (contact accelerations)
//              0 ≤ F_z ≤ F_max,c,  |F_x|, |F_y| ≤ μ F_z              (friction pyramid)
//              |τ_j| ≤ τ_max,j,  τ = S_a [A (q̈_cmd + Δq̈) + b + g − J_cᵀ F]
//
// Forces are in world axes, the normal along +z (flat ground). Output: τ per joint
// (Layout::joints order), the corrected q̈ and the forces. Allocation-free after
// construction; the QP is wholebody::QpSolver.
//
// Solved in reduced variables y = [Δq̈_j (n_j), F (3 n_c)], the same problem without its
// equalities: the floating-base rows give the base's Δq̈_b = P y + p₀ (A_bb, the robot's
// composite inertia at the base, is positive definite), and each slack is the contact's
// acceleration, s = K y + k. Substituted into the cost and the torque rows, they leave a
// dense (n_j + 3 n_c)-variable QP with inequalities only: a third of the variables and no
// equality phase (the solver's largest cost in the full form, issue 27).
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "dmbd/wholebody/qp.hpp"
#include "dmbd/wholebody/robot_model.hpp"

namespace dmbd::wholebody {

// One contact's bound and weights (the phase machine's blend of stance and swing).
struct ContactSetting {
  double f_max_N = 550.0;
  double w_tangential = 1.0;
  double w_normal = 0.01;
  double w_slack = 1000.0;
};

struct WbcQpParams {
  double mu = 0.3;                   // friction coefficient of the pyramid
  double w_qdd = 100.0;              // weight on Δq̈
  // Weight on the floating base's translational Δq̈ (v indices 3–5; < 0: w_qdd, the
  // authors'). Lower lets the base accelerate as the contacts and gravity make it rather
  // than the joints giving way. Not 0 (the cost would not be positive definite); the
  // constructor throws InputError for 0 or a value that is not finite.
  double w_qdd_base = -1.0;
  double torque_limit_Nm = 100.0;    // |τ_j| bound, all joints (the authors' ±100 N m), or the
                                     // joint's own effort limit (Layout) where that is lower
  // Each solve starts from the last tick's active constraints (QpSolver::set_warm_start):
  // the same minimiser to rounding, in fewer active-set changes while the contacts and
  // limits that bind stay the same from tick to tick.
  bool warm_start = true;
};

class WbcQp {
 public:
  // A floating-base layout (base_dofs 6); num_contacts point contacts.
  WbcQp(const Layout& layout, int num_contacts, const WbcQpParams& params = {});

  // J_c: 3 n_c x nv (contact points' linear Jacobians, stacked), Jc_dot_v: 3 n_c.
  QpStatus solve(const ModelData& data, const Eigen::Ref<const Eigen::MatrixXd>& J_c,
                 const Eigen::Ref<const Eigen::VectorXd>& Jc_dot_v, const Eigen::Ref<const Eigen::VectorXd>& qdd_cmd,
                 const ContactSetting* contacts);

  const Eigen::VectorXd& tau() const { return tau_; }        // per joint
  const Eigen::VectorXd& qdd() const { return qdd_; }        // q̈_cmd + Δq̈
  const Eigen::VectorXd& forces() const { return forces_; }  // 3 n_c, world
  const QpSolver& qp() const { return qp_; }

 private:
  bool reduce(const ModelData& data, const Eigen::Ref<const Eigen::MatrixXd>& J_c,
              const Eigen::Ref<const Eigen::VectorXd>& Jc_dot_v, const Eigen::Ref<const Eigen::VectorXd>& qdd_cmd);
  void build_cost(const ContactSetting* contacts);
  void build_inequalities(const ModelData& data, const Eigen::Ref<const Eigen::MatrixXd>& J_c, const ContactSetting* contacts);
  void recover(const Eigen::Ref<const Eigen::VectorXd>& qdd_cmd);
  void torques_of(const ModelData& data, const Eigen::Ref<const Eigen::MatrixXd>& J_c);

  int nv_, nj_, nc_, n_;   // n_: the reduced variables, n_j + 3 n_c
  WbcQpParams params_;
  QpSolver qp_;
  Eigen::LLT<Eigen::Matrix<double, 6, 6>> base_inertia_;  // A_bb
  Eigen::Matrix<double, 6, Eigen::Dynamic> P_;            // Δq̈_b = P y + p₀
  Eigen::Matrix<double, 6, Eigen::Dynamic> base_rhs_;     // [−A_bj, J_c,bᵀ], P's right-hand side
  Eigen::Matrix<double, 6, 1> p0_;
  Eigen::MatrixXd K_;      // slack s = K y + k (3 n_c x n)
  Eigen::VectorXd k_;
  Eigen::MatrixXd B_;      // the weighted residual rows [√W_b P; √W_s K] (6 + 3 n_c x n)
  Eigen::VectorXd beta_;   // and their constants [√W_b p₀; √W_s k]
  Eigen::MatrixXd G_, C_eq_, C_in_;
  Eigen::VectorXd a_, b_eq_, b_in_, rhs_, tau_, qdd_, forces_, full_tau_;
  Eigen::VectorXd limit_;  // per joint: min(torque_limit_Nm, the joint's effort limit)
};

}  // namespace dmbd::wholebody
