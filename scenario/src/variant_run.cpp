// Running a scenario's variant (run_variant, scenario.hpp): its plant started in its
// initial state, its controllers (diagrams and bus controllers) on the bus, the checks
// of what would otherwise pass in silence (variant_checks.hpp), the run and its facts.
#include "engine_names.hpp"

#include <algorithm>
#include <chrono>

#include "dmbd/base/error.hpp"
#include "dmbd/experiments/registry.hpp"
#include "dmbd/scenario/scenario.hpp"
#include "variant_checks.hpp"
#include "variant_controllers.hpp"

namespace dmbd::scenario {

namespace {

// Where an entry of robot: was written (its file:line:col), else the scenario file.
std::string where_of(const Scenario& s, const RobotSetup& r, const std::string& key) {
  const auto it = r.where.find(key);
  return it == r.where.end() ? s.file : it->second;
}

// The plant at t = 0: the initial angles, on the ground (a floating base), locks held.
void start_plant(const Scenario& s, const RobotSetup& r, model::Plant& plant) {
  plant.reset();
  Eigen::VectorXd q0 = plant.joint_positions();
  for (const auto& [n, q] : r.initial) {
    const int j = plant.joint_index(n);
    if (j < 0) throw InputError(where_of(s, r, "initial:" + n) + ": robot.initial: '" + n + "' is not a moving joint");
    q0[j] = q;
  }
  plant.set_joint_positions(q0);
  plant.place_on_ground();  // a floating robot stands on its feet in its initial posture
  for (const auto& [n, q] : r.lock) {
    const int j = plant.joint_index(n);
    if (j < 0) throw InputError(where_of(s, r, "lock:" + n) + ": robot.lock: '" + n + "' is not a moving joint");
    plant.lock_joint(j, q);
  }
}

// Everything the co-simulation runs besides the controllers.
SimulationSpec base_spec(const Scenario& s, const VariantSetup& v, const RunOptions& options) {
  SimulationSpec spec;
  spec.references = v.references;
  spec.forces = v.forces;
  if (v.robot.support) {
    if (v.robot.base != model::BaseMode::Floating)
      throw InputError(where_of(s, v.robot, "support") + ": robot.support: only a floating base can be supported");
    spec.support = v.robot.support;
  }
  if (v.end_on_fall && v.robot.base != model::BaseMode::Floating)
    throw InputError(s.file + ": end_on_fall: only a floating-base robot can fall");
  spec.end_on_fall = v.end_on_fall;
  spec.duration_s = options.duration_s.value_or(v.duration_s);
  spec.log_rate_hz = v.log_rate_hz;
  spec.log_only = s.log_only;
  spec.sensor_noise = v.sensor_noise;
  spec.seed = v.seed;
  spec.force_noise_N = v.force_noise_N;
  spec.cooling = v.cooling;
  return spec;
}

// The simulator's true values the experiment reads (experiments/experiment.hpp).
void record_experiment(const Scenario& s, const VariantSetup& v, const VariantPlant& vp, const model::Plant& plant, VariantResult& res) {
  const experiments::Experiment* e = experiments::find_experiment(s.experiment.type);
  if (!e) return;
  std::vector<std::pair<std::string, double>> q0;
  for (const auto& j : vp.robot.joints) q0.emplace_back(j.name, initial_angle(v.robot, j.name));
  e->record(s.experiment, {plant, vp.robot, q0}, res.truth);
}

}  // namespace

VariantResult run_variant(const Scenario& s, const VariantSetup& v, const RunOptions& options) {
  const VariantPlant vp = variant_plant(s, v);
  check_experiment_names(s, vp.robot);
  VariantResult res;
  res.name = v.name;
  res.axes = v.axes;
  model::Plant plant(vp.robot, vp.options);
  start_plant(s, v.robot, plant);
  record_experiment(s, v, vp, plant, res);

  SimulationSpec spec = base_spec(s, v, options);
  std::vector<VariantController> scenario_controllers;
  for (const auto& c : v.controllers) {
    scenario_controllers.push_back(variant_controller(s, c, spec.duration_s));
    spec.controllers.push_back(scenario_controllers.back().spec);
    const auto& fp = scenario_controllers.back().fixed_point;
    res.fixed_point.insert(res.fixed_point.end(), fp.begin(), fp.end());
  }
  const std::vector<BusControllerRun> bus = bus_controllers(v, vp, plant, spec.duration_s);
  for (const auto& b : bus) {
    spec.controllers.push_back(bus_controller_spec(*b.options, b.controller));
    b.controller->record(plant, res.truth);
  }
  check_outputs_reach(s, v, spec, plant, bus);

  Simulation sim(plant, spec);
  const auto t0 = std::chrono::steady_clock::now();
  const long long steps0 = plant.integrator_steps();
  res.log = sim.run(options.on_progress);
  res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  res.real_time_factor = spec.duration_s / std::max(res.wall_s, 1e-9);
  res.integrator_steps = plant.integrator_steps() - steps0;
  res.controller_steps = sim.controller_steps();
  record_controllers(sim, spec, scenario_controllers, res);
  record_limits(sim, plant, res);
  fixed_point_warnings(res);
  for (const auto& b : bus) tick_timing(b.controller->tick_times_us(), b.controller->timing_name(), res);
  return res;
}

}  // namespace dmbd::scenario
