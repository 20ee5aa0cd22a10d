// Prioritised inverse kinematics by null-space projection (prioritized_ik.hpp).
#include "dmbd/wholebody/prioritized_ik.hpp"

#include <cassert>
#include <string>

#include "dmbd/base/error.hpp"

namespace dmbd::wholebody {

PrioritizedIk::PrioritizedIk(int nv, int contact_dim, const std::vector<int>& task_dims, double sv_threshold)
    : nv_(nv),
      sqrt_w_(Eigen::VectorXd::Ones(nv)),
      Jc_t_(nv, contact_dim),
      Nt_(nv, nv),
      N_(nv, nv),
      dq_(nv),
      qd_(nv),
      qdd_(nv) {
  // J⁺ = Jᵀ(J Jᵀ)⁺ is the dynamically consistent inverse with A = I; its eigenvalue
  // threshold is the square of the singular-value one.
  const double eig_threshold = sv_threshold * sv_threshold;
  contact_pinv_ = std::make_unique<DynamicallyConsistentInverse>(contact_dim, nv, eig_threshold, false);  // N: start
  for (int m : task_dims) {
    pinv_.push_back(std::make_unique<DynamicallyConsistentInverse>(m, nv, eig_threshold, false));  // N: add_task
    J_pre_.emplace_back(m, nv);
    J_pre_t_.emplace_back(nv, m);
    residual_.emplace_back(m);
  }
  Nt_.setIdentity();
}

void PrioritizedIk::set_weights(const Eigen::Ref<const Eigen::VectorXd>& w) {
  if (w.size() != nv_) throw InputError("prioritized IK: " + std::to_string(w.size()) + " weights for " + std::to_string(nv_) + " coordinates");
  if (!w.allFinite() || (w.array() <= 0.0).any()) throw InputError("prioritized IK: the weights must be positive and finite");
  sqrt_w_ = w.cwiseSqrt();  // W's Cholesky factor (the square roots a factorisation of diag(w) takes)
}

void PrioritizedIk::solve(const ModelData& data, const Eigen::Ref<const Eigen::MatrixXd>& J_c,
                          const Eigen::Ref<const Eigen::VectorXd>& Jc_dot_v, const Task* const* tasks) {
  assert(data.v.size() == nv_);
  start(J_c, Jc_dot_v);
  for (size_t i = 0; i < pinv_.size(); ++i) add_task(data, *tasks[i], static_cast<int>(i));
}

// The last task's update of N is only wanted by a caller who asks for N.
const Eigen::MatrixXd& PrioritizedIk::null_space() const {
  if (!pinv_.empty() && last_update_pending_) {
    shrink(pinv_.back()->Jbar(), J_pre_t_.back());
    last_update_pending_ = false;
  }
  N_ = Nt_.transpose();
  return N_;
}

// The contacts: N₀ = I − J_c⁺ J_c, and the accelerations that keep the contacts still,
// q̈ = J_c⁺ (−J̇_c v) (zero without contacts).
void PrioritizedIk::start(const Eigen::Ref<const Eigen::MatrixXd>& J_c, const Eigen::Ref<const Eigen::VectorXd>& Jc_dot_v) {
  assert(J_c.cols() == nv_ || J_c.rows() == 0);
  dq_.setZero();
  qd_.setZero();
  last_update_pending_ = false;
  if (J_c.rows() == 0) {
    Nt_.setIdentity();
    qdd_.setZero();
    return;
  }
  contact_pinv_->compute_diagonal(sqrt_w_, J_c);
  Jc_t_ = J_c.transpose();
  Nt_.setIdentity();
  shrink(contact_pinv_->Jbar(), Jc_t_);  // N₀ = I − J_c⁺ J_c
  qdd_.noalias() = -contact_pinv_->Jbar() * Jc_dot_v;
}

// One task in the null space of those above: the three updates of the header, then
// N ← N (I − J_pre⁺ J_pre), formed as N − J_pre⁺ J_pre (a rank-m update instead of an
// nv x nv product). The two are equal: N is a W-orthogonal projector (N² = N and
// N W⁻¹ = W⁻¹ Nᵀ, true of N₀ and kept by each step), so with J_pre = J N,
// J_pre⁺ = W⁻¹ Nᵀ Jᵀ Λ = N W⁻¹ Jᵀ Λ and N J_pre⁺ = N² W⁻¹ Jᵀ Λ = J_pre⁺. After the last
// task N is not needed for the solution: its update waits for null_space().
void PrioritizedIk::add_task(const ModelData& data, const Task& task, int i) {
  const auto k = static_cast<size_t>(i);
  const Eigen::MatrixXd& J = task.jacobian();
  assert(J.rows() == J_pre_[k].rows());
  Eigen::MatrixXd& J_pre = J_pre_[k];
  Eigen::VectorXd& res = residual_[k];
  project(J, J_pre_t_[k]);
  J_pre = J_pre_t_[k].transpose();
  pinv_[k]->compute_diagonal(sqrt_w_, J_pre);
  res = task.error();
  res.noalias() -= J * dq_;
  dq_.noalias() += pinv_[k]->Jbar() * res;
  // ẋ_d = ė + J v (the task's reference rate).
  res = task.error_rate();
  res.noalias() += J * data.v;
  res.noalias() -= J * qd_;
  qd_.noalias() += pinv_[k]->Jbar() * res;
  res = task.command() - task.jacobian_dot_v();
  res.noalias() -= J * qdd_;
  qdd_.noalias() += pinv_[k]->Jbar() * res;
  if (k + 1 < pinv_.size()) shrink(pinv_[k]->Jbar(), J_pre_t_[k]);
  else last_update_pending_ = true;
}

// J_preᵀ = (J N)ᵀ column by column: column r is Σ_j J(r,j) (row j of N), and N's rows are
// the columns of the Nᵀ kept, so each term is a contiguous axpy; J's zeros (a selection's,
// a link's Jacobian off its chain) are skipped. (A tall-thin product with a 2- or 3-row
// factor: written out because Eigen's coefficient-wise product vectorises along those
// 2 or 3 rows and its blocked one packs panels for them.)
void PrioritizedIk::project(const Eigen::MatrixXd& J, Eigen::MatrixXd& J_pre_t) const {
  J_pre_t.setZero();
  for (Eigen::Index r = 0; r < J.rows(); ++r)
    for (Eigen::Index j = 0; j < nv_; ++j) {
      const double c = J(r, j);
      if (c != 0.0) J_pre_t.col(r).noalias() += c * Nt_.col(j);
    }
}

// N ← N − J̄ J_pre, kept as Nᵀ ← Nᵀ − J_preᵀ J̄ᵀ: column c of Nᵀ less Σ_i J̄(c,i) (column
// i of J_preᵀ), contiguous axpys again.
void PrioritizedIk::shrink(const Eigen::MatrixXd& Jbar, const Eigen::MatrixXd& J_pre_t) const {
  for (Eigen::Index c = 0; c < nv_; ++c)
    for (Eigen::Index i = 0; i < J_pre_t.cols(); ++i) Nt_.col(c).noalias() -= Jbar(c, i) * J_pre_t.col(i);
}

}  // namespace dmbd::wholebody
