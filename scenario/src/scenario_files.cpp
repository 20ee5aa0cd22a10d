// The files a scenario reads: itself, its diagrams and their subsystems, a robot folder
// (not one of dmbd's own) or a URDF with its meshes, an actuator file.
#include "engine_names.hpp"
#include "dmbd/scenario/scenario_files.hpp"

#include <algorithm>
#include <filesystem>

#include "dmbd/diagrams/diagram.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/model/robot_folder.hpp"
#include "robot_cache.hpp"

namespace dmbd::scenario {

namespace {

namespace fs = std::filesystem;

void add(std::vector<std::string>& files, const std::string& path) {
  const std::string p = fs::absolute(path).lexically_normal().string();
  if (std::find(files.begin(), files.end(), p) == files.end()) files.push_back(p);
}

void add_diagram(std::vector<std::string>& files, const diagrams::Diagram& d) {
  add(files, d.file());
  for (const auto& b : d.blocks())
    if (b.subsystem) add_diagram(files, *b.subsystem);
}

void add_urdf(std::vector<std::string>& files, const std::string& urdf) {
  add(files, urdf);
  const model::RobotDescription& robot = *detail::cached_urdf(urdf);
  for (const auto& link : robot.links)
    for (const auto* shapes : {&link.visuals, &link.collisions})
      for (const auto& shape : *shapes)
        if (shape.geometry.mesh) add(files, shape.geometry.mesh->path);
}

}  // namespace

std::vector<std::string> scenario_files(const Scenario& s) {
  std::vector<std::string> files;
  add(files, s.file);
  for (const auto& v : s.variants) {
    for (const auto& c : v.controllers) {
      const std::size_t known = files.size();
      add(files, c.diagram);
      if (files.size() == known) continue;  // loaded for an earlier controller (its subsystems do not depend on parameters)
      blocks::ParameterMap overrides(c.parameters.begin(), c.parameters.end());
      add_diagram(files, *diagrams::Diagram::load(c.diagram, overrides));
    }
    // A robot folder of dmbd's own (installed, or the source tree's) is not listed: every
    // dmbd has it. Any other: its robot.yaml, URDF with meshes and actuator file.
    if (v.robot.folder && model::is_builtin_robot_dir(v.robot.folder->dir)) continue;
    if (v.robot.folder) add(files, v.robot.folder->file);
    add_urdf(files, v.robot.urdf);
    if (!v.robot.actuator_file.empty()) add(files, v.robot.actuator_file);
  }
  return files;
}

}  // namespace dmbd::scenario
