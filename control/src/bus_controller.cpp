// BusController: ports named after bus signals, tick timing (bus_controller.hpp).
#include "dmbd/control/bus_controller.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace dmbd::control {

BusController::BusController(const BusControllerOptions& options, long long max_ticks) : rate_hz_(options.rate_hz) {
  tick_us_.reserve(static_cast<std::size_t>(std::max(max_ticks, 1LL)));
}

void BusController::add_output(const std::string& signal, const std::string& unit) {
  outputs_.push_back(signal);
  units_.push_back(unit);
}

void BusController::step(const double* u, double* y) {
  const auto start = std::chrono::steady_clock::now();
  tick(u, y);
  ++ticks_;
  if (tick_us_.size() < tick_us_.capacity())
    tick_us_.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
}

void BusController::record(const model::Plant&, std::map<std::string, double>&) const {}

long long ticks_over(double duration_s, double rate_hz) { return static_cast<long long>(std::ceil(duration_s * rate_hz)) + 1; }

}  // namespace dmbd::control
