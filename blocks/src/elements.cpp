#include "dmbd/blocks/elements.hpp"

#include <cmath>
#include <string>

#include "dmbd/blocks/error.hpp"

namespace dmbd::blocks {

TransferFunction gain_block(double k) { return TransferFunction(k); }

TransferFunction pd(double p, double d, double tau_d) {
  if (tau_d < 0.0) throw InputError("PD derivative filter time constant must be >= 0");
  if (tau_d == 0.0) return TransferFunction(Polynomial({p, d}), Polynomial::constant(1.0));
  return TransferFunction(Polynomial({p, p * tau_d + d}), Polynomial({1.0, tau_d}));
}

TransferFunction pid(double p, double i, double d, double tau_d) {
  if (tau_d < 0.0) throw InputError("PID derivative filter time constant must be >= 0");
  if (d != 0.0 && tau_d == 0.0)
    throw InputError("PID with a derivative gain needs a derivative filter time constant > 0 to be proper");
  // P + I/s + D s/(tau s + 1) over the common denominator s (tau s + 1).
  return TransferFunction(Polynomial({i, p + i * tau_d, p * tau_d + d}), Polynomial({0.0, 1.0, tau_d}));
}

TransferFunction pid_terms(double p, std::optional<double> i, std::optional<double> d, double tau_d) {
  TransferFunction g(p);
  if (i) g = g + TransferFunction(Polynomial::constant(*i), Polynomial({0.0, 1.0}));
  if (d) {
    if (!(tau_d > 0.0) || !std::isfinite(tau_d))
      throw InputError("PID: a derivative term needs a filter time constant > 0 (D s alone is improper)");
    g = g + TransferFunction(Polynomial({0.0, *d}), Polynomial({1.0, tau_d}));
  }
  return g;
}

TransferFunction butterworth_lowpass(int order, double cutoff_rad_s) {
  if (order < 1 || order > 20) throw InputError("Butterworth order must be between 1 and 20, got " + std::to_string(order));
  if (!(cutoff_rad_s > 0.0) || !std::isfinite(cutoff_rad_s)) throw InputError("Butterworth cutoff must be > 0");
  std::vector<Complex> poles;
  for (int k = 0; k < order; ++k)
    poles.push_back(std::polar(cutoff_rad_s, M_PI / 2.0 + (2.0 * k + 1.0) * M_PI / (2.0 * order)));
  // The real pole of an odd order comes out with a rounding-level imaginary part.
  for (auto& p : poles)
    if (std::abs(p.imag()) < 1e-12 * cutoff_rad_s) p = Complex(p.real(), 0.0);
  return TransferFunction(Polynomial::constant(std::pow(cutoff_rad_s, order)), Polynomial::from_roots(poles, 1.0));
}

TransferFunction integrator(double k) { return TransferFunction(Polynomial::constant(k), Polynomial({0.0, 1.0})); }

}  // namespace dmbd::blocks
