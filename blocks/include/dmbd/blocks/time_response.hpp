#pragma once
// Time responses of state-space models.
#include <functional>
#include <optional>
#include <vector>

#include "dmbd/blocks/state_space.hpp"

namespace dmbd::blocks {

// A sampled response: row k of y is the outputs at time t[k].
struct TimeResponse {
  std::vector<double> t;  // s
  Matrix y;               // samples x outputs
};

// Step (unit, on input `in`) from t = 0 to t_end at n equally spaced samples. A
// continuous system is discretised exactly (ZOH is exact for the constant input);
// a discrete one is sampled at its own k ts up to t_end (n is then ignored). InputError
// for an input that does not exist, t_end <= 0 or n < 2.
TimeResponse step(const StateSpace& sys, double t_end, int n, int in = 0);
// Unit impulse on input `in`: continuous y(t) = C e^{At} B (the D delta term is left
// out); discrete: the unit pulse response. InputError as step().
TimeResponse impulse(const StateSpace& sys, double t_end, int n, int in = 0);
// Response to u (samples x inputs) held constant between samples spaced dt apart (exact
// for piecewise-constant input), from initial state x0 (zero when empty). A discrete
// system needs dt == its ts. InputError when u's columns or x0's size do not match the
// system, or dt <= 0.
TimeResponse lsim(const StateSpace& sys, const Matrix& u, double dt, const Vector& x0 = Vector());

// Figures of merit of a step response (step_info, step_figures); each empty when it is
// not defined. Times in seconds from the step.
struct StepInfo {
  // Final value: the DC gain for a stable system, empty otherwise (and then all
  // figures below are empty).
  std::optional<double> final_value;
  std::optional<double> rise_time_s;      // 10 % to 90 % of the final value (rise_low, rise_high)
  std::optional<double> settling_time_s;  // last exit from the +-2 % band (settling_fraction)
  std::optional<double> overshoot_pct;    // (peak - final) / final * 100, clamped at 0
  // The extreme value in the direction of the final value: the maximum (the minimum when
  // the final value is negative), refined between samples when the exact response is known.
  std::optional<double> peak, peak_time_s;  // the time of the peak
};

// Step information of channel (out, in) from its sampled step response. For a
// continuous system every crossing time and the peak are refined between samples on
// the exact response (matrix exponential), so the figures do not depend on the grid.
// All empty for an unstable system; InputError for a channel that does not exist.
StepInfo step_info(const StateSpace& sys, const TimeResponse& step_response, int out = 0, int in = 0,
                   double settling_fraction = 0.02, double rise_low = 0.1, double rise_high = 0.9);

// The figures of step_info from samples y at times t of a step response whose final
// value is `final`, with crossing times and the peak refined on y_at (the exact
// response at any time) when it is given, else taken at the samples.
StepInfo step_figures(const std::vector<double>& t, const std::vector<double>& y, double final,
                      const std::function<double(double)>& y_at, double settling_fraction = 0.02,
                      double rise_low = 0.1, double rise_high = 0.9);

// A reasonable t_end for a step response: 7 slowest time constants, or 10 periods
// of the slowest oscillation; for a stable system at least the mean delay of the
// impulse response of prod 1/(1 - s/p) plus 6 of its standard deviations (sum of
// -1/p, sum of 1/p^2: a chain of n lags of tau rises at n tau +- sqrt(n) tau);
// clamped to [1e-6, 1e6] s.
double default_step_horizon(const StateSpace& sys);
// The same from the poles (in z when ts > 0).
double step_horizon(const std::vector<Complex>& poles, double ts);

}  // namespace dmbd::blocks
