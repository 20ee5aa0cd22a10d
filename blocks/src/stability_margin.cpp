#include "dmbd/blocks/stability_margin.hpp"

#include "golden_section.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dmbd::blocks {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::vector<double> sample_frequencies(const std::vector<Complex>& features, double ts) {
  std::vector<double> w = frequency_grid_around(features, ts, 2000);
  const double top = ts > 0.0 ? M_PI / ts : kInf;
  for (const Complex& r : features) {
    const Complex s = ts > 0.0 ? std::log(r) / ts : r;
    for (double v : {std::abs(s), std::abs(s.imag())})
      if (v > 0.0 && v <= top && std::isfinite(v)) w.push_back(v);
  }
  w.push_back(0.0);
  if (ts > 0.0) w.push_back(top);
  std::sort(w.begin(), w.end());
  w.erase(std::unique(w.begin(), w.end()), w.end());
  return w;
}

// The minimum of a locally unimodal f on [a, b] by golden-section search.
double golden_min(const std::function<double(double)>& f, double a, double b) { return golden_section(f, a, b, 1e-12, 300).best(); }

}  // namespace

StabilityMargin stability_margin(const std::function<Complex(double)>& loop_at, const std::vector<Complex>& features,
                                 double ts, Complex at_infinity) {
  const auto f = [&](double w) {
    const double v = std::abs(1.0 + loop_at(w));
    return std::isfinite(v) ? v : kInf;
  };
  const std::vector<double> w = sample_frequencies(features, ts);
  std::vector<double> fw(w.size());
  for (size_t k = 0; k < w.size(); ++k) fw[k] = f(w[k]);
  StabilityMargin out;
  const size_t last = w.size() - 1;
  for (size_t k = 0; k < w.size(); ++k) {
    if (!std::isfinite(fw[k])) continue;
    const bool below_left = k == 0 || fw[k] < fw[k - 1];
    const bool below_right = k == last || fw[k] <= fw[k + 1];
    if (!below_left || !below_right) continue;
    if (k == 0 || k == last) {
      out.minima.push_back({w[k], fw[k]});
      continue;
    }
    const double wm = golden_min(f, w[k - 1], w[k + 1]);
    const double fm = f(wm);
    out.minima.push_back(fm < fw[k] ? Crossing{wm, fm} : Crossing{w[k], fw[k]});
  }
  // Continuous: beyond the last sample |1 + L| tends to |1 + L(inf)|.
  const double f_inf = std::abs(1.0 + at_infinity);
  if (ts <= 0.0 && std::isfinite(f_inf) && (w.size() < 2 || fw[last] < fw[last - 1]) && f_inf <= fw[last]) {
    if (!out.minima.empty() && out.minima.back().w_rad_s == w[last]) out.minima.pop_back();
    out.minima.push_back({kInf, f_inf});
  }
  out.margin = kInf;
  out.w_rad_s = std::numeric_limits<double>::quiet_NaN();
  for (const Crossing& c : out.minima)
    if (c.margin < out.margin) {
      out.margin = c.margin;
      out.w_rad_s = c.w_rad_s;
    }
  return out;
}

}  // namespace dmbd::blocks
