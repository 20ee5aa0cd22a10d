#pragma once
// The response of a state-space model to sampled inputs that are linear between samples
// (first-order hold), with its states: python-control's forced_response and SciPy's lsim.
#include "dmbd/blocks/state_space.hpp"

namespace dmbd::blocks {

// Row k of each: the states and outputs at t_0 + k dt.
struct StateTrajectory {
  Matrix x;  // samples x states
  Matrix y;  // samples x outputs
};

// From x(t_0) = x0 (zero when empty) under u (samples x inputs) at samples dt apart.
// Continuous: u is linear between samples, and the step over one interval is exact:
// with the state [x; u; (u1 - u0)/dt], d/dt [x; u; v] = [A x + B u; v; 0], so
// [x1; u1; v] = e^{M dt} [x0; u0; v], M = [A B 0; 0 0 I; 0 0 0] (Van Loan), which gives
// x1 = Ad x0 + Bd0 u0 + Bd1 u1; the exponential by SchurExponential (to rounding for any
// dt and stiffness). Discrete: x[k+1] = A x[k] + B u[k], and dt must be the sample time
// (relative 1e-9). y = C x + D u at every sample. InputError when u's columns or x0's
// size do not match the system, u or x0 is not finite, fewer than one sample, or a bad dt.
StateTrajectory forced_response(const StateSpace& sys, const Matrix& u, double dt, const Vector& x0 = Vector());

}  // namespace dmbd::blocks
