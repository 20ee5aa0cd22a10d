#pragma once
// The shipped robot folders for the tests: the source tree's robots/ (DMBD_ROBOTS_DIR,
// dmbd_model's public definition).
#include <string>

#include "dmbd/model/actuator.hpp"
#include "dmbd/model/robot_description.hpp"

namespace dmbd::test {

inline std::string robot_dir(const std::string& name) { return std::string(DMBD_ROBOTS_DIR) + "/" + name; }
inline std::string draco_dir() { return robot_dir("draco"); }
// DRACO's URDF and its actuator table.
inline std::string draco_urdf() { return draco_dir() + "/draco.urdf"; }
inline std::vector<model::ActuatorParams> draco_actuators(const NumberParser& numbers = plain_number) {
  return model::load_actuators(draco_dir() + "/actuators.yaml", numbers);
}

}  // namespace dmbd::test
