// Real-time factor of the shipped scenarios (simulated time / wall time), each variant
// run for 1 s of simulated time without frames, through the same path as
// `dmbd simulate` (run_variant: plant, controllers as loop programs, sensors, thermals).
#include <benchmark/benchmark.h>

#include <string>

#include "dmbd/scenario/scenario.hpp"

namespace {

void scenario_rtf(benchmark::State& st, const std::string& name) {
  const auto s = dmbd::scenario::load_scenario(std::string(DMBD_SOURCE_DIR) + "/examples/scenarios/" + name + ".yaml");
  dmbd::scenario::RunOptions o;
  o.duration_s = 1.0;
  double sim = 0, wall = 0;
  long long steps = 0;
  for (auto _ : st) {
    for (const auto& v : s.variants) {
      const auto r = dmbd::scenario::run_variant(s, v, o);
      sim += 1.0;
      wall += r.wall_s;
      steps += r.integrator_steps;
    }
  }
  st.counters["rtf"] = sim / wall;
  st.counters["integrator_steps_per_sim_s"] = static_cast<double>(steps) / sim;
}

}  // namespace

BENCHMARK_CAPTURE(scenario_rtf, sysid_knee, std::string("sysid_knee"))->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(scenario_rtf, force_dob, std::string("force_dob"))->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(scenario_rtf, position_controllers, std::string("position_controllers"))->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(scenario_rtf, thermal, std::string("thermal"))->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(scenario_rtf, standing, std::string("standing"))->Unit(benchmark::kMillisecond)->Iterations(1);

BENCHMARK_MAIN();
