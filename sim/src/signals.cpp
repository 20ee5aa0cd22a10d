#include "dmbd/sim/signals.hpp"

#include <cmath>

namespace dmbd::sim {

namespace {
constexpr double kPi = 3.14159265358979323846;

// Cosine fade-in over [0, ramp] and fade-out over [d - ramp, d] (d = 0: no end).
double taper(double t, double ramp, double d) {
  if (ramp <= 0) return 1.0;
  double w = 1.0;
  if (t < ramp) w = 0.5 - 0.5 * std::cos(kPi * t / ramp);
  if (d > 0 && t > d - ramp) w = std::min(w, 0.5 - 0.5 * std::cos(kPi * std::max(0.0, d - t) / ramp));
  return w;
}
}  // namespace

double exponential_chirp_phase(double f0_hz, double f1_hz, double duration_s, double t_s) {
  const double k = std::log(f1_hz / f0_hz) / duration_s;
  return 2 * kPi * f0_hz / k * std::expm1(k * t_s);
}

double Source::value(double t) const {
  double sum = 0;
  for (const Source& s : plus) sum += s.value(t);
  return sum + own_value(t);
}

double Source::own_value(double t) const {
  switch (kind) {
    case Kind::Constant:
      return offset;
    case Kind::Steps: {
      double v = offset;
      for (const auto& [ts, val] : steps) {
        if (t + 1e-12 >= ts) v = offset + val;
        else break;
      }
      return v;
    }
    case Kind::Sine: {
      const double tau = t - start_s;
      if (tau < 0 || (duration_s > 0 && tau > duration_s)) return offset;
      return offset + amplitude * taper(tau, ramp_s, duration_s) * std::sin(2 * kPi * freq_hz * tau);
    }
    case Kind::Chirp: {
      const double tau = t - start_s;
      if (tau < 0 || tau > duration_s) return offset;
      return offset + amplitude * taper(tau, ramp_s, duration_s) *
                          std::sin(exponential_chirp_phase(f0_hz, f1_hz, duration_s, tau));
    }
  }
  return offset;
}

double Source::frequency_hz(double t) const {
  const double tau = t - start_s;
  if (kind == Kind::Sine) return freq_hz;
  if (kind == Kind::Chirp && tau >= 0 && tau <= duration_s) return f0_hz * std::pow(f1_hz / f0_hz, tau / duration_s);
  return 0;
}

}  // namespace dmbd::sim
