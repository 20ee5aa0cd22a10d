// What a variant would otherwise run with in silence (variant_checks.hpp).
#include "variant_checks.hpp"

#include <algorithm>
#include <set>

#include <fmt/format.h>

#include "dmbd/base/error.hpp"
#include "dmbd/base/strings.hpp"
#include "dmbd/experiments/registry.hpp"
#include "dmbd/scenario/evaluate.hpp"

namespace dmbd::scenario {

namespace {

std::string where_of(const Scenario& s, const RobotSetup& r, const std::string& key) {
  const auto it = r.where.find(key);
  return it == r.where.end() ? s.file : it->second;
}



// The plant's inputs: every joint's torque, every actuator's current.
std::set<std::string> plant_inputs(const model::Plant& plant) {
  std::set<std::string> in;
  for (const auto& j : plant.joint_names()) in.insert(j + ".torque");
  for (int k = 0; k < plant.num_actuators(); ++k) in.insert(plant.actuator(k).joint + ".current");
  return in;
}

// Every signal something reads: the controllers' inputs, the plots, the experiment's
// text keys, the overlays, the scenario's log: list.
std::set<std::string> read_signals(const Scenario& s, const VariantSetup& v, const SimulationSpec& spec) {
  std::set<std::string> r(s.log_signals.begin(), s.log_signals.end());
  for (const auto& c : spec.controllers) r.insert(c.inputs.begin(), c.inputs.end());
  for (const auto& p : s.plots)
    for (const auto& sig : p.signals) r.insert(sig.substr(sig.find(':') == std::string::npos ? 0 : sig.find(':') + 1));
  for (const auto& [key, value] : s.experiment.text) r.insert(value);
  for (const auto& o : variant_overlays(s, v)) r.insert(o.signals.begin(), o.signals.end());
  return r;
}

void check_limits(const std::string& where, const char* what, const model::Joint& j, double q) {
  if (j.has_limits && j.type != model::JointType::Continuous && (q < j.lower || q > j.upper))
    throw InputError(fmt::format("{}: robot.{}: joint '{}' at {} {}, outside its limits [{}, {}]", where, what, j.name, q,
                                 j.type == model::JointType::Prismatic ? "m" : "rad", j.lower, j.upper));
}

}  // namespace

void check_joint_angles(const Scenario& s, const RobotSetup& r, const model::RobotDescription& robot) {
  for (const auto& [list, what] : {std::make_pair(&r.initial, "initial"), std::make_pair(&r.lock, "lock")})
    for (const auto& [name, q] : *list)
      if (const int j = robot.joint_index(name); j >= 0)
        check_limits(where_of(s, r, std::string(what) + ":" + name), what, robot.joints[static_cast<std::size_t>(j)], q);
}

void check_experiment_names(const Scenario& s, const model::RobotDescription& robot) {
  const experiments::ExperimentSetup& e = s.experiment;
  const experiments::Experiment* exp = experiments::find_experiment(e.type);
  if (!exp) return;
  auto at = [&](const std::string& key) {
    const auto it = e.where.find(key);
    return it == e.where.end() ? s.file : it->second;
  };
  auto joint = [&](const std::string& key, const std::string& name) {
    if (robot.joint_index(name) < 0) throw InputError(at(key) + ": experiment." + key + ": the robot has no joint '" + name + "'");
  };
  if (!e.joint.empty()) joint("joint", e.joint);
  if (e.joint.empty() && exp->needs_joint()) throw InputError(at("type") + ": experiment " + e.type + ": expected 'joint' (the joint it looks at)");
  for (const auto& [key, kind] : exp->keys()) {
    if (kind == experiments::KeyKind::Joint && e.text.count(key)) joint(key, e.text.at(key));
    if (kind == experiments::KeyKind::Joints && e.names.count(key))
      for (const auto& n : e.names.at(key)) joint(key, n);
    if (kind == experiments::KeyKind::Link && e.text.count(key) && robot.link_index(e.text.at(key)) < 0)
      throw InputError(at(key) + ": experiment." + key + ": the robot has no link '" + e.text.at(key) + "'");
  }
}

void check_outputs_reach(const Scenario& s, const VariantSetup& v, const SimulationSpec& spec, const model::Plant& plant,
                         const std::vector<BusControllerRun>& bus) {
  const std::set<std::string> inputs = plant_inputs(plant), read = read_signals(s, v, spec);
  for (const auto& c : v.controllers)
    for (std::size_t k = 0; k < c.outputs.size(); ++k) {
      const std::string& sig = c.outputs[k].second;
      if (inputs.count(sig) || read.count(sig)) continue;
      const std::string at = k < c.output_where.size() && !c.output_where[k].empty() ? c.output_where[k] : c.where;
      throw InputError(fmt::format("{}: controller '{}': output '{}' is bound to '{}', which is no plant input and nothing reads (a controller, "
                                   "a plot, the experiment, an overlay, the scenario's log: list); the closest plant input is '{}'",
                                   at, c.name, c.outputs[k].first, sig, closest_name(sig, std::vector<std::string>(inputs.begin(), inputs.end()))));
    }
  for (const auto& b : bus)
    for (const auto& jc : b.controller->joint_commands())
      if (std::none_of(jc.signals.begin(), jc.signals.end(), [&](const std::string& x) { return inputs.count(x) || read.count(x); })) {
        const std::string list = join(jc.signals);
        throw InputError(fmt::format("{}: {}: the command for joint '{}' reaches nothing: no controller reads {} (the joint's own loop, "
                                     "e.g. a force or position controller among `controllers`)",
                                     b.options->where, b.options->name, jc.joint, list));
      }
}

}  // namespace dmbd::scenario
