// What a user should read before a scenario's runs (scenario_notes, scenario.hpp).
#include <set>

#include <fmt/format.h>

#include "dmbd/base/strings.hpp"
#include "dmbd/blocks/expression_numbers.hpp"
#include "dmbd/model/actuator.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/scenario/scenario.hpp"
#include "robot_cache.hpp"

namespace dmbd::scenario {

std::vector<std::string> scenario_notes(const Scenario& s) {
  std::vector<std::string> out;
  for (const auto& n : s.notes) out.push_back("note: " + n);
  std::set<std::string> urdfs, tables;
  for (const auto& v : s.variants) {
    const RobotSetup& r = v.robot;
    if (r.urdf.empty() || !urdfs.insert(r.urdf).second) continue;
    const model::RobotDescription& robot = *detail::cached_urdf(r.urdf);
    for (const auto& w : robot.warnings) out.push_back("warning: " + w);
    if (!r.all_actuators || r.actuator_file.empty() || !tables.insert(r.urdf + "\n" + r.actuator_file).second) continue;
    const auto ideal = model::joints_without_actuator(model::load_actuators(r.actuator_file, blocks::expression_numbers()), robot);
    if (!ideal.empty())
      out.push_back(fmt::format("note: {}: {} joint(s) without an entry in {}, driven by ideal joint torques: {}", s.file, ideal.size(),
                                r.actuator_file, join(ideal)));
  }
  return out;
}

}  // namespace dmbd::scenario
