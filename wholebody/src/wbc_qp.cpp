// The whole-body controller's QP (wbc_qp.hpp): its matrices, rebuilt each tick into
// storage sized once, and the torques of its solution.
#include "dmbd/wholebody/wbc_qp.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "dmbd/base/error.hpp"

namespace dmbd::wholebody {

namespace {

constexpr int kBase = 6;  // floating-base rows of the equations of motion

}  // namespace

WbcQp::WbcQp(const Layout& layout, int num_contacts, const WbcQpParams& params)
    : nv_(layout.nv),
      nj_(static_cast<int>(layout.joints.size())),
      nc_(num_contacts),
      n_(layout.nv + 6 * num_contacts),
      params_(params),
      qp_(n_, kBase + 3 * num_contacts, 6 * num_contacts + 2 * nj_),
      G_(Eigen::MatrixXd::Zero(n_, n_)),
      C_eq_(Eigen::MatrixXd::Zero(kBase + 3 * num_contacts, n_)),
      C_in_(Eigen::MatrixXd::Zero(6 * num_contacts + 2 * nj_, n_)),
      AJ_(Eigen::MatrixXd::Zero(layout.nv, layout.nv + 3 * num_contacts)),
      a_(Eigen::VectorXd::Zero(n_)),
      b_eq_(Eigen::VectorXd::Zero(kBase + 3 * num_contacts)),
      b_in_(Eigen::VectorXd::Zero(6 * num_contacts + 2 * nj_)),
      rhs_(Eigen::VectorXd::Zero(layout.nv)),
      tau_(Eigen::VectorXd::Zero(nj_)),
      qdd_(Eigen::VectorXd::Zero(layout.nv)),
      forces_(Eigen::VectorXd::Zero(3 * num_contacts)),
      full_tau_(Eigen::VectorXd::Zero(layout.nv)),
      limit_(Eigen::VectorXd::Constant(nj_, params.torque_limit_Nm)) {
  for (int j = 0; j < nj_; ++j)
    limit_[j] = std::min(limit_[j], layout.joints[static_cast<size_t>(j)].limits.effort_Nm);
  if (layout.base_dofs != kBase) throw InputError("whole-body QP: the robot's base must be floating");
  if (!std::isfinite(params.w_qdd_base) || params.w_qdd_base == 0.0)
    throw InputError("whole-body QP: w_qdd_base must be positive (or negative for w_qdd)");
  for (int j = 0; j < nj_; ++j)
    if (layout.joints[static_cast<size_t>(j)].v_index != kBase + j)
      throw InputError("whole-body QP: the joints must follow the base in v");
  // Contact accelerations minus their slack (the slack block is constant).
  C_eq_.block(kBase, nv_ + 3 * nc_, 3 * nc_, 3 * nc_) = -Eigen::MatrixXd::Identity(3 * nc_, 3 * nc_);
  // The friction pyramids: F_z ≥ 0, μF_z ∓ F_x ≥ 0, μF_z ∓ F_y ≥ 0 (F_z ≤ F_max per tick).
  for (int c = 0; c < nc_; ++c) {
    const int f = nv_ + 3 * c, r = 6 * c;
    C_in_(r, f + 2) = 1.0;
    C_in_(r + 1, f + 2) = -1.0;
    for (int k = 0; k < 2; ++k) {
      C_in_(r + 2 + 2 * k, f + 2) = params_.mu;
      C_in_(r + 2 + 2 * k, f + k) = -1.0;
      C_in_(r + 3 + 2 * k, f + 2) = params_.mu;
      C_in_(r + 3 + 2 * k, f + k) = 1.0;
    }
  }
}

QpStatus WbcQp::solve(const ModelData& data, const Eigen::Ref<const Eigen::MatrixXd>& J_c,
                      const Eigen::Ref<const Eigen::VectorXd>& Jc_dot_v, const Eigen::Ref<const Eigen::VectorXd>& qdd_cmd,
                      const ContactSetting* contacts) {
  assert(J_c.rows() == 3 * nc_ && J_c.cols() == nv_ && qdd_cmd.size() == nv_);
  AJ_.leftCols(nv_) = data.A;
  AJ_.rightCols(3 * nc_) = -J_c.transpose();
  rhs_ = data.bg;  // A q̈_cmd + b + g: what Δq̈ and F must balance
  rhs_.noalias() += data.A * qdd_cmd;
  build_cost(contacts);
  build_equalities(J_c, Jc_dot_v, qdd_cmd);
  build_inequalities(contacts);
  const QpStatus status = qp_.solve(G_, a_, C_eq_, b_eq_, C_in_, b_in_);
  if (status != QpStatus::Optimal) return status;
  qdd_ = qdd_cmd + qp_.x().head(nv_);
  forces_ = qp_.x().segment(nv_, 3 * nc_);
  torques_of(data, J_c);
  return status;
}

// ½zᵀGz with G diagonal: 2 × each weight (the QP's ½ cancels the problem's own scale).
void WbcQp::build_cost(const ContactSetting* contacts) {
  G_.diagonal().head(nv_).setConstant(2.0 * params_.w_qdd);
  if (params_.w_qdd_base >= 0.0) G_.diagonal().segment(3, 3).setConstant(2.0 * params_.w_qdd_base);  // base translation
  for (int c = 0; c < nc_; ++c) {
    const int f = nv_ + 3 * c, s = nv_ + 3 * nc_ + 3 * c;
    G_(f, f) = G_(f + 1, f + 1) = 2.0 * contacts[c].w_tangential;
    G_(f + 2, f + 2) = 2.0 * contacts[c].w_normal;
    for (int k = 0; k < 3; ++k) G_(s + k, s + k) = 2.0 * contacts[c].w_slack;
  }
}

// Base rows: [A_b, −J_c,bᵀ] [Δq̈; F] = −(A q̈_cmd + b + g)_b; contact rows:
// J_c Δq̈ − s = −J_c q̈_cmd − J̇_c v.
void WbcQp::build_equalities(const Eigen::Ref<const Eigen::MatrixXd>& J_c, const Eigen::Ref<const Eigen::VectorXd>& Jc_dot_v,
                             const Eigen::Ref<const Eigen::VectorXd>& qdd_cmd) {
  C_eq_.topLeftCorner(kBase, nv_ + 3 * nc_) = AJ_.topRows(kBase);
  b_eq_.head(kBase) = -rhs_.head(kBase);
  C_eq_.block(kBase, 0, 3 * nc_, nv_) = J_c;
  b_eq_.tail(3 * nc_) = -Jc_dot_v;
  b_eq_.tail(3 * nc_).noalias() -= J_c * qdd_cmd;
}

// F_z ≤ F_max per contact, and each joint's torque within ±τ_max:
// ±(S_a [A, −J_cᵀ] [Δq̈; F] + S_a (A q̈_cmd + b + g)) ≥ −τ_max.
void WbcQp::build_inequalities(const ContactSetting* contacts) {
  for (int c = 0; c < nc_; ++c) b_in_[6 * c + 1] = -contacts[c].f_max_N;
  const int t = 6 * nc_;
  const auto joint_rows = AJ_.bottomRows(nj_);
  C_in_.block(t, 0, nj_, nv_ + 3 * nc_) = joint_rows;
  C_in_.block(t + nj_, 0, nj_, nv_ + 3 * nc_) = -joint_rows;
  b_in_.segment(t, nj_) = -rhs_.tail(nj_);
  b_in_.segment(t, nj_) -= limit_;
  b_in_.segment(t + nj_, nj_) = rhs_.tail(nj_);
  b_in_.segment(t + nj_, nj_) -= limit_;
}

// τ = S_a [A q̈ + b + g − J_cᵀ F].
void WbcQp::torques_of(const ModelData& data, const Eigen::Ref<const Eigen::MatrixXd>& J_c) {
  full_tau_ = data.bg;
  full_tau_.noalias() += data.A * qdd_;
  full_tau_.noalias() -= J_c.transpose() * forces_;
  tau_ = full_tau_.tail(nj_);
}

}  // namespace dmbd::wholebody
