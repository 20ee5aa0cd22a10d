// Reading a scenario's bus controllers (docs/scenario-format.md, "bus_controllers"): each
// entry's type found in the registry (control/registry.hpp) and its options read over
// the defaults: an entry of the same name already there (the base scenario's, for a
// variant), else the robot folder's controllers.TYPE, else the type's own.
#include <fmt/format.h>

#include "dmbd/base/strings.hpp"
#include "engine_names.hpp"
#include "scenario_reader.hpp"

#include "dmbd/blocks/expression_numbers.hpp"
#include "dmbd/control/registry.hpp"

namespace dmbd::scenario::detail {

void Reader::bus_controllers(const YAML::Node& list, VariantSetup& v) const {
  if (!list.IsSequence()) fail(list, "bus_controllers: expected a list of {type: ..., ...}");
  each(list, [&](const YAML::Node& e) {
    if (!e.IsMap() || !e["type"]) fail(e, "bus_controllers: each entry needs a 'type' (one of: " + join(control::bus_controller_types()) + ")");
    bus_controller(e, text(e["type"], "bus_controllers.type"), v);
  });
}

void Reader::bus_controller(const YAML::Node& n, const std::string& type, VariantSetup& v) const {
  const control::BusControllerType* t = control::find_bus_controller(type);
  if (!t) fail(n["type"] ? n["type"] : n, "bus_controllers: unknown type '" + type + "' (one of: " + join(control::bus_controller_types()) + ")");
  const std::string name = n.IsMap() && n["name"] ? text(n["name"], type + ".name") : type;
  auto same = std::find_if(v.bus_controllers.begin(), v.bus_controllers.end(), [&](const auto& o) { return o->name == name; });
  std::shared_ptr<const control::BusControllerOptions> base;
  if (same != v.bus_controllers.end()) {
    if ((*same)->type != type) fail(n, fmt::format("bus_controllers: '{}' is a {} already, not a {}", name, (*same)->type, type));
    base = *same;
  } else if (v.robot.folder && v.robot.folder->controllers.IsMap() && v.robot.folder->controllers[type]) {
    // The robot folder's defaults, read from its robot.yaml (its problems named there).
    yaml::Reader folder_rd(v.robot.folder->file, blocks::expression_numbers());
    folder_rd.guard([&] { base = t->read(yaml::Fields(folder_rd), v.robot.folder->controllers[type], nullptr); });
    for (const auto& d : folder_rd.diagnostics()) rd.error(d.where, d.message);
    if (folder_rd.failed()) throw yaml::Skip{};
  }
  std::shared_ptr<control::BusControllerOptions> o = t->read(*this, n, base.get());
  o->name = name;
  if (same != v.bus_controllers.end()) *same = o;
  else v.bus_controllers.push_back(o);
}

}  // namespace dmbd::scenario::detail
