// The whole-body controller's QP (wbc_qp.hpp): its matrices, rebuilt each tick into
// storage sized once, and the torques of its solution.
#include "dmbd/wholebody/wbc_qp.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "dmbd/base/error.hpp"
#include "spd_inverse.hpp"

namespace dmbd::wholebody {

namespace {

constexpr int kBase = 6;  // floating-base rows of the equations of motion

}  // namespace

WbcQp::WbcQp(const Layout& layout, int num_contacts, const WbcQpParams& params)
    : nv_(layout.nv),
      nj_(static_cast<int>(layout.joints.size())),
      nc_(num_contacts),
      n_(nj_ + 3 * num_contacts),
      params_(params),
      qp_(n_, 0, 6 * num_contacts + 2 * nj_),
      P_(6, n_),
      base_rhs_(6, n_),
      K_(3 * num_contacts, n_),
      k_(3 * num_contacts),
      B_(kBase + 3 * num_contacts, n_),
      beta_(kBase + 3 * num_contacts),
      G_(Eigen::MatrixXd::Zero(n_, n_)),
      C_eq_(0, n_),
      C_in_(Eigen::MatrixXd::Zero(6 * num_contacts + 2 * nj_, n_)),
      a_(Eigen::VectorXd::Zero(n_)),
      b_eq_(0),
      b_in_(Eigen::VectorXd::Zero(6 * num_contacts + 2 * nj_)),
      rhs_(Eigen::VectorXd::Zero(layout.nv)),
      tau_(Eigen::VectorXd::Zero(nj_)),
      qdd_(Eigen::VectorXd::Zero(layout.nv)),
      forces_(Eigen::VectorXd::Zero(3 * num_contacts)),
      full_tau_(Eigen::VectorXd::Zero(layout.nv)),
      limit_(Eigen::VectorXd::Constant(nj_, params.torque_limit_Nm)) {
  for (int j = 0; j < nj_; ++j)
    limit_[j] = std::min(limit_[j], layout.joints[static_cast<size_t>(j)].limits.effort_Nm);
  qp_.set_warm_start(params.warm_start);
  if (layout.base_dofs != kBase) throw InputError("whole-body QP: the robot's base must be floating");
  if (!std::isfinite(params.w_qdd_base) || params.w_qdd_base == 0.0)
    throw InputError("whole-body QP: w_qdd_base must be positive (or negative for w_qdd)");
  for (int j = 0; j < nj_; ++j)
    if (layout.joints[static_cast<size_t>(j)].v_index != kBase + j)
      throw InputError("whole-body QP: the joints must follow the base in v");
  // The friction pyramids: F_z ≥ 0, μF_z ∓ F_x ≥ 0, μF_z ∓ F_y ≥ 0 (F_z ≤ F_max per tick).
  for (int c = 0; c < nc_; ++c) {
    const int f = nj_ + 3 * c, r = 6 * c;
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
  rhs_ = data.bg;  // A q̈_cmd + b + g: what Δq̈ and F must balance
  rhs_.noalias() += data.A * qdd_cmd;
  if (!reduce(data, J_c, Jc_dot_v, qdd_cmd)) return QpStatus::NotPositiveDefinite;
  build_cost(contacts);
  build_inequalities(data, J_c, contacts);
  const QpStatus status = qp_.solve(G_, a_, C_eq_, b_eq_, C_in_, b_in_);
  if (status != QpStatus::Optimal) return status;
  recover(qdd_cmd);
  torques_of(data, J_c);
  return status;
}

// The equalities solved for the variables they fix. Base rows: A_bb Δq̈_b + A_bj Δq̈_j −
// J_c,bᵀ F = −rhs_b, so Δq̈_b = A_bb⁻¹ ([−A_bj, J_c,bᵀ] y − rhs_b). Contact rows: s =
// J_c (q̈_cmd + Δq̈) + J̇_c v = J_c,b Δq̈_b + [J_c,j, 0] y + e. False if A_bb is not
// positive definite (no physical floating base).
// The products here are small (at most 16 x 12 x 16 on DRACO): lazyProduct evaluates
// them coefficient by coefficient, without the packing a blocked product spends on them.
bool WbcQp::reduce(const ModelData& data, const Eigen::Ref<const Eigen::MatrixXd>& J_c,
                   const Eigen::Ref<const Eigen::VectorXd>& Jc_dot_v, const Eigen::Ref<const Eigen::VectorXd>& qdd_cmd) {
  base_inertia_.compute(data.A.topLeftCorner<kBase, kBase>());
  if (base_inertia_.info() != Eigen::Success) return false;
  // A_bb⁻¹ once (fixed 6 x 6, from its factor: spd_inverse.hpp), then a product: solving
  // in place against the 6 x n right-hand side takes Eigen's blocked triangular path,
  // three times the cost.
  Eigen::Matrix<double, kBase, kBase> inverse, work;
  spd_inverse_from_factor(base_inertia_.matrixLLT(), work, inverse);
  base_rhs_.leftCols(nj_) = -data.A.topRightCorner(kBase, nj_);  // [−A_bj, J_c,bᵀ]
  base_rhs_.rightCols(3 * nc_) = J_c.leftCols(kBase).transpose();
  P_.noalias() = inverse.lazyProduct(base_rhs_);
  p0_.noalias() = -(inverse * rhs_.head<kBase>());
  K_.noalias() = J_c.leftCols(kBase).lazyProduct(P_);
  K_.leftCols(nj_) += J_c.rightCols(nj_);
  k_ = Jc_dot_v;
  k_.noalias() += J_c * qdd_cmd;
  k_.noalias() += J_c.leftCols(kBase) * p0_;
  return true;
}

// ½yᵀGy + aᵀy: the full problem's ½zᵀ diag(g) z (g = 2 × each weight) on the base's
// and the slacks' residuals B y + β (weighted by √g), plus the joints' and forces' own
// diagonal terms. G = BᵀB entry by entry, each a dot product of two of B's columns (the
// lower triangle, mirrored): a third of the cost of Eigen's product for these sizes.
void WbcQp::build_cost(const ContactSetting* contacts) {
  for (int i = 0; i < kBase; ++i) {
    const bool translation = i >= 3 && params_.w_qdd_base >= 0.0;
    const double w = std::sqrt(2.0 * (translation ? params_.w_qdd_base : params_.w_qdd));
    B_.row(i) = w * P_.row(i);
    beta_[i] = w * p0_[i];
  }
  for (int c = 0; c < nc_; ++c) {
    const double w = std::sqrt(2.0 * contacts[c].w_slack);
    B_.middleRows(kBase + 3 * c, 3) = w * K_.middleRows(3 * c, 3);
    beta_.segment(kBase + 3 * c, 3) = w * k_.segment(3 * c, 3);
  }
  for (int j = 0; j < n_; ++j) {
    for (int i = j; i < n_; ++i) G_(i, j) = B_.col(i).dot(B_.col(j));
    G_.row(j).tail(n_ - j - 1) = G_.col(j).tail(n_ - j - 1).transpose();
    a_[j] = B_.col(j).dot(beta_);
  }
  G_.diagonal().head(nj_).array() += 2.0 * params_.w_qdd;
  for (int c = 0; c < nc_; ++c) {
    const int f = nj_ + 3 * c;
    G_(f, f) += 2.0 * contacts[c].w_tangential;
    G_(f + 1, f + 1) += 2.0 * contacts[c].w_tangential;
    G_(f + 2, f + 2) += 2.0 * contacts[c].w_normal;
  }
}

// F_z ≤ F_max per contact, and each joint's torque within ±τ_max, τ = M y + m with
// M = A_jb P + [A_jj, −J_c,jᵀ] and m = A_jb p₀ + rhs_j: ±(M y + m) ≥ −τ_max.
void WbcQp::build_inequalities(const ModelData& data, const Eigen::Ref<const Eigen::MatrixXd>& J_c,
                               const ContactSetting* contacts) {
  for (int c = 0; c < nc_; ++c) b_in_[6 * c + 1] = -contacts[c].f_max_N;
  const int t = 6 * nc_;
  auto M = C_in_.middleRows(t, nj_);
  M.noalias() = data.A.bottomLeftCorner(nj_, kBase).lazyProduct(P_);
  M.leftCols(nj_) += data.A.bottomRightCorner(nj_, nj_);
  M.rightCols(3 * nc_) -= J_c.rightCols(nj_).transpose();
  C_in_.middleRows(t + nj_, nj_) = -M;
  auto m = b_in_.segment(t + nj_, nj_);  // m, then the bounds' constants from it
  m = rhs_.tail(nj_);
  m.noalias() += data.A.bottomLeftCorner(nj_, kBase) * p0_;
  b_in_.segment(t, nj_) = -m - limit_;
  m -= limit_;
}

// Δq̈ = [P y + p₀; y_j], F = y_F.
void WbcQp::recover(const Eigen::Ref<const Eigen::VectorXd>& qdd_cmd) {
  const Eigen::VectorXd& y = qp_.x();
  qdd_ = qdd_cmd;
  qdd_.head<kBase>() += p0_;
  qdd_.head<kBase>().noalias() += P_ * y;
  qdd_.tail(nj_) += y.head(nj_);
  forces_ = y.tail(3 * nc_);
}

// τ = S_a [A q̈ + b + g − J_cᵀ F].
void WbcQp::torques_of(const ModelData& data, const Eigen::Ref<const Eigen::MatrixXd>& J_c) {
  full_tau_ = data.bg;
  full_tau_.noalias() += data.A * qdd_;
  full_tau_.noalias() -= J_c.transpose() * forces_;
  tau_ = full_tau_.tail(nj_);
}

}  // namespace dmbd::wholebody
