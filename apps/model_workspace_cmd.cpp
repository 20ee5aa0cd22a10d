#include "model_workspace_cmd.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <string>
#include <system_error>
#include <vector>

#include "cli_values.hpp"
#include "dmbd/base/error.hpp"
#include "dmbd/base/file.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/model/workspace.hpp"
#include "dmbd/report/range_of_motion.hpp"
#include "dmbd/viz/heat_map.hpp"

namespace dmbd::apps {

namespace {

namespace m = dmbd::model;
namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;
const char* const kAxis[] = {"x", "y", "z"};

struct Plane {
  const char* file;  // in --out
  const char* name;  // for titles
  int h, v;          // coordinate axes
};
const Plane kPlanes[] = {{"workspace_xz.png", "sagittal", 0, 2}, {"workspace_yz.png", "frontal", 1, 2}};
const char* const kRomFile = "range_of_motion.png";
const char* const kJsonFile = "workspace.json";

// The output folder (made when missing) and its files, checked before any work.
void prepare_out(const std::string& out) {
  std::error_code ec;
  if (!fs::exists(out, ec)) fs::create_directories(out, ec);
  if (ec) throw OutputError("--out '" + out + "': cannot create the folder: " + ec.message());
  check_output_folder(out, "--out");
  for (const Plane& p : kPlanes) check_output_file((fs::path(out) / p.file).string(), "--out");
  check_output_file((fs::path(out) / kRomFile).string(), "--out");
  check_output_file((fs::path(out) / kJsonFile).string(), "--out");
}

viz::HeatMap heat_map(const m::Workspace& ws, const m::DensityGrid& g, const Plane& p) {
  viz::HeatMap map;
  map.title = fmt::format("{} workspace relative to {}, {} plane ({}-{}): {} samples, seed {}", ws.link,
                          ws.reference, p.name, kAxis[p.h], kAxis[p.v], ws.samples, ws.seed);
  map.x_label = fmt::format("{} (m)", kAxis[p.h]);
  map.y_label = fmt::format("{} (m)", kAxis[p.v]);
  map.colorbar_label = fmt::format("density score: samples per {:g} cm cell / {:g}", g.cell_m * 100, g.max_count);
  map.x0 = g.h0, map.y0 = g.v0, map.cell_w = map.cell_h = g.cell_m;
  map.cols = g.cols, map.rows = g.rows;
  map.values.reserve(g.counts.size());
  for (double n : g.counts) map.values.push_back(n / g.max_count);
  return map;
}

nlohmann::json grid_json(const m::DensityGrid& g, const Plane& p) {
  return {{"file", p.file},         {"plane", std::string(kAxis[p.h]) + kAxis[p.v]},
          {"cell_m", g.cell_m},     {"origin_m", {g.h0, g.v0}},
          {"cols", g.cols},         {"rows", g.rows},
          {"max_count", g.max_count}, {"density_score", "samples per cell / max_count"}};
}

nlohmann::json workspace_json(const m::RobotDescription& robot, const m::Workspace& ws,
                              const std::vector<m::DensityGrid>& grids) {
  nlohmann::json joints = nlohmann::json::array(), extents, maps = nlohmann::json::array();
  for (const m::ChainJoint& c : ws.chain)
    joints.push_back({{"name", c.name},
                      {"lower", c.lower},
                      {"upper", c.upper},
                      {"range_rad", c.upper - c.lower},
                      {"range_deg", (c.upper - c.lower) * 180 / kPi},
                      {"limits", c.unlimited ? "none: sampled over [-pi, pi]" : "URDF"}});
  for (int k = 0; k < 3; ++k) extents[kAxis[k]] = {{"min_m", ws.min[k]}, {"max_m", ws.max[k]}};
  for (std::size_t i = 0; i < grids.size(); ++i) maps.push_back(grid_json(grids[i], kPlanes[i]));
  return {{"robot", robot.name},  {"source", robot.source}, {"link", ws.link},
          {"relative_to", ws.reference}, {"samples", ws.samples}, {"seed", ws.seed},
          {"sampling", "uniform in each joint's limits, independent (mt19937_64)"},
          {"position", "link origin in the relative_to link's frame"},
          {"extents", extents},   {"joints", joints},           {"density_maps", maps},
          {"files", {{"density_maps", {kPlanes[0].file, kPlanes[1].file}},
                     {"range_of_motion", kRomFile},
                     {"json", kJsonFile}}}};
}

}  // namespace

ModelWorkspace::ModelWorkspace(CLI::App& model) {
  cmd_ = model.add_subcommand("workspace",
                              "A link's workspace by sampling the joint space within the limits: density maps "
                              "(sagittal and frontal), the range of motion of each joint, workspace.json");
  cmd_->add_option("urdf", urdf_, "The URDF file (or --robot)");
  cmd_->add_option("--robot", robot_, "A robot folder by name, found on the robot search path (docs/robot-folder.md)");
  cmd_->add_option("--link", link_, "The link whose origin is sampled (e.g. l_foot)")->required();
  cmd_->add_option("--out", out_, "Folder for the figures and workspace.json (made when missing)")->required();
  cmd_->add_option("--relative-to", relative_to_, "Positions in this link's frame (default: the root link)");
  cmd_->add_option("--samples", samples_, "Number of joint-space samples, 1 to 10^7 (default 100000)");
  cmd_->add_option("--seed", seed_, "Seed of the sampler (default 1)");
  cmd_->add_option("--cell", cell_, "Cell size of the density maps in m (default 0.02)");
}

int ModelWorkspace::run() {
  const m::RobotDescription robot = m::load_urdf(urdf_path(urdf_, robot_));
  const std::string reference = relative_to_.empty() ? robot.links.front().name : relative_to_;
  const int samples = parse_count(samples_, "--samples");
  const double cell = parse_number(cell_, "--cell");
  if (!(cell > 0)) throw InputError("--cell '" + cell_ + "': expected a positive size in m");
  m::moving_chain(robot, link_, reference);  // names a wrong link before the folder is made
  prepare_out(out_);
  const auto t0 = std::chrono::steady_clock::now();
  const m::Workspace ws = m::sample_workspace(robot, link_, reference, {static_cast<std::size_t>(samples), seed_});
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::vector<m::DensityGrid> grids;
  for (const Plane& p : kPlanes) grids.push_back(m::density_grid(ws.points, p.h, p.v, cell));
  const auto path = [&](const char* file) { return (fs::path(out_) / file).string(); };
  for (std::size_t i = 0; i < grids.size(); ++i) {
    const double aspect = grids[i].rows / static_cast<double>(grids[i].cols);  // equal axes: the map's shape
    const int height_px = std::clamp(static_cast<int>(std::lround(125 + 655 * aspect)), 320, 1000);
    viz::save_heat_map_png(heat_map(ws, grids[i], kPlanes[i]), 900, height_px, path(kPlanes[i].file));
    std::cout << "wrote " << path(kPlanes[i].file) << "\n";
  }
  write_file_atomic(path(kRomFile), viz::encode_png(report::range_of_motion_image(robot, ws.chain)));
  std::cout << "wrote " << path(kRomFile) << "\n";
  write_file_atomic(path(kJsonFile), workspace_json(robot, ws, grids).dump(2) + "\n");
  std::cout << "wrote " << path(kJsonFile) << "\n";
  for (int k = 0; k < 3; ++k)
    std::cout << fmt::format("{} of {} relative to {}: {:.4f} .. {:.4f} m\n", kAxis[k], ws.link, ws.reference,
                             ws.min[k], ws.max[k]);
  for (const m::ChainJoint& c : ws.chain)
    std::cout << fmt::format("joint {}: {:.4g} .. {:.4g} ({:.4g} rad, {:.1f} deg){}\n", c.name, c.lower, c.upper,
                             c.upper - c.lower, (c.upper - c.lower) * 180 / kPi,
                             c.unlimited ? ": no limits, sampled over [-pi, pi]" : "");
  std::cout << fmt::format("sampling: {} samples of {} joints, uniform within the limits, seed {}, {:.2f} s\n",
                           ws.samples, ws.chain.size(), ws.seed, seconds);
  return 0;
}

}  // namespace dmbd::apps
