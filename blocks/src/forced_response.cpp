#include "dmbd/blocks/forced_response.hpp"

#include <cmath>
#include <string>

#include "dmbd/base/error.hpp"
#include "dmbd/blocks/schur_exponential.hpp"

namespace dmbd::blocks {

namespace {

void check(const StateSpace& sys, const Matrix& u, double dt, const Vector& x0) {
  if (u.cols() != sys.num_inputs())
    throw InputError("U: expected " + std::to_string(sys.num_inputs()) + " inputs, got " + std::to_string(u.cols()));
  if (u.rows() < 1) throw InputError("U: expected at least one sample");
  if (!u.allFinite()) throw InputError("U: has values that are not finite");
  if (x0.size() && x0.size() != sys.num_states())
    throw InputError("X0: expected " + std::to_string(sys.num_states()) + " states, got " + std::to_string(x0.size()));
  if (!x0.allFinite()) throw InputError("X0: has values that are not finite");
  if (!(dt > 0.0) || !std::isfinite(dt)) throw InputError("T: expected samples a positive time apart");
  if (sys.is_discrete() && std::abs(dt - sys.ts()) > 1e-9 * sys.ts())
    throw InputError("T: the samples are " + std::to_string(dt) + " s apart, the system's sample time is " +
                     std::to_string(sys.ts()) + " s (expected equal)");
}

// The one-interval map x1 = ad x0 + b0 u0 + b1 u1.
struct Hold {
  Matrix ad, b0, b1;
};

Hold first_order_hold(const StateSpace& sys, double dt) {
  const Eigen::Index n = sys.num_states(), m = sys.num_inputs();
  if (sys.is_discrete()) return {sys.a(), sys.b(), Matrix::Zero(n, m)};
  Matrix big = Matrix::Zero(n + 2 * m, n + 2 * m);
  big.topLeftCorner(n, n) = sys.a();
  big.block(0, n, n, m) = sys.b();
  big.block(n, n + m, m, m) = Matrix::Identity(m, m);
  const Matrix e = SchurExponential(big).exp(dt);
  const Matrix b1 = e.block(0, n + m, n, m) * (1.0 / dt);
  return {e.topLeftCorner(n, n), e.block(0, n, n, m) - b1, b1};
}

}  // namespace

StateTrajectory forced_response(const StateSpace& sys, const Matrix& u, double dt, const Vector& x0) {
  check(sys, u, dt, x0);
  const Hold h = first_order_hold(sys, dt);
  const Eigen::Index samples = u.rows(), n = sys.num_states();
  StateTrajectory out{Matrix(samples, n), Matrix(samples, sys.num_outputs())};
  Vector x = x0.size() ? x0 : Vector::Zero(n);
  Vector next(n);
  for (Eigen::Index k = 0; k < samples; ++k) {
    out.x.row(k) = x.transpose();
    if (k + 1 == samples) break;
    next.noalias() = h.ad * x;
    next.noalias() += h.b0 * u.row(k).transpose();
    next.noalias() += h.b1 * u.row(k + 1).transpose();
    x.swap(next);
  }
  out.y = out.x * sys.c().transpose() + u * sys.d().transpose();
  return out;
}

}  // namespace dmbd::blocks
