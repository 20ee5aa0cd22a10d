#include "dmbd/base/progress.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace dmbd {

std::optional<double> remaining_seconds(double elapsed_s, double fraction) {
  if (!(fraction > 0.0 && fraction <= 1.0) || !(elapsed_s >= 0.0) || !std::isfinite(elapsed_s)) return std::nullopt;
  if (fraction >= 1.0) return 0.0;
  if (elapsed_s < 1.0 || fraction < 0.02) return std::nullopt;
  return elapsed_s * (1.0 - fraction) / fraction;
}

std::string format_duration(std::optional<double> seconds) {
  if (!seconds || !std::isfinite(*seconds) || *seconds < 0.0) return "--";
  const long long s = std::llround(*seconds);
  char text[64];
  if (s < 60) {
    std::snprintf(text, sizeof text, "%lld s", s);
  } else if (s < 3600) {
    std::snprintf(text, sizeof text, "%lld min %02lld s", s / 60, s % 60);
  } else {
    const long long m = (s + 30) / 60;  // whole minutes beyond an hour
    std::snprintf(text, sizeof text, "%lld h %02lld min", m / 60, m % 60);
  }
  return text;
}

std::string progress_line(double fraction, const std::string& label, double elapsed_s) {
  const double f = std::clamp(std::isfinite(fraction) ? fraction : 0.0, 0.0, 1.0);
  const int width = 30, n = static_cast<int>(f * width);
  char text[256];
  std::snprintf(text, sizeof text, "[%s%s] %3d%%  %-24.24s %6.1f s  ETA %s",
                std::string(static_cast<std::size_t>(n), '#').c_str(),
                std::string(static_cast<std::size_t>(width - n), '.').c_str(), static_cast<int>(f * 100), label.c_str(),
                elapsed_s, format_duration(remaining_seconds(elapsed_s, f)).c_str());
  return text;
}

}  // namespace dmbd
