#pragma once
// Robots are folders (docs/robot-folder.md): robots/NAME/ holds robot.yaml, the URDF and
// its meshes, the actuator file (docs/actuator-format.md) and the options of the robot's
// bus controllers (the feet, the torso, joint groups, gains). A scenario names a robot
// by NAME (found on the robot search path) or gives a URDF; no robot is built into the
// code.
//
// robot.yaml (format 1):
//   format: 1
//   name: DRACO                      # what reports call the robot (default: NAME)
//   urdf: draco.urdf                 # required, relative to the folder
//   actuators: actuators.yaml        # optional: the default actuator file
//   controllers: {TYPE: {...}, ...}  # optional: each bus controller type's defaults
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace dmbd::model {

struct RobotFolder {
  std::string name;          // the folder's name: what a scenario's robot.name says
  std::string display_name;  // `name`: what reports call the robot
  std::string dir;           // the folder (absolute, normalised)
  std::string file;          // its robot.yaml
  std::string urdf;          // `urdf`, resolved (it exists)
  std::string actuators;     // `actuators`, resolved ("" when not given)
  // `controllers`: bus controller type -> its options, as written (a null node when not
  // given); read by the types themselves (control/registry.hpp) with `file` in messages.
  YAML::Node controllers;
};

// The folders searched for a robot NAME (each holds NAME/robot.yaml), in order: `first`
// (the scenario's folder), then each folder of the environment variable
// DMBD_ROBOT_PATH (':'-separated), then the installed robots (<prefix>/share/dmbd/
// robots, `cmake --install`), then the robots/ folder of the source tree the library
// was built from.
std::vector<std::string> robot_search_path(const std::vector<std::string>& first = {});

// The robot NAME found on robot_search_path(first) and read. Throws ModelError "robot
// 'NAME' not found (searched: DIR, DIR, ...)", or robot.yaml's mistakes, each at its
// file:line:col.
RobotFolder find_robot(const std::string& name, const std::vector<std::string>& first = {});

// A robot folder read from `dir` (dir/robot.yaml). Throws ModelError as find_robot.
RobotFolder load_robot_folder(const std::string& dir);

// Whether `dir` is one of dmbd's own robot folders (installed or in the source tree):
// a copy of a scenario needs not carry it (every dmbd has it).
bool is_builtin_robot_dir(const std::string& dir);

}  // namespace dmbd::model
