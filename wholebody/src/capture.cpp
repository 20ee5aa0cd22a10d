// Capturability of the stepping linear inverted pendulum (capture.hpp).
#include "dmbd/wholebody/capture.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "dmbd/base/error.hpp"

namespace dmbd::wholebody {

namespace {

void check_positive(double x, const char* what) {
  if (!(x > 0.0) || !std::isfinite(x)) throw InputError(std::string("capture analysis: ") + what + " must be positive and finite");
}

void check_range(const StepRange& s) {
  if (!(s.min_m <= s.max_m)) throw InputError("capture analysis: a step range's min is above its max");
}

}  // namespace

// The recursion of the header over a time t (β = e^{−ωt}).
CaptureInterval capture_interval_before(double omega_per_s, double t_s, const StepRange& step,
                                        const CaptureInterval& next, double cop_range_m) {
  check_positive(omega_per_s, "omega");
  check_range(step);
  if (!(t_s >= 0.0)) throw InputError("capture analysis: the time to the step must not be negative");
  if (!(cop_range_m >= 0.0)) throw InputError("capture analysis: the CoP range must not be negative");
  const double beta = std::exp(-omega_per_s * t_s), r = cop_range_m;
  return {-r + (next.lo_m + step.min_m + r) * beta, r + (next.hi_m + step.max_m - r) * beta};
}

// Around the cycle, last step first, until the intervals stop changing: each pass
// multiplies the distance to the fixed point by β^n (n steps), so it converges for any
// start; the 0-step interval [−r, r] is the start.
std::vector<CaptureInterval> capture_intervals(double omega_per_s, double step_time_s,
                                               const std::vector<StepRange>& cycle, double cop_range_m) {
  check_positive(omega_per_s, "omega");
  check_positive(step_time_s, "the step time");
  if (cycle.empty()) throw InputError("capture analysis: no step range");
  for (const auto& s : cycle) check_range(s);
  const std::size_t n = cycle.size();
  std::vector<CaptureInterval> c(n, CaptureInterval{-cop_range_m, cop_range_m});
  constexpr int kMaxPasses = 10000;
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    double change = 0.0;
    for (std::size_t i = n; i-- > 0;) {
      const CaptureInterval updated = capture_interval_before(omega_per_s, step_time_s, cycle[i], c[(i + 1) % n], cop_range_m);
      change = std::max({change, std::abs(updated.lo_m - c[i].lo_m), std::abs(updated.hi_m - c[i].hi_m)});
      c[i] = updated;
    }
    if (change <= 1e-15 * (1.0 + std::abs(c[0].lo_m) + std::abs(c[0].hi_m))) break;
  }
  return c;
}

double push_capture_point_shift(double force_N, double duration_s, double mass_kg, double omega_per_s) {
  check_positive(mass_kg, "the mass");
  check_positive(omega_per_s, "omega");
  if (!(duration_s >= 0.0)) throw InputError("capture analysis: the push's duration must not be negative");
  return force_N / (mass_kg * omega_per_s * omega_per_s) * std::expm1(omega_per_s * duration_s);
}

}  // namespace dmbd::wholebody
