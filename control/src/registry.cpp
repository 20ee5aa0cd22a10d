// The bus controller registry (registry.hpp): the built-in types, one line each, and
// the common options.
#include "dmbd/control/registry.hpp"


#include <fmt/format.h>

#include "builtin_types.hpp"
#include "dmbd/base/registry.hpp"
#include "dmbd/sim/event_grid.hpp"

namespace dmbd::control {

namespace {

Registry<BusControllerType>& types() {
  static Registry<BusControllerType> t({
      {"osc", detail::osc_type()},          // operational space control (osc_controller.hpp)
      {"balance", detail::balance_type()},  // balancing by stepping (balance_controller.hpp)
  });
  return t;
}

}  // namespace

void register_bus_controller(const std::string& type, std::shared_ptr<const BusControllerType> t) { types().add(type, std::move(t)); }
const BusControllerType* find_bus_controller(const std::string& type) { return types().find(type); }
std::vector<std::string> bus_controller_types() { return types().names(); }

std::vector<sim::Overlay> BusControllerType::overlays(const BusControllerOptions&) const { return {}; }

std::vector<const char*> common_option_keys() { return {"type", "name", "rate_hz", "delay_s", "assumed_load_set"}; }

void read_common_options(const yaml::Fields& f, const YAML::Node& n, BusControllerOptions& o) {
  const std::string what = o.type;
  f.optional(n, "name", [&](const YAML::Node& x) { o.name = f.text(x, what + ".name"); });
  f.optional(n, "rate_hz", [&](const YAML::Node& r) {
    const double rate = f.positive(r, what + ".rate_hz");
    if (const std::string problem = sim::rate_problem(rate); !problem.empty()) f.fail(r, what + ".rate_hz: " + problem);
    o.rate_hz = rate;
  });
  f.optional(n, "delay_s", [&](const YAML::Node& d) {
    const double delay = f.number_in(d, what + ".delay_s", 0.0, 1e9, "s");
    if (delay > 1.0 / o.rate_hz)
      f.fail(d, fmt::format("{}.delay_s: {} s is longer than one period of {} Hz ({} s)", what, delay, o.rate_hz, 1.0 / o.rate_hz));
    o.delay_s = delay;
  });
  f.optional(n, "assumed_load_set", [&](const YAML::Node& x) {
    o.assumed_load_set = f.text(x, what + ".assumed_load_set");
    o.assumed_load_set_where = f.at(x);
  });
}

}  // namespace dmbd::control
