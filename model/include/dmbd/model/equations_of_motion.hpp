#pragma once
// The equations of motion of RobotDynamics' bare tree, A(q) v̇ + b(q, v) + g(q) = τ,
// solved either way at the dynamics' current state (set_state first): inverse dynamics
// (v̇ → τ, Pinocchio's rnea) and forward dynamics (τ → v̇, Pinocchio's aba). Both from
// the tree kernel's A and b + g; forward dynamics factors A by Eigen's LLT (O(n³), a few
// µs for DRACO's 16 velocities; no articulated-body pass is kept for a tree this small).
// SimbodyReference has Simbody's O(n) recursive Newton–Euler and articulated-body
// operators for the same two, which the tests compare with these.
#include "dmbd/model/dynamics.hpp"

#include <Eigen/Core>

namespace dmbd::model {

// τ = A v̇ + b + g. Throws ModelError when v̇ has not nv entries.
Eigen::VectorXd inverse_dynamics(const RobotDynamics& dynamics, const Eigen::Ref<const Eigen::VectorXd>& vdot);

// v̇ = A⁻¹ (τ − b − g). Throws ModelError when τ has not nv entries.
Eigen::VectorXd forward_dynamics(const RobotDynamics& dynamics, const Eigen::Ref<const Eigen::VectorXd>& tau);

}  // namespace dmbd::model
