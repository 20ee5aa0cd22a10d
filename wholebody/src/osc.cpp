// Operational space control with a posture task in the null space (osc.hpp).
#include "dmbd/wholebody/osc.hpp"

#include "dmbd/base/error.hpp"

namespace dmbd::wholebody {

OperationalSpaceControl::OperationalSpaceControl(const Layout& layout, int task_dim, int posture_dim)
    : A_factor_(layout.nv),
      inv_(task_dim, layout.nv),
      posture_inv_(posture_dim, layout.nv, 1e-9, false),  // the lowest task: no null space
      F_(Eigen::VectorXd::Zero(task_dim)),
      tau0_(Eigen::VectorXd::Zero(layout.nv)),
      F0_(Eigen::VectorXd::Zero(posture_dim)),
      a_(Eigen::VectorXd::Zero(task_dim)),
      a0_(Eigen::VectorXd::Zero(posture_dim)) {
  if (layout.base_dofs != 0)
    throw InputError("operational space control: the robot's base must be fixed (every coordinate actuated)");
}

void OperationalSpaceControl::compute(const ModelData& data, const Task& task, const Task* posture,
                                      Eigen::Ref<Eigen::VectorXd> tau) {
  A_factor_.compute(data.A);  // one factor of A for the task and the posture
  inv_.compute(A_factor_, task.jacobian());
  // F = Λ (ẍ_cmd − J̇ v);  τ = Jᵀ F + b + g  (= A J̄ (ẍ_cmd − J̇ v) + b + g).
  a_ = task.command() - task.jacobian_dot_v();
  F_.noalias() = inv_.Lambda() * a_;
  tau.noalias() = task.jacobian().transpose() * F_;
  tau += data.bg;
  if (posture == nullptr || F0_.size() == 0) return;
  a0_ = posture->command() - posture->jacobian_dot_v();
  if (posture->jacobian().isIdentity(0.0)) {
    // A posture of every coordinate in v's order: J_p = I, so Λ_p = A exactly and
    // τ₀ = A q̈_cmd (no inverse of A⁻¹ to form).
    tau0_.noalias() = data.A * a0_;
  } else {
    posture_inv_.compute(A_factor_, posture->jacobian());
    F0_.noalias() = posture_inv_.Lambda() * a0_;
    tau0_.noalias() = posture->jacobian().transpose() * F0_;
  }
  tau.noalias() += inv_.N().transpose() * tau0_;
}

}  // namespace dmbd::wholebody
