// dmbd::blocks time responses: step and impulse against closed forms, lsim
// superposition and ZOH equivalence, step_info figures (grid independent), discrete
// systems.
#include <gtest/gtest.h>

#include <cmath>

#include "dmbd/blocks/discretize.hpp"
#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/time_response.hpp"
#include "test_support.hpp"

namespace dmbd::blocks {
namespace {

StateSpace lag_ss(double a) { return StateSpace::from_tf(TransferFunction(Polynomial({a}), Polynomial({a, 1.0}))); }

StateSpace second_order(double wn, double zeta) {
  return StateSpace::from_tf(TransferFunction(Polynomial({wn * wn}), Polynomial({wn * wn, 2.0 * zeta * wn, 1.0})));
}

TEST(TimeResponse, StepOfFirstOrderLag) {
  const double a = 3.0, t_end = 4.0;
  const int n = 401;
  const TimeResponse r = step(lag_ss(a), t_end, n);
  ASSERT_EQ(r.t.size(), static_cast<size_t>(n));
  ASSERT_EQ(r.y.rows(), n);
  ASSERT_EQ(r.y.cols(), 1);
  for (int k = 0; k < n; ++k) {
    const double t = r.t[static_cast<size_t>(k)];
    EXPECT_NEAR(t, k * t_end / (n - 1), 1e-14);  // the sample grid: 1e-14 absolute
    // 1 - e^{-a t}: exact ZOH recurrence, 400 steps of ~eps each: 1e-12 absolute (brief).
    EXPECT_NEAR(r.y(k, 0), 1.0 - std::exp(-a * t), 1e-12) << "t = " << t;
  }
}

TEST(TimeResponse, ImpulseOfFirstOrderLag) {
  const double a = 3.0, t_end = 4.0;
  const int n = 201;
  const TimeResponse r = impulse(lag_ss(a), t_end, n);
  for (int k = 0; k < n; ++k) {
    const double t = r.t[static_cast<size_t>(k)];
    // a e^{-a t}: powers of the exact e^{A dt}, relative 1e-12 of the peak a.
    EXPECT_NEAR(r.y(k, 0), a * std::exp(-a * t), 1e-12 * a) << "t = " << t;
  }
}

TEST(TimeResponse, ImpulseLeavesOutTheDirectTerm) {
  // (s+2)/(s+1) = 1 + 1/(s+1): the delta from D is left out (header), y = e^{-t}.
  const TimeResponse r = impulse(StateSpace::from_tf(TransferFunction::parse("(s+2)/(s+1)")), 2.0, 21);
  for (size_t k = 0; k < r.t.size(); ++k)
    EXPECT_NEAR(r.y(static_cast<Eigen::Index>(k), 0), std::exp(-r.t[k]), 1e-13) << r.t[k];  // 1e-13 absolute
}

TEST(TimeResponse, StaticGainAndMimo) {
  // A static gain: the step is D at every sample (exact).
  const StateSpace k = StateSpace::gain(Matrix::Constant(1, 1, 2.0));
  const TimeResponse rk = step(k, 1.0, 5);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(rk.y(i, 0), 2.0);
  // Two decoupled lags side by side: each input drives only its own output, equal to
  // the SISO responses (1e-13 absolute).
  const StateSpace a = StateSpace::from_tf(TransferFunction::parse("2/(s+2)"));
  const StateSpace b = StateSpace::from_tf(TransferFunction::parse("(s+3)/(s^2+s+4)"));
  const StateSpace ab = append(a, b);
  const TimeResponse s1 = step(ab, 3.0, 31, 1);
  const TimeResponse sb = step(b, 3.0, 31);
  for (int i = 0; i < 31; ++i) {
    EXPECT_EQ(s1.y(i, 0), 0.0);  // exactly zero: no coupling
    EXPECT_NEAR(s1.y(i, 1), sb.y(i, 0), 1e-13) << i;
  }
}

TEST(TimeResponse, StepOfSecondOrderClosedForm) {
  const double wn = 2.0, zeta = 0.3, wd = wn * std::sqrt(1.0 - zeta * zeta);
  const TimeResponse r = step(second_order(wn, zeta), 10.0, 501);
  for (size_t k = 0; k < r.t.size(); ++k) {
    const double t = r.t[k];
    // 1 - e^{-zeta wn t} (cos wd t + zeta/sqrt(1-zeta^2) sin wd t): 1e-12 absolute.
    const double want = 1.0 - std::exp(-zeta * wn * t) *
                                  (std::cos(wd * t) + zeta / std::sqrt(1.0 - zeta * zeta) * std::sin(wd * t));
    EXPECT_NEAR(r.y(static_cast<Eigen::Index>(k), 0), want, 1e-12) << "t = " << t;
  }
}

TEST(TimeResponse, LsimSuperpositionOfShiftedSteps) {
  // u is piecewise constant: 0 for k < 5, 2 for 5 <= k < 20, -1 for 20 <= k < 32, 0.5 after.
  // u = 2 H(k-5) - 3 H(k-20) + 1.5 H(k-32), so y[k] = 2 s[k-5] - 3 s[k-20] + 1.5 s[k-32]
  // with s the sampled step response.
  const StateSpace g = StateSpace::from_tf(TransferFunction::parse("(s+3)/((s+1)*(s^2+0.8*s+16))"));
  const double dt = 0.05;
  const int n = 120;
  Matrix u = Matrix::Zero(n, 1);
  for (int k = 0; k < n; ++k) u(k, 0) = k < 5 ? 0.0 : k < 20 ? 2.0 : k < 32 ? -1.0 : 0.5;
  const TimeResponse y = lsim(g, u, dt);
  const TimeResponse s = step(g, dt * (n - 1), n);
  ASSERT_NEAR(s.t[1], dt, 1e-15);  // same grid (1 ulp)
  auto sk = [&](int k) { return k < 0 ? 0.0 : s.y(k, 0); };
  for (int k = 0; k < n; ++k) {
    const double want = 2.0 * sk(k - 5) - 3.0 * sk(k - 20) + 1.5 * sk(k - 32);
    // Linear recurrences with the same matrices: rounding only, 1e-12 absolute
    // (responses of order 0.5).
    EXPECT_NEAR(y.y(k, 0), want, 1e-12) << "k = " << k;
  }
}

TEST(TimeResponse, LsimEqualsLsimOfZohDiscretisedSystem) {
  const StateSpace g = StateSpace::from_tf(TransferFunction::parse("(2*s^2 + s + 3)/((s+1)*(s^2+0.8*s+16))"));
  const double dt = 0.02;
  const int n = 300;
  Matrix u(n, 1);
  for (int k = 0; k < n; ++k) u(k, 0) = std::sin(0.07 * k) + (k % 17 < 8 ? 1.0 : -0.5);
  const TimeResponse yc = lsim(g, u, dt);
  const TimeResponse yd = lsim(c2d(g, dt, C2dMethod::Zoh), u, dt);
  ASSERT_EQ(yc.y.rows(), yd.y.rows());
  for (int k = 0; k < n; ++k) {
    EXPECT_NEAR(yd.t[static_cast<size_t>(k)], yc.t[static_cast<size_t>(k)], 1e-12);  // same instants
    // Same expm-based matrices from two call paths: 1e-12 absolute on O(1) outputs.
    EXPECT_NEAR(yd.y(k, 0), yc.y(k, 0), 1e-12) << "k = " << k;
  }
  // And against the ZOH discretisation of the TF simulated as a discrete SS of the TF
  // path (a different realisation): 1e-9 absolute (coefficient rounding near z = 1).
  const TimeResponse ytf =
      lsim(StateSpace::from_tf(c2d(TransferFunction::parse("(2*s^2 + s + 3)/((s+1)*(s^2+0.8*s+16))"), dt,
                                   C2dMethod::Zoh)),
           u, dt);
  for (int k = 0; k < n; ++k) EXPECT_NEAR(ytf.y(k, 0), yc.y(k, 0), 1e-9) << "k = " << k;
}

TEST(TimeResponse, LsimInitialStateAndErrors) {
  // x' = -a x + a u, y = x: free response from x0 = 2 is 2 e^{-a t} (1e-13 absolute).
  const double a = 1.5;
  const StateSpace g(Matrix::Constant(1, 1, -a), Matrix::Constant(1, 1, a), Matrix::Ones(1, 1), Matrix::Zero(1, 1));
  const TimeResponse r = lsim(g, Matrix::Zero(50, 1), 0.1, Vector::Constant(1, 2.0));
  for (int k = 0; k < 50; ++k) EXPECT_NEAR(r.y(k, 0), 2.0 * std::exp(-a * 0.1 * k), 1e-13) << "k = " << k;
  EXPECT_THROW(lsim(g, Matrix::Zero(10, 2), 0.1), InputError);                       // input columns
  EXPECT_THROW(lsim(g, Matrix::Zero(10, 1), 0.1, Vector::Zero(3)), InputError);      // x0 size
  EXPECT_THROW(lsim(g, Matrix::Zero(10, 1), 0.0), InputError);                       // dt
  const StateSpace gd = c2d(g, 0.1, C2dMethod::Zoh);
  EXPECT_THROW(lsim(gd, Matrix::Zero(10, 1), 0.2), InputError);                      // dt != ts
  EXPECT_THROW(step(g, -1.0, 10), InputError);
  EXPECT_THROW(step(g, 1.0, 1), InputError);
  EXPECT_THROW(step(g, 1.0, 10, 1), InputError);  // no input 1
}

TEST(StepInfo, FirstOrderLagClosedForm) {
  // 1 - e^{-at}: 10 % at ln(10/9)/a, 90 % at ln(10)/a -> rise ln 9 / a; the 2 % band is
  // entered for good at ln 50 / a; no overshoot; final value 1.
  const double a = 2.0;
  const StateSpace g = lag_ss(a);
  const StepInfo i1 = step_info(g, step(g, 5.0, 101));
  const StepInfo i2 = step_info(g, step(g, 4.0, 37));  // a different, coarser grid
  ASSERT_TRUE(i1.final_value && i1.rise_time_s && i1.settling_time_s && i1.overshoot_pct);
  ASSERT_TRUE(i2.rise_time_s && i2.settling_time_s);
  EXPECT_NEAR(*i1.final_value, 1.0, 1e-14);  // DC gain by LU: 1e-14
  // Crossings refined by bisection on the exact response: 1e-10 absolute.
  EXPECT_NEAR(*i1.rise_time_s, std::log(9.0) / a, 1e-10);
  EXPECT_NEAR(*i1.settling_time_s, std::log(50.0) / a, 1e-10);
  EXPECT_NEAR(*i1.overshoot_pct, 0.0, 1e-9);  // monotone response: clipped at 0 (1e-9 %)
  // Grid independent: two grids give the same figures to 1e-9 (brief).
  EXPECT_NEAR(*i2.rise_time_s, *i1.rise_time_s, 1e-9);
  EXPECT_NEAR(*i2.settling_time_s, *i1.settling_time_s, 1e-9);
}

TEST(StepInfo, SecondOrderOvershootAndPeakTime) {
  for (const double zeta : {0.1, 0.3, 0.6}) {
    const double wn = 4.0;
    const StateSpace g = second_order(wn, zeta);
    const double os = 100.0 * std::exp(-zeta * M_PI / std::sqrt(1.0 - zeta * zeta));
    const double tp = M_PI / (wn * std::sqrt(1.0 - zeta * zeta));
    const StepInfo i1 = step_info(g, step(g, 12.0, 241));
    const StepInfo i2 = step_info(g, step(g, 10.0, 97));
    ASSERT_TRUE(i1.overshoot_pct && i1.peak_time_s && i1.peak) << zeta;
    ASSERT_TRUE(i2.overshoot_pct && i2.peak_time_s) << zeta;
    // The peak is found by golden section on the exact response: the peak value to
    // ~eps (1e-9 % absolute on the overshoot), its time only to ~sqrt(eps) because the
    // response is flat there (1e-6 relative).
    EXPECT_NEAR(*i1.overshoot_pct, os, 1e-9) << zeta;
    EXPECT_NEAR(*i1.peak, 1.0 + os / 100.0, 1e-11) << zeta;
    EXPECT_NEAR(*i1.peak_time_s, tp, 1e-6 * tp) << zeta;
    // Grid independence of the same figures (same tolerances).
    EXPECT_NEAR(*i2.overshoot_pct, *i1.overshoot_pct, 1e-9) << zeta;
    EXPECT_NEAR(*i2.peak_time_s, *i1.peak_time_s, 1e-6 * tp) << zeta;
    // Rise and settling times are also grid independent (bisection: 1e-9).
    ASSERT_TRUE(i1.rise_time_s && i2.rise_time_s && i1.settling_time_s && i2.settling_time_s) << zeta;
    EXPECT_NEAR(*i2.rise_time_s, *i1.rise_time_s, 1e-9) << zeta;
    EXPECT_NEAR(*i2.settling_time_s, *i1.settling_time_s, 1e-9) << zeta;
    // Settling time is at least the peak time when the overshoot exceeds 2 %.
    if (os > 2.0) {
      EXPECT_GT(*i1.settling_time_s, tp) << zeta;
    }
  }
}

TEST(StepInfo, NegativeGainMirrorsPositive) {
  // -G has the mirrored step response: same overshoot (measured in the direction of
  // the final value), rise, settling and peak time; final value and peak negated.
  const double wn = 4.0, zeta = 0.3;
  const StateSpace g = second_order(wn, zeta);
  const StateSpace ng = StateSpace::from_tf(TransferFunction(Polynomial({-wn * wn}), Polynomial({wn * wn, 2.0 * zeta * wn, 1.0})));
  const StepInfo p = step_info(g, step(g, 10.0, 201));
  const StepInfo n = step_info(ng, step(ng, 10.0, 201));
  ASSERT_TRUE(p.overshoot_pct && n.overshoot_pct && n.final_value && n.peak);
  EXPECT_NEAR(*n.final_value, -*p.final_value, 1e-14);  // LU solve: 1e-14
  EXPECT_NEAR(*n.overshoot_pct, *p.overshoot_pct, 1e-9);  // same tolerances as above
  EXPECT_NEAR(*n.peak, -*p.peak, 1e-11);
  EXPECT_NEAR(*n.peak_time_s, *p.peak_time_s, 1e-6);
  EXPECT_NEAR(*n.rise_time_s, *p.rise_time_s, 1e-9);
  EXPECT_NEAR(*n.settling_time_s, *p.settling_time_s, 1e-9);
}

TEST(StepInfo, SettlingTimeSatisfiesItsDefinition) {
  // For an underdamped system, the settling time t_s is where |y/final - 1| = 2 % for
  // the last time: check it on a fine grid after and just before t_s.
  const StateSpace g = second_order(3.0, 0.25);
  const StepInfo info = step_info(g, step(g, 15.0, 151));
  ASSERT_TRUE(info.settling_time_s);
  const double ts = *info.settling_time_s;
  const TimeResponse fine = step(g, 15.0, 15001);
  for (size_t k = 0; k < fine.t.size(); ++k) {
    if (fine.t[k] > ts + 1e-9) {
      // Inside the band after t_s (1e-12 slack for rounding at the boundary).
      EXPECT_LE(std::abs(fine.y(static_cast<Eigen::Index>(k), 0) - 1.0), 0.02 + 1e-12) << "t = " << fine.t[k];
    }
  }
  // At t_s the response is on the band edge (1e-9: the bisection tolerance).
  const TimeResponse at = step(g, ts, 2);
  EXPECT_NEAR(std::abs(at.y(1, 0) - 1.0), 0.02, 1e-9);
}

TEST(StepInfo, UnstableSystemHasNoFinalValue) {
  const StateSpace g = StateSpace::from_tf(TransferFunction::parse("1/((s-0.5)*(s+2))"));
  const StepInfo info = step_info(g, step(g, 5.0, 51));
  EXPECT_FALSE(info.final_value.has_value());
  EXPECT_FALSE(info.rise_time_s.has_value());
  EXPECT_FALSE(info.settling_time_s.has_value());
  EXPECT_FALSE(info.overshoot_pct.has_value());
  // An integrator is not stable either.
  const StateSpace integ = StateSpace::from_tf(TransferFunction::parse("1/s"));
  EXPECT_FALSE(step_info(integ, step(integ, 5.0, 51)).final_value.has_value());
}

TEST(TimeResponse, DiscreteStepOfDiscreteSystem) {
  // H(z) = (1 - p)/(z - p): y[k] = 1 - p^k (one sample of delay), sampled at k ts.
  const double p = 0.8, ts = 0.1;
  const StateSpace g = StateSpace::from_tf(TransferFunction(Polynomial({1.0 - p}), Polynomial({-p, 1.0}), ts));
  const TimeResponse r = step(g, 3.0, 999 /* ignored for a discrete system */);
  ASSERT_EQ(r.t.size(), 31u);  // floor(3.0 / 0.1) + 1 samples
  for (size_t k = 0; k < r.t.size(); ++k) {
    EXPECT_NEAR(r.t[k], k * ts, 1e-12);  // k ts
    // 1 - p^k by the recurrence: 1e-14 absolute after 30 steps.
    EXPECT_NEAR(r.y(static_cast<Eigen::Index>(k), 0), 1.0 - std::pow(p, static_cast<double>(k)), 1e-14) << k;
  }
  // Unit pulse response: (1 - p) p^{k-1} for k >= 1, 0 at k = 0 (1e-15 absolute).
  const TimeResponse h = impulse(g, 1.0, 0);
  EXPECT_NEAR(h.y(0, 0), 0.0, 1e-15);
  for (Eigen::Index k = 1; k < h.y.rows(); ++k)
    EXPECT_NEAR(h.y(k, 0), (1.0 - p) * std::pow(p, static_cast<double>(k - 1)), 1e-15) << k;
  // step_info on the samples: final value 1; rise: first samples at or above 10 % and
  // 90 %: y[1] = 0.2 and y[k] >= 0.9 first at k = 11 (1 - 0.8^11 = 0.914) -> 1.0 s
  // exactly up to the sample times (1e-12).
  const StepInfo info = step_info(g, r);
  ASSERT_TRUE(info.final_value && info.rise_time_s && info.settling_time_s);
  EXPECT_NEAR(*info.final_value, 1.0, 1e-14);
  EXPECT_NEAR(*info.rise_time_s, 1.1 - 0.1, 1e-12);
  // Inside 2 % from the first k with 0.8^k <= 0.02: k = 18 (0.018) -> 1.8 s.
  EXPECT_NEAR(*info.settling_time_s, 1.8, 1e-12);
}

TEST(TimeResponse, DefaultHorizon) {
  // Stable: 7 / slowest decay rate (implementation choice within "6 slowest time
  // constants" of the header comment); at least 6 time constants.
  const double h = default_step_horizon(lag_ss(2.0));
  EXPECT_GE(h, 6.0 / 2.0);
  EXPECT_LE(h, 10.0 / 2.0);
  // Clamped to [1e-6, 1e6].
  EXPECT_LE(default_step_horizon(lag_ss(1e-9)), 1e6);
  EXPECT_GE(default_step_horizon(lag_ss(1e9)), 1e-6);
}

}  // namespace
}  // namespace dmbd::blocks
