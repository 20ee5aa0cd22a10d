#pragma once
// Operational space control (paper Sec. IV-A, the OSC law):
//   τ = A J̄ (ẍ_cmd − J̇ v) + b + g + Nᵀ τ₀
// with ẍ_cmd = ẍ_d + Kp e + Kd ė from the task, J̄ = A⁻¹Jᵀ(J A⁻¹ Jᵀ)⁻¹ and N = I − J̄ J
// (A J̄ = Jᵀ Λ: the law is the classical Jᵀ F, F = Λ(ẍ_cmd − J̇ v), plus b + g).
// A posture task, when given, acts in the null space of the operational task: its own
// operational-space torque τ₀ = J_pᵀ Λ_p (ẍ_cmd,p − J̇_p v) (for a posture of every
// joint: A q̈_cmd,p) enters as Nᵀ τ₀, which moves no task coordinate (J A⁻¹ Nᵀ = 0).
// For a fully actuated robot (a fixed base: every coordinate a joint). Allocation-free
// after construction.
#include <Eigen/Core>

#include "dmbd/wholebody/projection.hpp"
#include "dmbd/wholebody/robot_model.hpp"
#include "dmbd/wholebody/task.hpp"

namespace dmbd::wholebody {

class OperationalSpaceControl {
 public:
  // Throws InputError for a floating base (the law needs every coordinate actuated).
  // posture_dim: the posture task's dimension (0: none).
  OperationalSpaceControl(const Layout& layout, int task_dim, int posture_dim = 0);

  // τ (nv) for `task` (updated at data's state) and, if given, `posture` in its null
  // space. Both tasks must have been updated at data's state.
  void compute(const ModelData& data, const Task& task, const Task* posture, Eigen::Ref<Eigen::VectorXd> tau);

  const DynamicallyConsistentInverse& inverse() const { return inv_; }
  const Eigen::VectorXd& task_force() const { return F_; }   // Λ(ẍ_cmd − J̇ v), m

 private:
  Eigen::LLT<Eigen::MatrixXd> A_factor_;
  DynamicallyConsistentInverse inv_, posture_inv_;
  Eigen::VectorXd F_, tau0_, F0_, a_, a0_;  // a: ẍ_cmd − J̇ v
};

}  // namespace dmbd::wholebody
