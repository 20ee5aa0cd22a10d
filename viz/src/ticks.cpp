// Tick placement and tick-label formatting.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "dmbd/viz/plot.hpp"
#include "plot_detail.hpp"

namespace dmbd::viz {
namespace detail {

double pow10(int k) {
  static constexpr double kExact[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                      1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  if (k >= 0 && k <= 22) return kExact[k];
  if (k < 0 && k >= -22) return 1.0 / kExact[-k];
  return std::pow(10.0, k);
}

// m * 10^e for integer-valued m, rounded once (so 3 * 0.2 -> 0.6, not 0.6000000000000001).
double scaled(double m, int e) { return e >= 0 ? m * pow10(e) : m / pow10(-e); }
// Decomposes a 1-2-5 step into mantissa and exponent.
std::pair<double, int> split_step(double step) {
  int e = static_cast<int>(std::floor(std::log10(step)));
  double m = std::round(step / pow10(e));
  if (m >= 10) {
    m /= 10;
    ++e;
  }
  return {m, e};
}

double multiple_of(double k, double step) {
  if (!(step > 0) || !std::isfinite(step)) return k * step;
  const auto [m, e] = split_step(step);
  const bool decimal = std::abs(scaled(m, e) - step) <= 1e-12 * step;
  return (decimal ? scaled(k * m, e) : k * step) + 0.0;  // + 0.0 turns -0 into 0
}

double nice_step(double range, int max_intervals) {
  if (!(range > 0) || !std::isfinite(range)) return 0;
  const double raw = range / std::max(max_intervals, 1);
  const double lg = std::log10(raw);
  if (!std::isfinite(lg)) return 0;
  const int e = static_cast<int>(std::floor(lg));
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    const double step = scaled(m, e);
    if (step >= raw * (1 - 1e-12)) return std::isfinite(step) && step > 0 ? step : 0;
  }
  return 0;
}

std::vector<double> multiples_within(double lo, double hi, double step, int max_count) {
  std::vector<double> out;
  if (!(step > 0) || !std::isfinite(step) || !(lo <= hi)) return out;
  const double k0 = std::ceil(lo / step - 1e-9);
  const double k1 = std::floor(hi / step + 1e-9);
  if (!std::isfinite(k0) || !std::isfinite(k1) || k1 - k0 + 1 > max_count) return out;
  for (double k = k0; k <= k1; k += 1) {
    const double v = multiple_of(k, step);
    if (out.empty() || v > out.back()) out.push_back(v);
  }
  return out;
}

}  // namespace detail

std::vector<double> nice_ticks(double lo, double hi, int max_ticks) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) return {};
  if (lo > hi) std::swap(lo, hi);
  if (lo == hi) return {lo};
  max_ticks = std::max(max_ticks, 2);
  double step = detail::nice_step(hi - lo, max_ticks - 1);
  if (step == 0) return {lo, hi};
  // That step always fits; the next smaller one may too when the ends fall between
  // ticks ([-0.1, 3.1] with 4 ticks: 0, 1, 2, 3 rather than 0, 2).
  {
    const auto [m, e] = detail::split_step(step);
    const double smaller = m == 1 ? detail::scaled(5, e - 1) : detail::scaled(m == 2 ? 1 : 2, e);
    auto ticks = detail::multiples_within(lo, hi, smaller, max_ticks);
    if (ticks.size() >= 2) return ticks;
  }
  // The smallest 1-2-5 step >= range / intervals gives at most max_ticks ticks; the
  // loop only guards against rounding at the ends.
  for (int guard = 0; guard < 4; ++guard) {
    auto ticks = detail::multiples_within(lo, hi, step, max_ticks);
    if (!ticks.empty()) return ticks;
    step = detail::nice_step(step * 1.0000001, 1);
    if (step == 0) break;
  }
  return {lo, hi};
}

std::vector<double> log_ticks(double lo, double hi) {
  std::vector<double> out;
  if (!(lo > 0) || !std::isfinite(lo) || !std::isfinite(hi) || hi < lo) return out;
  const int k0 = static_cast<int>(std::ceil(std::log10(lo) - 1e-9));
  const int k1 = static_cast<int>(std::floor(std::log10(hi) + 1e-9));
  for (int k = k0; k <= k1; ++k) {
    const double v = detail::pow10(k);
    if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9)) out.push_back(v);
  }
  return out;
}

std::string format_tick(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  if (value == 0) return "0";
  const double a = std::abs(value);
  std::string s = fmt::format("{:.6g}", value);
  if (s.find('e') == std::string::npos) {
    // %g uses plain digits up to 999999.5; plain only below 1e5 here (99999.95 -> "100000").
    if (a >= 1e-4 && a < 1e5) return s;
    s = fmt::format("{:.5e}", value);
  }
  const auto pos = s.find('e');
  std::string mant = s.substr(0, pos);
  if (mant.find('.') != std::string::npos) {
    while (!mant.empty() && mant.back() == '0') mant.pop_back();
    if (!mant.empty() && mant.back() == '.') mant.pop_back();
  }
  std::string exp = s.substr(pos + 1);
  bool negative = false;
  if (!exp.empty() && (exp[0] == '+' || exp[0] == '-')) {
    negative = exp[0] == '-';
    exp.erase(0, 1);
  }
  exp.erase(0, std::min(exp.find_first_not_of('0'), exp.size() - 1));
  return mant + "e" + (negative ? "-" : "") + exp;
}

Color palette_color(std::size_t index) { return plot::palette_color(index); }

}  // namespace dmbd::viz
