#pragma once
// Prioritised inverse kinematics by null-space projection (the kinematic part of the
// paper's whole-body control, Sec. IV-B; Kim et al. 2019): starting from the null space
// of the contacts, each task in priority order is solved in the null space of every
// task above it, for a configuration step, joint rates and joint accelerations:
//
//   N₀ = I − J_c⁺ J_c,  Δq = 0,  q̇ = 0,  q̈ = J_c⁺ (−J̇_c v)
//   for task i:  J_pre = J_i N_{i−1}
//     Δq ← Δq + J_pre⁺ (e_i − J_i Δq)
//     q̇  ← q̇  + J_pre⁺ (ẋ_d,i − J_i q̇)
//     q̈  ← q̈  + J_pre⁺ (ẍ_cmd,i − J̇_i v − J_i q̈)
//     N_i = N_{i−1} (I − J_pre⁺ J_pre)  (formed as N_{i−1} − J_pre⁺ J_pre: prioritized_ik.cpp)
//
// J⁺ is the Moore–Penrose pseudo-inverse with singular values below `sv_threshold`
// times the largest left out (the authors' SVD threshold, 0.003). Every N_i is the
// orthogonal projector onto the joint motions that move no contact and no task above,
// so J_i J_pre⁺ = I (J_pre of full row rank) and a lower task never disturbs a higher
// one (J_k N_i = 0 for k ≤ i); every task is met exactly when the tasks and contacts
// are compatible. With set_weights(w), J⁺ = W⁻¹Jᵀ(JW⁻¹Jᵀ)⁺ (W = diag w): each step is
// the one of least Σ w_i Δq_i² instead of least Σ Δq_i², the N_i are W-orthogonal
// projectors and the priorities hold as before. A large weight on a floating base's
// coordinates keeps the solution from moving the base in ways no joint can (with a point
// contact, a rotation of the whole robot about it). The accelerations are kinematic, as in the authors' controller: the
// QP that follows corrects them for the dynamics. Δq and q̇ live in v's coordinates (a
// floating base's rotation as a world-axes rotation vector: q_des = integrate(q, Δq, 1)).
// Allocation-free after construction.
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "dmbd/wholebody/projection.hpp"
#include "dmbd/wholebody/robot_model.hpp"
#include "dmbd/wholebody/task.hpp"

namespace dmbd::wholebody {

class PrioritizedIk {
 public:
  // nv: the model's; contact_dim: rows of the contact Jacobian (0: none); task_dims: the
  // tasks' dimensions in priority order (solve() takes tasks of these dimensions).
  PrioritizedIk(int nv, int contact_dim, const std::vector<int>& task_dims, double sv_threshold = 0.003);

  // Tasks updated at data's state (data.v is the current rate), in priority order;
  // J_c and J̇_c v at that state.
  void solve(const ModelData& data, const Eigen::Ref<const Eigen::MatrixXd>& J_c,
             const Eigen::Ref<const Eigen::VectorXd>& Jc_dot_v, const Task* const* tasks);

  const Eigen::VectorXd& delta_q() const { return dq_; }   // configuration step (v coordinates)
  const Eigen::VectorXd& qd() const { return qd_; }        // joint rates (v)
  const Eigen::VectorXd& qdd() const { return qdd_; }      // accelerations (v)
  const Eigen::MatrixXd& null_space() const;                // after the last task (formed when asked)

  // One positive weight per v coordinate (all 1 at construction). Throws InputError for
  // a size other than nv or a weight that is not positive and finite. Not for a tick.
  void set_weights(const Eigen::Ref<const Eigen::VectorXd>& w);

 private:
  void start(const Eigen::Ref<const Eigen::MatrixXd>& J_c, const Eigen::Ref<const Eigen::VectorXd>& Jc_dot_v);
  void add_task(const ModelData& data, const Task& task, int i);
  void project(const Eigen::MatrixXd& J, Eigen::MatrixXd& J_pre_t) const;
  void shrink(const Eigen::MatrixXd& Jbar, const Eigen::MatrixXd& J_pre_t) const;

  int nv_;
  Eigen::VectorXd sqrt_w_;  // J⁺ is the A-weighted inverse with A = W = diag(sqrt_w_)² (I by default)
  std::unique_ptr<DynamicallyConsistentInverse> contact_pinv_;
  std::vector<std::unique_ptr<DynamicallyConsistentInverse>> pinv_;       // per task
  std::vector<Eigen::MatrixXd> J_pre_;                                      // per task
  std::vector<Eigen::MatrixXd> J_pre_t_;                                    // per task, transposed
  std::vector<Eigen::VectorXd> residual_;                                   // per task
  Eigen::MatrixXd Jc_t_;                   // J_cᵀ
  mutable Eigen::MatrixXd Nt_;             // Nᵀ: N's rows as contiguous columns
  mutable Eigen::MatrixXd N_;              // null_space()'s copy
  mutable bool last_update_pending_ = false;  // Nt_ still lacks the last task's update
  Eigen::VectorXd dq_, qd_, qdd_;
};

}  // namespace dmbd::wholebody
