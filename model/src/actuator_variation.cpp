// Variations of an actuator table after it is read: a named load set put in place of the
// entries' `load:` terms, and one parameter scaled on every entry (docs/actuator-format.md,
// "Load sets" and "Scaling"). The scenario applies them per run (robot.actuators).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "dmbd/base/number_text.hpp"
#include "dmbd/base/strings.hpp"
#include "dmbd/model/actuator.hpp"
#include "dmbd/model/error.hpp"

namespace dmbd::model {

namespace {

// A parameter by its symbol: the field and whether it must stay positive (a factor 0
// would leave a rotor without inertia, a spring without stiffness, a motor without torque).
struct Scalable {
  const char* symbol;
  double ActuatorParams::*field;
  bool positive;
};

const std::vector<Scalable>& table_of_scalables() {
  static const std::vector<Scalable> t = {
      {"J_m", &ActuatorParams::J_m_kgm2, true},
      {"B_m", &ActuatorParams::B_m_Nms, false},
      {"K_s", &ActuatorParams::K_s_N_per_m, true},
      {"B_s", &ActuatorParams::B_s_Ns_per_m, false},
      {"M_r", &ActuatorParams::M_r_kg, false},
      {"B_l", &ActuatorParams::B_l_Ns_per_m, false},
      {"k_tau", &ActuatorParams::k_tau_Nm_per_A, true},
      {"viscous_friction", &ActuatorParams::viscous_friction_Nms, false},
      {"coulomb_friction", &ActuatorParams::coulomb_friction_Nm, false},
  };
  return t;
}

// The set names the table's entries have, each once, in file order.
std::string set_names(const std::vector<ActuatorParams>& table) {
  std::vector<std::string> names;
  for (const auto& p : table)
    for (const auto& s : p.load_sets)
      if (std::find(names.begin(), names.end(), s.name) == names.end()) names.push_back(s.name);
  return names.empty() ? std::string("none") : join(names);
}

}  // namespace

void select_load_set(std::vector<ActuatorParams>& table, const std::string& name) {
  std::vector<std::string> missing;
  std::string first_where;
  for (ActuatorParams& p : table) {
    const auto it = std::find_if(p.load_sets.begin(), p.load_sets.end(), [&](const auto& s) { return s.name == name; });
    if (it != p.load_sets.end()) {
      p.B_l_Ns_per_m = it->B_l_Ns_per_m;
      continue;
    }
    missing.push_back("'" + p.joint + "'");
    if (first_where.empty()) first_where = p.where.empty() ? std::string("actuator table") : p.where;
  }
  if (!missing.empty())
    throw ModelError(first_where + ": " + (missing.size() == 1 ? "actuator " : "actuators ") + join(missing) + (missing.size() == 1 ? " has" : " have") +
                     " no load set '" + name + "' (the table's load sets: " + set_names(table) + ")");
}

const std::vector<std::string>& scalable_parameters() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const Scalable& s : table_of_scalables()) out.push_back(s.symbol);
    return out;
  }();
  return names;
}

void scale_parameter(std::vector<ActuatorParams>& table, const std::string& symbol, double factor) {
  const auto& t = table_of_scalables();
  const auto it = std::find_if(t.begin(), t.end(), [&](const Scalable& s) { return symbol == s.symbol; });
  if (it == t.end())
    throw ModelError("unknown actuator parameter '" + symbol + "' to scale (expected one of: " + join(scalable_parameters()) + ")");
  if (!std::isfinite(factor) || factor < 0 || (it->positive && factor == 0))
    throw ModelError("the scale of actuator parameter '" + symbol + "' must be " + (it->positive ? "> 0" : ">= 0") + ", got " +
                     number_text(factor));
  for (ActuatorParams& p : table) p.*(it->field) *= factor;
}

}  // namespace dmbd::model
