#include "model_cmd.hpp"

#include "cli_values.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "dmbd/model/robot_folder.hpp"
#include "dmbd/model/error.hpp"
#include "dmbd/model/robot_description.hpp"

namespace dmbd::apps {

namespace {

namespace m = dmbd::model;


bool has_axis(m::JointType t) { return t != m::JointType::Fixed && t != m::JointType::Floating; }

// Numbers in text: 6 significant digits, no "-0".
std::string num(double v) { return fmt::format("{:.6g}", v == 0.0 ? 0.0 : v); }

nlohmann::json info_json(const m::RobotDescription& r, const m::ModelSummary& s) {
  nlohmann::json joints = nlohmann::json::array();
  for (const m::Joint& j : r.joints) {
    nlohmann::json o{{"name", j.name},   {"type", m::joint_type_name(j.type)}, {"parent", j.parent}, {"child", j.child},
                     {"lower", nullptr}, {"upper", nullptr},          {"axis", nullptr},    {"effort", nullptr},
                     {"velocity", nullptr}, {"damping", j.damping},   {"friction", j.friction}};
    if (j.has_limits) {
      o["lower"] = j.lower;
      o["upper"] = j.upper;
    }
    if (has_axis(j.type)) o["axis"] = {j.axis.x(), j.axis.y(), j.axis.z()};
    if (j.effort > 0) o["effort"] = j.effort;
    if (j.velocity > 0) o["velocity"] = j.velocity;
    joints.push_back(o);
  }
  nlohmann::json repairs = nlohmann::json::array();
  for (const m::Repair& rp : r.repairs)
    repairs.push_back({{"link", rp.link}, {"kind", rp.kind}, {"before", rp.before}, {"after", rp.after}, {"what", rp.what}});
  nlohmann::json links = nlohmann::json::array();
  for (const m::Link& l : r.links) links.push_back({{"name", l.name}, {"mass_kg", l.mass_kg}});
  return {{"name", s.name},
          {"source", r.source},
          {"root", r.links.empty() ? std::string() : r.links.front().name},
          {"links", s.links},
          {"dof", s.dof},
          {"joint_counts",
           {{"fixed", s.fixed},
            {"revolute", s.revolute},
            {"continuous", s.continuous},
            {"prismatic", s.prismatic},
            {"floating", s.floating},
            {"planar", s.planar}}},
          {"joints", joints},
          {"link_masses", links},
          {"total_mass_kg", s.total_mass_kg},
          {"height_m", s.height_m},
          {"meshes_loaded", s.meshes_loaded},
          {"meshes_missing", s.meshes_missing},
          {"repairs", repairs},
          {"warnings", r.warnings}};
}

std::string info_text(const m::RobotDescription& r, const m::ModelSummary& s) {
  std::ostringstream o;
  o << "robot '" << s.name << "' (" << r.source << ")\n";
  auto row = [&](const char* key, const std::string& value) { o << fmt::format("  {:<8} {}\n", key, value); };
  row("links", std::to_string(s.links) + (r.links.empty() ? "" : " (root " + r.links.front().name + ")"));
  row("dof", std::to_string(s.dof) + " (revolute + continuous + prismatic)");
  row("joints", fmt::format("{}: fixed {}, revolute {}, continuous {}, prismatic {}, floating {}, planar {}",
                            r.joints.size(), s.fixed, s.revolute, s.continuous, s.prismatic, s.floating, s.planar));
  row("mass", num(s.total_mass_kg) + " kg");
  row("height", num(s.height_m) + " m (visual geometry, every joint at 0)");
  row("meshes", fmt::format("{} loaded, {} missing", s.meshes_loaded, s.meshes_missing.size()));
  for (const std::string& u : s.meshes_missing) o << "           missing: " << u << "\n";
  if (!r.joints.empty()) {
    // One row per joint, columns as wide as their widest cell.
    std::vector<std::array<std::string, 8>> rows;
    rows.push_back({"joint", "type", "parent -> child", "lower", "upper", "effort", "velocity", "axis"});
    for (const m::Joint& j : r.joints) {
      const bool lin = j.type == m::JointType::Prismatic;
      const std::string u = lin ? " m" : " rad";
      rows.push_back({j.name, m::joint_type_name(j.type), j.parent + " -> " + j.child, j.has_limits ? num(j.lower) + u : "-",
                      j.has_limits ? num(j.upper) + u : "-", j.effort > 0 ? num(j.effort) + (lin ? " N" : " N m") : "-",
                      j.velocity > 0 ? num(j.velocity) + (lin ? " m/s" : " rad/s") : "-",
                      has_axis(j.type) ? num(j.axis.x()) + " " + num(j.axis.y()) + " " + num(j.axis.z()) : "-"});
    }
    std::array<std::size_t, 8> w{};
    for (const auto& rw : rows)
      for (std::size_t c = 0; c < w.size(); ++c) w[c] = std::max(w[c], rw[c].size());
    o << "\n";
    for (const auto& rw : rows) {
      std::string line = " ";
      for (std::size_t c = 0; c < w.size(); ++c) {
        const bool right = c >= 3 && c <= 6;  // numbers
        line += " " + (right ? fmt::format("{:>{}}", rw[c], w[c]) : fmt::format("{:<{}}", rw[c], w[c]));
      }
      while (!line.empty() && line.back() == ' ') line.pop_back();
      o << line << "\n";
    }
  }
  return o.str();
}

}  // namespace

ModelCommand::ModelCommand(CLI::App& app) : Command(app, "model", "Robot descriptions (URDF): summaries and checks") {
  cmd_->require_subcommand(1);
  info_ = cmd_->add_subcommand(
      "info", "Summary of a URDF: links, degrees of freedom, joints with limits and axes, mass, height, meshes");
  info_->add_option("urdf", urdf_, "The URDF file (or --robot)");
  info_->add_option("--robot", robot_, "A robot folder by name, found on the robot search path (docs/robot-folder.md)");
  info_->add_flag("--json", json_, "Print one JSON object instead of the table");
  info_->add_option("--package-path", package_paths_,
                    "Folder searched for package://NAME/PATH meshes (as DIR/NAME/PATH, then DIR/PATH); repeatable. "
                    "The URDF's folder and its parents are searched after these")
      ->allow_extra_args(false);  // one folder per --package-path: `--package-path DIR file.urdf` works
  info_->add_flag("--strict", strict_,
                  "A mesh that cannot be found or read is an error, and so is an inertia or a mass that would be "
                  "repaired (default: a warning; docs/model.md, Repairs)");
  workspace_ = std::make_unique<ModelWorkspace>(*cmd_);
}

int ModelCommand::run() {
  if (workspace_->selected()) return workspace_->run();
  m::UrdfOptions options;
  options.package_paths = package_paths_;
  options.strict = strict_;
  const m::RobotDescription robot = m::load_urdf(urdf_path(urdf_, robot_), options);
  const m::ModelSummary summary = m::summarize(robot);
  // Everything is computed before anything is printed: a failure prints no half report.
  const std::string out = json_ ? info_json(robot, summary).dump() + "\n" : info_text(robot, summary);
  for (const std::string& w : robot.warnings) std::cerr << "warning: " << w << "\n";
  std::cout << out << std::flush;
  return 0;
}

}  // namespace dmbd::apps
