// Real-time factor of the shipped scenarios (simulated time / wall time), each variant
// run for 1 s of simulated time without frames, through the same path as
// `dmbd simulate` (run_variant: plant, controllers as loop programs, sensors, thermals);
// and of Simbody's Atlas standing on its feet's boxes (tests/support/atlas_scenario.hpp;
// skipped where Debian's simbody docs are absent), so that a robot with box feet and 29
// joint loops is measured beside DRACO's spheres.
//
// --write_atlas=DIR writes DIR/atlas_v4_free_pelvis.urdf and DIR/atlas.yaml (10 s), the
// same scenario for `dmbd simulate` (to time it against another build).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "atlas_scenario.hpp"
#include "dmbd/model/robot_description.hpp"
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
BENCHMARK_CAPTURE(scenario_rtf, balance, std::string("balance"))->Unit(benchmark::kMillisecond)->Iterations(1);

namespace {

// Decompresses Simbody's Atlas into dir and writes its standing scenario there; returns
// the scenario's path, or "" with `why` set (the URDF absent, the folder not writable).
std::string write_atlas(const std::string& dir, double duration_s, std::string& why) {
  namespace fs = std::filesystem;
  if (!fs::exists(dmbd::test::atlas::kAtlasGz)) {
    why = std::string(dmbd::test::atlas::kAtlasGz) + " is absent (Debian's simbody docs)";
    return "";
  }
  std::error_code ec;
  fs::create_directories(dir.empty() ? "." : dir, ec);
  const std::string urdf = dir + "/atlas_v4_free_pelvis.urdf";
  if (ec || !dmbd::test::atlas::decompress_atlas(urdf)) {
    why = "cannot write '" + urdf + "'";
    return "";
  }
  dmbd::model::UrdfOptions o;
  o.load_meshes = false;
  const auto robot = dmbd::model::load_urdf(urdf, o);
  const std::string path = dir + "/atlas.yaml";
  std::ofstream out(path);
  out << dmbd::test::atlas::scenario_text(robot, urdf, duration_s, "");
  if (!out.flush()) {
    why = "cannot write '" + path + "'";
    return "";
  }
  return path;
}

void atlas_rtf(benchmark::State& st) {
  const std::string dir = (std::filesystem::temp_directory_path() / "dmbd_bench_atlas").string();
  std::string why;
  const std::string path = write_atlas(dir, 1.0, why);
  if (path.empty()) {
    st.SkipWithError(why.c_str());
    return;
  }
  const auto s = dmbd::scenario::load_scenario(path);
  double sim = 0, wall = 0;
  for (auto _ : st) {
    const auto r = dmbd::scenario::run_variant(s, s.variants[0], {});
    sim += 1.0;
    wall += r.wall_s;
  }
  st.counters["rtf"] = sim / wall;
}

}  // namespace

BENCHMARK(atlas_rtf)->Name("scenario_rtf/atlas_standing")->Unit(benchmark::kMillisecond)->Iterations(1);

int main(int argc, char** argv) {
  const char* flag = "--write_atlas=";
  for (int i = 1; i < argc; ++i)
    if (std::strncmp(argv[i], flag, std::strlen(flag)) == 0) {
      std::string why;
      const std::string path = write_atlas(argv[i] + std::strlen(flag), 10.0, why);
      if (path.empty()) std::fprintf(stderr, "bench_sim: --write_atlas: %s\n", why.c_str());
      else std::printf("wrote %s\n", path.c_str());
      return path.empty() ? 1 : 0;
    }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
