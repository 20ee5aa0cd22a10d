#pragma once
// Shared helpers of the wholebody tests: evaluating a model at a state, deterministic
// random states, the closed-form forward dynamics and an RK4 step of a closed loop.
#include <functional>
#include <random>

#include <Eigen/Core>
#include <Eigen/LU>

#include "dmbd/wholebody/robot_model.hpp"

namespace dmbd::wholebody::testing {

// Every quantity of `model` at (q, v), in fresh storage.
inline ModelData evaluate(RobotModel& model, const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
  ModelData d = model.make_data();
  model.update(q, v, d);
  return d;
}

// Uniform in [-a, a] per entry, from a seeded generator (the tests are deterministic).
inline Eigen::VectorXd uniform(std::mt19937& rng, int n, double a) {
  std::uniform_real_distribution<double> u(-a, a);
  Eigen::VectorXd x(n);
  for (int i = 0; i < n; ++i) x[i] = u(rng);
  return x;
}

// q̈ = A⁻¹(τ − b − g) with a dense LU of the model's A (independent of the controllers'
// factorisations).
inline Eigen::VectorXd forward_dynamics(const ModelData& d, const Eigen::VectorXd& tau) {
  return d.A.partialPivLu().solve(tau - d.bg);
}

// One RK4 step from time t of the fixed-base closed loop q̈ = A⁻¹(τ(t, q, v) − b − g), the
// torque recomputed at every stage (a continuous-time control law).
using TorqueLaw = std::function<Eigen::VectorXd(double t, const ModelData&)>;
inline void rk4_step(RobotModel& model, const TorqueLaw& law, double t, double dt, Eigen::VectorXd& q,
                     Eigen::VectorXd& v) {
  ModelData d = model.make_data();
  auto accel = [&](double ts, const Eigen::VectorXd& qs, const Eigen::VectorXd& vs) {
    model.update(qs, vs, d);
    return forward_dynamics(d, law(ts, d));
  };
  const double h = 0.5 * dt;
  const Eigen::VectorXd k1v = accel(t, q, v), k1q = v;
  const Eigen::VectorXd k2v = accel(t + h, q + h * k1q, v + h * k1v), k2q = v + h * k1v;
  const Eigen::VectorXd k3v = accel(t + h, q + h * k2q, v + h * k2v), k3q = v + h * k2v;
  const Eigen::VectorXd k4v = accel(t + dt, q + dt * k3q, v + dt * k3v), k4q = v + dt * k3v;
  q += dt / 6.0 * (k1q + 2 * k2q + 2 * k3q + k4q);
  v += dt / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v);
}

}  // namespace dmbd::wholebody::testing
