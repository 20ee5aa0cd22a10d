// Issue 28: step and impulse responses exact at the samples over any horizon and
// stiffness (blocks::SchurExponential), against closed forms: 1/(s + 1) at 5e14 s,
// the stiff 1e6/((s + 1e-6)(s + 1e6)) at 1e6 and 1e7 s, repeated poles (Erlang step
// responses) out to 1e6 time constants, tiny t just after the step, and Siso::step,
// which dmbd analyze and the Python module use. (The wider randomised check against
// mpmath is tests/apps/long_horizon_check.py.)
#include <gtest/gtest.h>

#include <cmath>

#include "dmbd/blocks/schur_exponential.hpp"
#include "dmbd/blocks/siso.hpp"
#include "dmbd/blocks/time_response.hpp"
#include "test_support.hpp"

namespace dmbd::blocks {
namespace {

TransferFunction tf(const std::string& e) { return TransferFunction::parse(e, {}, 0.0); }

// Step of 1/(s + 1)^n: the Erlang distribution 1 - e^{-t} sum_{k<n} t^k/k!, and for
// small t its tail e^{-t} sum_{k>=n} t^k/k! (no cancellation).
double erlang_step(int n, double t) {
  double term = 1.0, head = 0.0;
  for (int k = 0; k < n; ++k, term *= t / k) head += term;
  if (t > 1.0) return 1.0 - std::exp(-t) * head;
  double tail = 0.0;
  for (int k = n; k < n + 40; ++k, term *= t / k) tail += term;
  return std::exp(-t) * tail;
}

TEST(ExactTimeResponse, LagOverFifteenOrdersOfMagnitudeIsOneAfterTheStep) {
  // Issue 28 row 2: was y = [0, 0.98450, 0.96923] (Eigen's squarings, then propagation).
  const Siso g = Siso::from_tf(tf("1/(s+1)"));
  const Siso::Step st = g.step(1e15, 3);
  EXPECT_EQ(st.response.y(0, 0), 0.0);                   // exactly D at t = 0
  EXPECT_NEAR(st.response.y(1, 0), 1.0, 1e-15);          // e^{-5e14} underflows: the final value
  EXPECT_NEAR(st.response.y(2, 0), 1.0, 1e-15);
  ASSERT_TRUE(st.info.settling_time_s.has_value());      // was null
  EXPECT_NEAR(*st.info.settling_time_s, -std::log(0.02), 1e-9);  // ln 50 s: 1e-9 absolute
}

TEST(ExactTimeResponse, StiffSlowModeIsExactAtTheSamples) {
  // Issue 28 row 2b: 1e6/((s + a)(s + b)), a = 1e-6, b = 1e6; was 632097.23 and 999634.23.
  const double a = 1e-6, b = 1e6;
  const Siso g = Siso::from_tf(tf("1e6/((s+1e-6)*(s+1e6))"));
  const Siso::Step st = g.step(1e7, 11);
  for (int k = 0; k < 11; ++k) {
    const double t = st.response.t[static_cast<size_t>(k)];
    const double y = 1e6 / (a * b) * (1.0 - (b * std::exp(-a * t) - a * std::exp(-b * t)) / (b - a));
    EXPECT_NEAR(st.response.y(k, 0), y, 1e-9 * 1e6) << "t = " << t;  // 1e-9 of the final value
  }
  EXPECT_NEAR(st.response.y(1, 0), 632120.5588, 1e-4);
  EXPECT_NEAR(st.response.y(10, 0), 999954.6001, 1e-4);
}

TEST(ExactTimeResponse, RepeatedPolesOutToAMillionTimeConstants) {
  for (int n : {3, 8}) {
    const Siso g = Siso::from_tf(tf("1/(s+1)^" + std::to_string(n)));
    for (double t_end : {30.0, 1e3, 1e6}) {
      const Siso::Step st = g.step(t_end, 21);
      for (int k = 0; k < 21; ++k) {
        const double t = st.response.t[static_cast<size_t>(k)];
        // 1e-11 of the final value 1 (rounding of the realisation's coefficients, C(8,4) = 70).
        EXPECT_NEAR(st.response.y(k, 0), erlang_step(n, t), 1e-11) << "n = " << n << ", t = " << t;
      }
    }
  }
}

TEST(ExactTimeResponse, TinyTimesAreExactRelativeToTheResponseItself) {
  // y ~ t^5/120 just after the step: 1e-12 relative to y itself, where the rounding of
  // the states (~ t) would be 1e-16 t = 1e10 times the response.
  const Siso g = Siso::from_tf(tf("1/(s+1)^5"));
  const Siso::Step st = g.step(1e-6, 5);
  EXPECT_EQ(st.response.y(0, 0), 0.0);
  for (int k = 1; k < 5; ++k) {
    const double t = st.response.t[static_cast<size_t>(k)], y = erlang_step(5, t);
    EXPECT_NEAR(st.response.y(k, 0), y, 1e-12 * y) << "t = " << t;
  }
}

TEST(ExactTimeResponse, StateSpaceStepAndImpulseAtLongHorizons) {
  const StateSpace sys = StateSpace::from_tf(tf("1e6/((s+1e-6)*(s+1e6))"));
  const TimeResponse st = step(sys, 1e7, 11);
  const TimeResponse im = impulse(sys, 1e7, 11);
  const double a = 1e-6, b = 1e6;
  for (int k = 0; k < 11; ++k) {
    const double t = st.t[static_cast<size_t>(k)];
    const double y = 1e6 / (a * b) * (1.0 - (b * std::exp(-a * t) - a * std::exp(-b * t)) / (b - a));
    const double h = 1e6 * (std::exp(-a * t) - std::exp(-b * t)) / (b - a);  // impulse response
    EXPECT_NEAR(st.y(k, 0), y, 1e-9 * 1e6) << "t = " << t;
    EXPECT_NEAR(im.y(k, 0), h, 1e-9 * 1.0) << "t = " << t;  // max h ~ 1
  }
}

TEST(ExactTimeResponse, UnstableResponseOverflowsWithoutNaNBeforeIt) {
  // e^{t} for t up to 1e3: finite up to 709, then beyond double (inf or NaN); the
  // samples before are exact.
  const Siso g = Siso::from_tf(tf("1/(s-1)"));
  const Siso::Step st = g.step(1e3, 11);
  for (int k = 0; k < 8; ++k) {
    const double t = st.response.t[static_cast<size_t>(k)];
    EXPECT_NEAR(st.response.y(k, 0), std::expm1(t), 1e-12 * std::expm1(t) + 1e-300) << "t = " << t;
  }
  EXPECT_FALSE(std::isfinite(st.response.y(8, 0)));  // e^{800}: not a number in double
}

TEST(SchurExponential, MatchesTheClosedFormOfAJordanBlock) {
  // e^{Jt} of a 3x3 Jordan block at -2: e^{-2t} [1 t t^2/2; 0 1 t; 0 0 1].
  Matrix j(3, 3);
  j << -2, 1, 0, 0, -2, 1, 0, 0, -2;
  const SchurExponential e(j);
  for (double t : {0.0, 1e-9, 0.3, 7.0, 300.0}) {
    const Matrix f = e.exp(t);
    const double d = std::exp(-2.0 * t);
    EXPECT_NEAR(f(0, 0), d, 1e-15);
    EXPECT_NEAR(f(0, 1), t * d, 1e-15);
    EXPECT_NEAR(f(0, 2), t * t / 2.0 * d, 1e-15);  // 1e-15 absolute: entries below 0.3
    EXPECT_NEAR(f(2, 0), 0.0, 1e-15);
  }
}

}  // namespace
}  // namespace dmbd::blocks
