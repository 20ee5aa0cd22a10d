#pragma once
// DRACO's bus controller options as its robot folder gives them (robots/draco/robot.yaml,
// controllers.TYPE), read by the type's own reader: what a scenario naming DRACO starts
// from, for the tests and benchmarks that build a controller in code.
#include <stdexcept>
#include <string>

#include "dmbd/base/yaml_fields.hpp"
#include "dmbd/control/balance_controller.hpp"
#include "dmbd/control/osc_controller.hpp"
#include "dmbd/control/registry.hpp"
#include "dmbd/model/robot_folder.hpp"

namespace dmbd::test {

template <class T>
T draco_options(const std::string& type) {
  const model::RobotFolder folder = model::find_robot("draco");
  yaml::Reader rd(folder.file);
  const auto o = control::find_bus_controller(type)->read(yaml::Fields(rd), folder.controllers[type], nullptr);
  if (rd.failed()) throw std::runtime_error(join_plain(rd.diagnostics()));
  return dynamic_cast<const T&>(*o);
}

inline control::BalanceSetup draco_balance_names() { return draco_options<control::BalanceSetup>("balance"); }
inline control::OscSetup draco_osc_options() { return draco_options<control::OscSetup>("osc"); }

}  // namespace dmbd::test
