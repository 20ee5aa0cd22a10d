// dmbd::blocks forced response with inputs linear between samples: a ramp through an
// integrator and a lag (closed forms), a constant input against the ZOH step, free
// response against the matrix exponential, discrete models, the refusals.
#include <gtest/gtest.h>

#include <cmath>

#include "dmbd/base/error.hpp"
#include "dmbd/blocks/forced_response.hpp"
#include "dmbd/blocks/schur_exponential.hpp"
#include "dmbd/blocks/time_response.hpp"

namespace dmbd::blocks {
namespace {

Matrix ramp(int n, double dt) {
  Matrix u(n, 1);
  for (int k = 0; k < n; ++k) u(k, 0) = k * dt;
  return u;
}

TEST(ForcedResponse, RampThroughIntegratorAndLag) {
  const double dt = 0.01, a = 2.0;
  const int n = 301;
  // 1/s: y = t^2 / 2, exact for the interpolated ramp.
  const StateTrajectory i = forced_response(StateSpace(Matrix::Zero(1, 1), Matrix::Ones(1, 1), Matrix::Ones(1, 1),
                                                       Matrix::Zero(1, 1)),
                                            ramp(n, dt), dt);
  // 1/(s + a): y = t/a - (1 - e^{-at})/a^2.
  const StateTrajectory l = forced_response(StateSpace(Matrix::Constant(1, 1, -a), Matrix::Ones(1, 1),
                                                       Matrix::Ones(1, 1), Matrix::Zero(1, 1)),
                                            ramp(n, dt), dt);
  for (int k = 0; k < n; ++k) {
    const double t = k * dt;
    EXPECT_NEAR(i.y(k, 0), t * t / 2.0, 1e-14 * (1.0 + t * t)) << t;  // 300 steps of rounding
    EXPECT_NEAR(l.y(k, 0), t / a - (1.0 - std::exp(-a * t)) / (a * a), 1e-14 * (1.0 + t)) << t;
    EXPECT_EQ(i.x(k, 0), i.y(k, 0));
  }
}

TEST(ForcedResponse, ConstantInputIsTheStep) {
  // Linear interpolation of a constant is the constant: the ZOH step of time_response.cpp.
  Matrix a(2, 2), b(2, 1), c(1, 2), d(1, 1);
  a << 0, 1, -4, -0.4;
  b << 0, 4;
  c << 1, 0.5;
  d << 0.1;
  const StateSpace sys(a, b, c, d);
  const TimeResponse s = step(sys, 5.0, 501);
  const StateTrajectory f = forced_response(sys, Matrix::Ones(501, 1), 0.01);
  for (int k = 0; k < 501; ++k) EXPECT_NEAR(f.y(k, 0), s.y(k, 0), 1e-13) << k;  // two exponentials, 500 steps
}

TEST(ForcedResponse, FreeResponseIsTheExponential) {
  Matrix a(3, 3);
  a << -1, 2, 0, -2, -1, 0.5, 0, 0, -3;
  const Vector x0 = Eigen::Vector3d(1.0, -0.5, 2.0);
  const StateSpace sys(a, Matrix::Zero(3, 1), Matrix::Identity(3, 3), Matrix::Zero(3, 1));
  const StateTrajectory f = forced_response(sys, Matrix::Zero(201, 1), 0.02, x0);
  const SchurExponential e(a);
  for (int k = 0; k < 201; k += 20)
    EXPECT_LE((f.x.row(k).transpose() - e.apply(x0, 0.02 * k)).norm(), 1e-14 * 10) << k;
}

TEST(ForcedResponse, DiscreteIsTheRecurrence) {
  Matrix a(1, 1), b(1, 1), c(1, 1), d(1, 1);
  a << 0.5;
  b << 1;
  c << 2;
  d << 1;
  const StateSpace sys(a, b, c, d, 0.1);
  Matrix u(4, 1);
  u << 1, 0, 0, 2;
  const StateTrajectory f = forced_response(sys, u, 0.1);
  // x = 0, 1, 0.5, 0.25; y = 2x + u.
  EXPECT_EQ(f.y(0, 0), 1.0);
  EXPECT_EQ(f.y(1, 0), 2.0);
  EXPECT_EQ(f.y(2, 0), 1.0);
  EXPECT_EQ(f.y(3, 0), 2.5);
  EXPECT_THROW(forced_response(sys, u, 0.2), InputError);
}

TEST(ForcedResponse, Refusals) {
  const StateSpace sys(Matrix::Constant(1, 1, -1.0), Matrix::Ones(1, 1), Matrix::Ones(1, 1), Matrix::Zero(1, 1));
  EXPECT_THROW(forced_response(sys, Matrix::Zero(5, 2), 0.1), InputError);
  EXPECT_THROW(forced_response(sys, Matrix::Zero(5, 1), 0.0), InputError);
  EXPECT_THROW(forced_response(sys, Matrix::Zero(5, 1), 0.1, Vector::Zero(2)), InputError);
  EXPECT_THROW(forced_response(sys, Matrix::Constant(5, 1, NAN), 0.1), InputError);
}

}  // namespace
}  // namespace dmbd::blocks
