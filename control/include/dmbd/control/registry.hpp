#pragma once
// The bus controller types a scenario can name (`bus_controllers: [{type: T, ...}]`,
// docs/scenario-format.md): one registry, the built-in types (osc, balance) listed in
// registry.cpp, one line each, and types registered at run time (a test's, a Python
// controller's). A type reads its options from YAML (over defaults: the robot folder's
// controllers.T, then the scenario's, then a variant's, key by key) and builds its
// controller for a variant's robot and plant.
#include <memory>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "dmbd/base/yaml_fields.hpp"
#include "dmbd/control/bus_controller.hpp"
#include "dmbd/sim/overlay.hpp"

namespace dmbd::control {

// A bus controller type: reads its options, builds its controller, says what to draw.
class BusControllerType {
 public:
  virtual ~BusControllerType() = default;
  // The options of one map, read over `base` (the type's defaults when null): every key
  // given replaces base's value, key by key. A problem is recorded in fields' reader at
  // its line (then yaml::Skip); an unknown key is one (read_common_options's keys and
  // the type's own are known).
  virtual std::shared_ptr<BusControllerOptions> read(const yaml::Fields& fields, const YAML::Node& node,
                                                     const BusControllerOptions* base) const = 0;
  // The controller for a variant. Throws InputError (at options.where) when the variant
  // cannot have it (a fixed base for balancing, a name the robot does not have, an
  // option that is not set).
  virtual std::shared_ptr<BusController> make(const BusControllerOptions& options, const BusControllerContext& context) const = 0;
  // What the frames draw for a controller with these options (none by default).
  virtual std::vector<sim::Overlay> overlays(const BusControllerOptions& options) const;
};

// The keys every bus controller has: type (checked by the caller), name, rate_hz
// (a whole number of nanoseconds per period) and delay_s (0 to one period), read from
// node into o. Keys of `node` it does not read are left to the type.
void read_common_options(const yaml::Fields& fields, const YAML::Node& node, BusControllerOptions& o);
// The common keys' names, for a type's list of allowed keys.
std::vector<const char*> common_option_keys();

// Registers (or replaces) a type under `type`. Not thread-safe against concurrent lookups.
void register_bus_controller(const std::string& type, std::shared_ptr<const BusControllerType> t);
// The type registered under `type`, or null.
const BusControllerType* find_bus_controller(const std::string& type);
// Every registered type's name, sorted.
std::vector<std::string> bus_controller_types();

}  // namespace dmbd::control
