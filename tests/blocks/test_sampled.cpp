// dmbd::blocks sampled-data models: ZOH discretisation with input and output dead
// times (the modified z-transform), against the textbook closed form, against an
// independent fine-step simulation, and against c2d times z^-d for whole periods.
#include <gtest/gtest.h>

#include <unsupported/Eigen/MatrixFunctions>

#include <cmath>
#include <vector>

#include "dmbd/blocks/delay.hpp"
#include "dmbd/blocks/discretize.hpp"
#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/sampled.hpp"
#include "test_support.hpp"

namespace dmbd::blocks {
namespace {

// G(z) of a discrete SISO model at z, from its matrices.
Complex response(const StateSpace& g, Complex z) { return g.evaluate(z)(0, 0); }

TEST(Sampled, FirstOrderLagWithAFractionalDelayIsTheModifiedZTransform) {
  // 1/(s + a) behind tau = d T + theta: with m = 1 - theta/T (Franklin, Powell, Workman,
  // Table of modified z-transforms),
  //   G(z) = z^-d [(1 - e^{-a m T}) z + (e^{-a m T} - e^{-a T})] / (a z (z - e^{-a T})).
  const double a = 30.0, T = 0.01;
  for (const double tau : {0.0025, 0.0132, 0.031}) {
    const int d = static_cast<int>(std::floor(tau / T));
    const double m = 1.0 - (tau - d * T) / T;
    const StateSpace g = c2d_zoh_delayed(StateSpace(Matrix::Constant(1, 1, -a), Matrix::Ones(1, 1), Matrix::Ones(1, 1),
                                                    Matrix::Zero(1, 1)),
                                         T, {tau});
    EXPECT_EQ(g.num_states(), 2 + d);
    for (const Complex z : {Complex(0.3, 0.8), Complex(-0.5, 0.1), Complex(1.7, -0.4)}) {
      const Complex ref = std::pow(z, -d) * ((1.0 - std::exp(-a * m * T)) * z + (std::exp(-a * m * T) - std::exp(-a * T))) /
                          (a * z * (z - std::exp(-a * T)));
      // A handful of roundings in the exponentials and the resolvent: 1e-12 relative.
      EXPECT_NEAR(std::abs(response(g, z) - ref), 0.0, 1e-12 * std::abs(ref)) << "tau " << tau;
    }
  }
}

TEST(Sampled, WholePeriodsAreTheZohModelTimesZToTheMinusD) {
  const TransferFunction p({100.0}, {100.0, 4.0, 1.0});  // 100/(s^2 + 4 s + 100)
  const double T = 0.005;
  const TransferFunction exact = c2d_zoh_delayed(p, T, 3 * T);
  const TransferFunction ref = c2d(p, T, C2dMethod::Zoh) * sample_delay(3, T);
  for (const Complex z : {Complex(0.9, 0.3), Complex(-0.2, 0.6)})
    EXPECT_NEAR(std::abs(exact.evaluate(z) - ref.evaluate(z)), 0.0, 1e-12 * std::abs(ref.evaluate(z)));
  EXPECT_EQ(exact.order(), 5);
  EXPECT_EQ(*whole_samples(3 * T, T), 3);
  EXPECT_FALSE(whole_samples(3.5 * T, T).has_value());
}

// The plant simulated on a grid 40 times finer than T, its input the held value of the
// period the delayed instant falls in: an independent formulation of the same
// sampled-data system (exact as well, since every delay is a multiple of T/40).
std::vector<Matrix> fine_simulation(const StateSpace& c, double T, const std::vector<double>& tau,
                                    const std::vector<int>& out_delay, const Matrix& u, int steps) {
  const int sub = 40, n = c.num_states(), m = c.num_inputs();
  const double h = T / sub;
  Matrix big = Matrix::Zero(n + m, n + m);
  big.topLeftCorner(n, n) = c.a() * h;
  big.topRightCorner(n, m) = c.b() * h;
  const Matrix e = big.exp(), phi = e.topLeftCorner(n, n), gam = e.topRightCorner(n, m);
  auto held = [&](int fine_index) {  // u at fine instant r h, each input delayed
    Matrix v = Matrix::Zero(m, 1);
    for (int j = 0; j < m; ++j) {
      const int r = fine_index - static_cast<int>(std::lround(tau[static_cast<size_t>(j)] / h));
      const int k = r < 0 ? -1 : r / sub;
      v(j, 0) = k < 0 ? 0.0 : u(j, k);
    }
    return v;
  };
  Matrix x = Matrix::Zero(n, 1);
  std::vector<Matrix> yhat;
  for (int k = 0; k < steps; ++k) {
    yhat.push_back(c.c() * x + c.d() * held(k * sub));
    for (int r = 0; r < sub; ++r) x = phi * x + gam * held(k * sub + r);
  }
  std::vector<Matrix> y(static_cast<size_t>(steps), Matrix::Zero(c.num_outputs(), 1));
  for (int k = 0; k < steps; ++k)
    for (int i = 0; i < c.num_outputs(); ++i) {
      const int kk = k - out_delay[static_cast<size_t>(i)];
      y[static_cast<size_t>(k)](i, 0) = kk < 0 ? 0.0 : yhat[static_cast<size_t>(kk)](i, 0);
    }
  return y;
}

TEST(Sampled, MimoWithInputAndOutputDelaysMatchesAFineStepSimulation) {
  // Two inputs, two outputs, direct feedthrough; delays 0.35 T, 2.6 T at the inputs and
  // 0, 2 periods at the outputs.
  Matrix a(3, 3), b(3, 2), cm(2, 3), d(2, 2);
  a << -5, 40, 0, -40, -5, 2, 0, 1, -12;
  b << 1, 0, 0.5, 2, 0, 1;
  cm << 1, 0, 1, 0, 2, -1;
  d << 0.3, 0, 0, -0.7;
  const StateSpace c(a, b, cm, d);
  const double T = 0.01;
  const std::vector<double> tau{0.35 * T, 2.6 * T};
  const std::vector<int> od{0, 2};
  const StateSpace g = c2d_zoh_delayed(c, T, tau, od);
  EXPECT_EQ(g.num_states(), 3 + 2 + 2 + 2);  // plant, two fractions, u2's 2 periods, y2's 2
  const int steps = 60;
  Matrix u(2, steps);
  for (int k = 0; k < steps; ++k) u.col(k) << std::sin(0.3 * k) + (k > 5 ? 1.0 : 0.0), std::cos(0.17 * k * k);
  const std::vector<Matrix> ref = fine_simulation(c, T, tau, od, u, steps);
  Matrix x = Matrix::Zero(g.num_states(), 1);
  for (int k = 0; k < steps; ++k) {
    const Matrix y = g.c() * x + g.d() * u.col(k);
    // 60 periods of a stable system, two exact formulations: 1e-12 absolute (|y| ~ 1).
    EXPECT_NEAR((y - ref[static_cast<size_t>(k)]).norm(), 0.0, 1e-12) << "k " << k;
    x = g.a() * x + g.b() * u.col(k);
  }
}

TEST(Sampled, WithoutDelaysItIsTheZohModel) {
  Matrix a(2, 2), b(2, 1), cm(1, 2), d(1, 1);
  a << 0, 1, -50, -3;
  b << 0, 1;
  cm << 1, 0;
  d << 0.1;
  const StateSpace c(a, b, cm, d), g = c2d_zoh_delayed(c, 0.02, {0.0}), ref = c2d(c, 0.02, C2dMethod::Zoh);
  EXPECT_NEAR((g.a() - ref.a()).norm() + (g.b() - ref.b()).norm() + (g.c() - ref.c()).norm() + (g.d() - ref.d()).norm(),
              0.0, 1e-14);
}

TEST(Sampled, BadArgumentsAreInputErrors) {
  const StateSpace c(Matrix::Constant(1, 1, -1.0), Matrix::Ones(1, 1), Matrix::Ones(1, 1), Matrix::Zero(1, 1));
  EXPECT_THROW(c2d_zoh_delayed(c, 0.01, {}), InputError);
  EXPECT_THROW(c2d_zoh_delayed(c, 0.01, {-0.001}), InputError);
  EXPECT_THROW(c2d_zoh_delayed(c, 0.0, {0.001}), InputError);
  EXPECT_THROW(c2d_zoh_delayed(c, 0.01, {0.001}, {1, 2}), InputError);
  EXPECT_THROW(c2d_zoh_delayed(c, 0.01, {1e4}), InputError);     // 10^6 periods: refused, not allocated
  EXPECT_THROW(c2d_zoh_delayed(c, 0.01, {0.0}, {5000}), InputError);
  EXPECT_NO_THROW(c2d_zoh_delayed(c, 0.01, {10.0}));               // 1000 periods: the limit
  EXPECT_THROW(c2d_zoh_delayed(c2d(c, 0.01, C2dMethod::Zoh), 0.01, {0.0}), InputError);
}

}  // namespace
}  // namespace dmbd::blocks
