#pragma once
// The co-simulation's event grid counts nanoseconds (simulation.cpp): a rate must have
// a whole number of nanoseconds per period and a run must end before 1e9 s. The
// scenario reader checks both at the line that gives the value; the simulation checks
// them again for a spec built in code.
#include <cmath>
#include <cstdint>
#include <string>

#include <fmt/format.h>

namespace dmbd::sim {

// The longest run the nanosecond grid holds, s.
constexpr double kMaxDurationS = 1e9;

// Why `rate_hz` cannot be a rate of the grid ("" when it can), e.g. "a rate of 1500.5
// Hz is not a whole number of nanoseconds per period".
inline std::string rate_problem(double rate_hz) {
  if (!(rate_hz > 0) || !std::isfinite(rate_hz)) return fmt::format("rate {} Hz is not positive", rate_hz);
  const double p = 1e9 / rate_hz;
  const auto r = static_cast<std::int64_t>(std::llround(p));
  // An absolute tolerance (a millionth of a nanosecond, or the rounding of 1e9 / rate
  // for very long periods): 1500 Hz is 666666.67 ns, which would tick at 1500.0008 Hz
  // while the program was discretised at 1500 Hz.
  if (r <= 0 || std::abs(p - static_cast<double>(r)) > std::max(1e-6, 1e-12 * p))
    return fmt::format("a rate of {} Hz is not a whole number of nanoseconds per period", rate_hz);
  return "";
}

}  // namespace dmbd::sim
