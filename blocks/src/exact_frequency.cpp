#include "dmbd/blocks/exact_frequency.hpp"

#include <cmath>
#include <limits>

namespace dmbd::blocks {

namespace {

constexpr double kDeg = 180.0 / M_PI;

// f(w) from the exact response; empty where it has no finite value.
using Scalar = std::function<std::optional<double>(double)>;

// The root of f nearest w0, bracketed by a sign change within w0 (1 + d)^+-1,
// d = 1e-9, 4e-9, ... up to 1 (a factor 2), then bisected (in w, to 2 ulps).
// Empty when f has no value at w0 or no sign change is found there.
std::optional<double> refine(const Scalar& f, double w0) {
  const std::optional<double> f0 = f(w0);
  if (!f0 || !(w0 > 0.0)) return std::nullopt;
  if (*f0 == 0.0) return w0;
  double a = 0.0, b = 0.0, fa = 0.0;
  bool found = false;
  for (double d = 1e-9; d <= 1.0 && !found; d *= 4.0) {
    for (double w : {w0 * (1.0 + d), w0 / (1.0 + d)}) {
      const std::optional<double> fw = f(w);
      if (fw && (*fw > 0.0) != (*f0 > 0.0)) {
        a = std::min(w, w0), b = std::max(w, w0);
        fa = a == w0 ? *f0 : *fw;
        found = true;
        break;
      }
    }
  }
  if (!found) return std::nullopt;
  for (int it = 0; it < 200 && b - a > 2.0 * std::numeric_limits<double>::epsilon() * b; ++it) {
    const double m = 0.5 * (a + b);
    const std::optional<double> fm = f(m);
    if (!fm) return std::nullopt;
    if (*fm == 0.0) return m;
    if ((*fm > 0.0) == (fa > 0.0)) {
      a = m, fa = *fm;
    } else {
      b = m;
    }
  }
  // A sign change that is a jump (the phase's branch cut, where L is positive real), not
  // a root, is no crossing: f must vanish there to well within its own scale.
  const double w = 0.5 * (a + b);
  const std::optional<double> fw = f(w);
  if (!fw || std::abs(*fw) > 1e-6) return std::nullopt;
  return w;
}

std::optional<Complex> finite(const ExactResponse& exact, double w) {
  const std::optional<Complex> h = exact(w);
  if (!h || *h == Complex(0.0) || !std::isfinite(std::abs(*h))) return std::nullopt;
  return h;
}

// arg h on the branch nearest `model` (radians).
double branch(Complex h, double model) {
  const double a = std::arg(h);
  return a + 2.0 * M_PI * std::round((model - a) / (2.0 * M_PI));
}

}  // namespace

Margins margins(const Zpk& loop, const ExactResponse& exact) {
  Margins m = margins(loop);
  if (!exact) return m;
  const Scalar log_mag = [&](double w) -> std::optional<double> {
    const auto h = finite(exact, w);
    return h ? std::optional<double>(std::log(std::abs(*h))) : std::nullopt;
  };
  const Scalar phase = [&](double w) -> std::optional<double> {  // arg L - pi, in (-pi, pi]
    const auto h = finite(exact, w);
    return h ? std::optional<double>(std::arg(-*h)) : std::nullopt;
  };
  for (Crossing& c : m.gain_crossovers) {
    const auto w = refine(log_mag, c.w_rad_s);
    const auto h = w ? finite(exact, *w) : std::nullopt;
    if (!h) continue;
    c.w_rad_s = *w;
    double pm = std::remainder(180.0 + branch(*h, loop.log_response(*w).imag()) * kDeg, 360.0);
    c.margin = pm <= -180.0 ? pm + 360.0 : pm;
  }
  const bool discrete = loop.is_discrete();
  for (Crossing& c : m.phase_crossovers) {
    if (c.w_rad_s == 0.0 || (discrete && c.w_rad_s >= M_PI / loop.ts())) continue;  // DC, Nyquist: exact already
    const auto w = refine(phase, c.w_rad_s);
    const auto h = w ? finite(exact, *w) : std::nullopt;
    if (!h) continue;
    c.w_rad_s = *w;
    c.margin = -20.0 * std::log10(std::abs(*h));
  }
  m.gain_margin_db.reset();
  m.phase_margin_deg.reset();
  m.gain_crossover_rad_s.reset();
  m.phase_crossover_rad_s.reset();
  settle_margins(m);
  return m;
}

std::optional<double> bandwidth(const Zpk& g, const ExactResponse& exact, double drop_db) {
  const std::optional<double> w0 = bandwidth(g, drop_db);
  if (!w0 || !exact) return w0;
  const double level = std::log(std::abs(*g.dc_gain())) + drop_db / 20.0 * std::log(10.0);
  const Scalar f = [&](double w) -> std::optional<double> {
    const auto h = finite(exact, w);
    return h ? std::optional<double>(std::log(std::abs(*h)) - level) : std::nullopt;
  };
  const std::optional<double> w = refine(f, *w0);
  return w ? w : w0;
}

Bode bode(const Zpk& g, const std::vector<double>& w_rad_s, const ExactResponse& exact) {
  Bode b = bode(g, w_rad_s);
  if (!exact) return b;
  for (size_t k = 0; k < w_rad_s.size(); ++k) {
    const auto h = finite(exact, w_rad_s[k]);
    if (!h) continue;
    b.response[k] = *h;
    b.mag_db[k] = 20.0 * std::log10(std::abs(*h));
    b.phase_deg[k] = branch(*h, b.phase_deg[k] / kDeg) * kDeg;
  }
  return b;
}

}  // namespace dmbd::blocks
