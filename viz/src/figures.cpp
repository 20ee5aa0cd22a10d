// Ready-made figures for `dmbd analyze`: Bode and step response.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "dmbd/viz/plot.hpp"

namespace dmbd::viz {
namespace {

struct Extent {
  double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
  bool empty() const { return !(lo <= hi); }
  void add(double v) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
};

// 4 significant digits in format_tick's style: 60.0123 -> "60.01", 1234.5 -> "1235".
std::string short_number(double v) { return format_tick(std::stod(fmt::format("{:.4g}", v))); }

}  // namespace

Figure bode_figure(const std::vector<double>& freq_hz, const std::vector<double>& mag_db,
                   const std::vector<double>& phase_deg, const std::string& title,
                   std::optional<double> gain_crossover_hz, std::optional<double> phase_crossover_hz) {
  if (mag_db.size() != freq_hz.size() || phase_deg.size() != freq_hz.size())
    throw std::invalid_argument(
        fmt::format("viz: bode_figure needs one magnitude and one phase per frequency, got "
                    "{} frequencies, {} magnitudes, {} phases",
                    freq_hz.size(), mag_db.size(), phase_deg.size()));
  Figure fig(1000, 700);
  fig.title = title;
  fig.add_axes();
  fig.add_axes();
  Axes& mag = fig.axes()[0];
  Axes& phase = fig.axes()[1];

  // Shared frequency axis: whole decades around the positive frequencies.
  Extent f, p;
  for (std::size_t i = 0; i < freq_hz.size(); ++i) {
    if (!(freq_hz[i] > 0) || !std::isfinite(freq_hz[i])) continue;
    f.add(freq_hz[i]);
    if (std::isfinite(phase_deg[i])) p.add(phase_deg[i]);
  }
  for (Axes* ax : {&mag, &phase}) {
    ax->x_scale = Scale::Log;
    if (!f.empty()) ax->x_limits = nice_limits(f.lo, f.hi, Scale::Log);
  }

  mag.y_label = "Magnitude (dB)";
  mag.x_tick_labels = false;  // shared with the phase axes below
  mag.series.push_back(Series{"", freq_hz, mag_db});
  mag.h_lines = {0.0};

  phase.y_label = "Phase (deg)";
  phase.x_label = "Frequency (Hz)";
  phase.series.push_back(Series{"", freq_hz, phase_deg});
  phase.h_lines = {-180.0};
  // Ticks at multiples of 45 deg (90 deg for wide ranges) when the range allows,
  // limits a little beyond the data on multiples of a third of that.
  if (!p.empty() && p.hi - p.lo >= 60) {
    const double range = p.hi - p.lo;
    const double step = range <= 400 ? 45 : 90;
    const double unit = step / 3;
    phase.y_tick_step = step;
    phase.y_limits =
        std::make_pair(std::floor((p.lo - 0.03 * range) / unit) * unit, std::ceil((p.hi + 0.03 * range) / unit) * unit);
  }

  const auto add_crossover = [&](std::optional<double> hz, const char* name) {
    if (!hz || !std::isfinite(*hz) || !(*hz > 0)) return;
    for (Axes* ax : {&mag, &phase}) ax->v_lines.push_back(*hz);
    mag.v_line_labels.push_back(fmt::format("{} {} Hz", name, short_number(*hz)));
  };
  add_crossover(gain_crossover_hz, "gain crossover");
  add_crossover(phase_crossover_hz, "phase crossover");
  return fig;
}

Figure step_figure(const std::vector<double>& t_s, const std::vector<double>& y, const std::string& title,
                   std::optional<double> final_value, const std::string& y_label) {
  if (y.size() != t_s.size())
    throw std::invalid_argument(
        fmt::format("viz: step_figure needs one output per time, got {} times and {} outputs", t_s.size(), y.size()));
  Figure fig(1000, 700);
  fig.title = title;
  Axes& ax = fig.add_axes();
  ax.x_label = "Time (s)";
  ax.y_label = y_label;
  ax.series.push_back(Series{"", t_s, y});

  Extent t, v;
  for (std::size_t i = 0; i < t_s.size(); ++i) {
    if (!std::isfinite(t_s[i]) || !std::isfinite(y[i])) continue;
    t.add(t_s[i]);
    v.add(y[i]);
  }
  const bool show_final = final_value && std::isfinite(*final_value);
  if (show_final) v.add(*final_value);
  if (!t.empty() && t.lo < t.hi) ax.x_limits = std::make_pair(t.lo, t.hi);  // time axis exactly as simulated
  if (!v.empty()) ax.y_limits = nice_limits(v.lo, v.hi, Scale::Linear);     // keeps the final value in view
  if (show_final) {
    ax.h_lines = {*final_value};
    ax.h_line_labels = {"final value " + short_number(*final_value)};
  }
  return fig;
}

}  // namespace dmbd::viz
