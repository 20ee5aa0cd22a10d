// A scenario's variant's robot and plant options (variant_plant). Running it:
// variant_run.cpp; reading the file: scenario_load.cpp.
#include "engine_names.hpp"
#include "dmbd/scenario/scenario.hpp"

#include "robot_cache.hpp"
#include "variant_checks.hpp"
#include "variant_controllers.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include <fmt/format.h>

#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/expression_numbers.hpp"
#include "dmbd/codegen/fixed.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "dmbd/model/actuator.hpp"
#include "dmbd/control/registry.hpp"
#include "dmbd/experiments/registry.hpp"
#include "dmbd/model/error.hpp"
#include "dmbd/model/robot_description.hpp"

namespace dmbd::scenario {

namespace {

model::RobotDescription load_robot(const RobotSetup& r) { return *detail::cached_urdf(r.urdf); }

// robot.actuators' `load` (a named load set of the file) and `scale` (a parameter of every
// entry times a factor), in that order; a mistake is an error at its scenario line.
template <class Where>
void vary_actuators(const RobotSetup& r, std::vector<model::ActuatorParams>& table, const Where& where) {
  if (!r.actuator_load_set.empty()) {
    try {
      model::select_load_set(table, r.actuator_load_set);
    } catch (const model::ModelError& e) {
      throw InputError(where("actuators.load") + ": robot.actuators.load: " + e.what());
    }
  }
  for (const auto& [symbol, factor] : r.actuator_scales) {
    try {
      model::scale_parameter(table, symbol, factor);
    } catch (const model::ModelError& e) {
      throw InputError(where("actuators.scale:" + symbol) + ": robot.actuators.scale: " + e.what());
    }
  }
}

}  // namespace

VariantPlant variant_plant(const Scenario& s, const VariantSetup& v) {
  const RobotSetup& r = v.robot;
  // Where an entry of robot: was written (its file:line:col), else the scenario file.
  auto where = [&](const std::string& key) {
    const auto it = r.where.find(key);
    return it == r.where.end() ? s.file : it->second;
  };
  model::RobotDescription robot = load_robot(r);
  check_joint_angles(s, r, robot);
  const model::RobotDescription as_loaded = robot;  // the actuator file is checked against it (welded joints are its joints)
  // Welded joints.
  std::vector<std::pair<std::string, double>> freeze = r.freeze;
  if (r.freeze_all_others)
    for (const auto& j : robot.joints) {
      const bool one_dof = j.type == model::JointType::Revolute || j.type == model::JointType::Continuous || j.type == model::JointType::Prismatic;
      if (!one_dof || std::count(r.moving.begin(), r.moving.end(), j.name)) continue;
      if (std::any_of(freeze.begin(), freeze.end(), [&](const auto& f) { return f.first == j.name; })) continue;
      freeze.emplace_back(j.name, j.has_limits ? std::clamp(0.0, j.lower, j.upper) : 0.0);
    }
  for (const auto& m : r.moving)
    if (robot.joint_index(m) < 0) throw InputError(where("moving:" + m) + ": robot.moving: the robot has no joint '" + m + "'");
  // The explicit welds, each checked where it was written (freeze_joints checks again).
  for (const auto& [name, q] : r.freeze) {
    const int j = robot.joint_index(name);
    if (j < 0) throw InputError(where("freeze:" + name) + ": robot.freeze: the robot has no joint '" + name + "'");
    const model::Joint& J = robot.joints[static_cast<std::size_t>(j)];
    if (J.has_limits && (q < J.lower || q > J.upper))
      throw InputError(fmt::format("{}: robot.freeze: joint '{}' welded at {} rad, outside its limits [{}, {}]", where("freeze:" + name), name, q,
                                   J.lower, J.upper));
  }
  try {
    robot = model::freeze_joints(robot, freeze);
  } catch (model::ModelError& e) {
    e.prepend(s.file + ": robot.freeze: ");
    throw;
  }
  for (const auto& p : r.payloads) {
    if (robot.link_index(p.link) < 0) throw InputError(where("payloads:" + p.link) + ": robot.payloads: the robot has no link '" + p.link + "'");
    model::add_payload(robot, p.link, p.mass_kg, p.com_L, p.inertia_kgm2);
  }

  // Actuators.
  std::vector<model::ActuatorParams> table;
  if (r.all_actuators || !r.actuators.empty()) {
    if (r.actuator_file.empty())
      throw InputError(where("actuators") + ": robot.actuators: no actuator file: the robot folder names none; give robot.actuators: "
                                            "{file: FILE, joints: all} (docs/actuator-format.md)");
    table = model::load_actuators(r.actuator_file, blocks::expression_numbers());
    model::check_actuators_against(table, as_loaded);
    vary_actuators(r, table, where);
  }
  model::PlantOptions po;
  po.base = r.base;
  po.X_WB = r.X_WB;
  po.gravity_m_s2 = r.gravity_m_s2;
  po.contact = r.contact;
  po.ground_normal = r.ground_normal;
  po.integration = v.integration.mode;
  po.step_s = v.integration.step_s;
  po.accuracy = v.integration.accuracy;
  for (const auto& a : table) {
    const bool wanted = r.all_actuators || std::count(r.actuators.begin(), r.actuators.end(), a.joint);
    const int j = robot.joint_index(a.joint);
    if (wanted && j >= 0 && robot.joints[static_cast<std::size_t>(j)].type != model::JointType::Fixed) po.actuators.push_back(a);
  }
  for (const auto& name : r.actuators)
    if (!std::any_of(po.actuators.begin(), po.actuators.end(), [&](const auto& a) { return a.joint == name; }))
      throw InputError(where("actuators:" + name) + ": robot.actuators: '" + name + "' is not a moving joint with an actuator");

  for (const auto& entry : r.armature) {  // not a structured binding: the lambda below captures the name (C++17)
    const std::string& name = entry.first;
    const int j = robot.joint_index(name);
    if (j < 0 || robot.joints[static_cast<std::size_t>(j)].type == model::JointType::Fixed)
      throw InputError(where("armature:" + name) + ": robot.armature: '" + name + "' is not a moving joint");
    if (std::any_of(po.actuators.begin(), po.actuators.end(), [&](const auto& a) { return a.joint == name; }))
      throw InputError(where("armature:" + name) + ": robot.armature: '" + name + "' is driven by its actuator, whose rotor is already modelled");
    robot.joints[static_cast<std::size_t>(j)].armature = entry.second;
  }

  auto initial_of = [&](const std::string& joint) { return initial_angle(r, joint); };
  // Reflected loads: a disc on the joint axis (added to the child link at the joint origin).
  for (const auto& load : r.loads) {
    const int j = robot.joint_index(load.joint);
    const auto act = std::find_if(po.actuators.begin(), po.actuators.end(), [&](const auto& a) { return a.joint == load.joint; });
    if (j < 0 || act == po.actuators.end())
      throw InputError(where("loads:" + load.joint) + ": robot.loads: '" + load.joint + "' is not an actuated moving joint");
    const double n_l = act->N_l(initial_of(load.joint));
    const double need = load.reflected_mass_kg / (n_l * n_l) - model::subtree_axis_inertia(robot, j);
    if (need < 0)
      throw InputError(fmt::format("{}: robot.loads: {} kg reflected is less than the bare link's {:.1f} kg", where("loads:" + load.joint), load.reflected_mass_kg,
                                   model::subtree_axis_inertia(robot, j) * n_l * n_l));
    const model::Joint& J = robot.joints[static_cast<std::size_t>(j)];
    const Eigen::Vector3d ax = J.axis.cwiseAbs();
    // A thin 10 kg disc about the axis, centred on it (no gravity torque).
    model::add_payload(robot, J.child, 10.0, Eigen::Vector3d::Zero(), need * ax + 0.5 * need * (Eigen::Vector3d::Ones() - ax));
  }
  return {std::move(robot), po};
}

double initial_angle(const RobotSetup& r, const std::string& joint) {
  for (const auto& [n, q] : r.initial)
    if (n == joint) return q;
  for (const auto& [n, q] : r.lock)
    if (n == joint) return q;
  return 0.0;
}

}  // namespace dmbd::scenario
