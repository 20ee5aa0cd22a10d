// The whole-robot speed benchmark: DRACO standing on flat ground under a 1 kHz joint
// controller (bench/standing_task.hpp), in each engine, 2 s of simulated time per
// iteration. Counters: rtf (simulated s / wall s of the stepping loop, model build not
// timed), steps_per_sim_s, max_tilt_rad, drop_m, fell (0/1). A final table sets the
// engines side by side per variant, with each engine's real-time factor relative to the
// first (the anchor, MuJoCo).
//
// Variants: ideal joint torques (Euler and implicit integrators) and the ten VLCAs as
// elastic joints driven by currents (Euler).
// Engines: MuJoCo (mujoco_draco.cpp; skipped with a note when MuJoCo was not found) and
// the project's own plant with its fixed step of 1 ms and 0.5 ms (dmbd_standing.cpp).
//
// --write_mjcf=DIR writes the generated MuJoCo models to DIR/draco_mujoco_{ideal,elastic}.xml.
#include "dmbd_standing.hpp"
#include "mujoco_draco.hpp"
#include "standing_task.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace {

using dmbd::bench::Integrator;
using dmbd::bench::StandingResult;
using dmbd::bench::StandingTask;
using dmbd::model::ActuatorParams;
using dmbd::model::RobotDescription;

const RobotDescription& draco() {
  static const RobotDescription r = dmbd::model::load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf");
  return r;
}

const std::vector<ActuatorParams>& actuators() {
  static const std::vector<ActuatorParams> a = dmbd::model::load_actuators(DMBD_ROBOTS_DIR "/draco/actuators.yaml");
  return a;
}

struct Variant {
  const char* name;
  bool elastic;  // actuators as elastic joints driven by currents, else ideal torques
  Integrator integrator;
};
const Variant kVariants[] = {{"ideal_euler", false, Integrator::Euler},
                             {"ideal_implicit", false, Integrator::Implicit},
                             {"elastic_euler", true, Integrator::Euler}};

StandingTask task_of(const Variant& v) {
  StandingTask t;  // 2 s, 1 kHz control and step, the task's gains
  t.integrator = v.integrator;
  return t;
}

// An engine: runs the standing task (actuators == nullptr: ideal torques).
using Runner = StandingResult (*)(const RobotDescription&, const std::vector<ActuatorParams>*, const StandingTask&);

// Everything an engine's runs of one variant added up, for the final table.
struct Tally {
  double sim_s = 0, wall_s = 0, max_tilt_rad = 0, drop_m = 0;
  long long steps = 0;
  bool fell = false, diverged = false;
  double rtf() const { return wall_s > 0 ? sim_s / wall_s : 0; }
};
std::vector<std::string> g_engines;                        // registration order; [0] is the anchor
std::map<std::string, std::map<std::string, Tally>> g_tally;  // engine -> variant -> tally

void add(Tally& t, const StandingResult& r) {
  t.sim_s += r.sim_s;
  t.wall_s += r.wall_s;
  t.steps += r.steps;
  t.max_tilt_rad = std::max(t.max_tilt_rad, r.max_tilt_rad);
  t.drop_m = std::max(t.drop_m, r.drop_m);
  t.fell = t.fell || r.fell;
  t.diverged = t.diverged || r.diverged;
}

void run_standing(benchmark::State& st, const std::string& engine, Runner run, const Variant& v) {
  const StandingTask task = task_of(v);
  Tally& t = g_tally[engine][v.name];
  t = Tally{};
  for (auto _ : st) {
    const StandingResult r = run(draco(), v.elastic ? &actuators() : nullptr, task);
    st.SetIterationTime(r.wall_s);
    add(t, r);
  }
  st.counters["rtf"] = t.rtf();
  st.counters["steps_per_sim_s"] = static_cast<double>(t.steps) / t.sim_s;
  st.counters["max_tilt_rad"] = t.max_tilt_rad;
  st.counters["drop_m"] = t.drop_m;
  st.counters["fell"] = t.fell ? 1 : 0;
}

// BM_<engine>Standing/<variant>, three iterations of 2 s each, timed by the engine's loop.
void register_engine(const std::string& engine, Runner run) {
  g_engines.push_back(engine);
  for (const Variant& v : kVariants)
    benchmark::RegisterBenchmark(("BM_" + engine + "Standing/" + v.name).c_str(),
                                 [engine, run, v](benchmark::State& st) { run_standing(st, engine, run, v); })
        ->UseManualTime()
        ->Unit(benchmark::kMillisecond)
        ->Iterations(3);
}

std::string outcome(const Tally& t) {
  char s[96];
  std::snprintf(s, sizeof s, "%s (tilt %.3f rad, drop %.4f m)",
                t.diverged ? "DIVERGED" : t.fell ? "FELL" : "stands", t.max_tilt_rad, t.drop_m);
  return s;
}

// Per variant: each engine's real-time factor and outcome; engines after the anchor
// also get their real-time factor divided by the anchor's.
void print_table() {
  if (g_engines.empty()) return;
  std::printf("\nDRACO standing, %s real-time factors (rtf = simulated s / wall s)\n", g_engines[0].c_str());
  for (const Variant& v : kVariants) {
    const auto anchor = g_tally[g_engines[0]].find(v.name);
    for (const std::string& e : g_engines) {
      const auto it = g_tally[e].find(v.name);
      if (it == g_tally[e].end()) continue;  // filtered out
      std::printf("  %-15s %-7s rtf %7.2f  %s", v.name, e.c_str(), it->second.rtf(), outcome(it->second).c_str());
      if (e != g_engines[0] && anchor != g_tally[g_engines[0]].end() && anchor->second.rtf() > 0)
        std::printf("  %s/%s = %.3f", e.c_str(), g_engines[0].c_str(), it->second.rtf() / anchor->second.rtf());
      std::printf("\n");
    }
  }
}

// --write_mjcf=DIR (taken out of argv before Google Benchmark sees it).
void write_mjcf_if_asked(int& argc, char** argv) {
  const char* flag = "--write_mjcf=";
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], flag, std::strlen(flag)) != 0) continue;
    const std::string dir = argv[i] + std::strlen(flag);
    std::ofstream(dir + "/draco_mujoco_ideal.xml") << dmbd::bench::draco_mjcf(draco(), nullptr, task_of(kVariants[0]));
    std::ofstream(dir + "/draco_mujoco_elastic.xml") << dmbd::bench::draco_mjcf(draco(), &actuators(), task_of(kVariants[2]));
    std::printf("wrote %s/draco_mujoco_{ideal,elastic}.xml\n", dir.c_str());
    for (int j = i; j + 1 < argc; ++j) argv[j] = argv[j + 1];
    --argc;
    return;
  }
}

}  // namespace

int main(int argc, char** argv) {
  write_mjcf_if_asked(argc, argv);
  if (dmbd::bench::mujoco_available())
    register_engine("Mujoco", dmbd::bench::run_mujoco_standing);
  else
    std::printf("%s\n", dmbd::bench::kMujocoMissing);
  // The project's simulator, side by side: its fixed step at the task's 1 ms and at the
  // 0.5 ms the shipped scenarios use.
  register_engine("Dmbd", dmbd::bench::run_dmbd_standing_1ms);
  register_engine("Dmbd05", dmbd::bench::run_dmbd_standing_05ms);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  if (!g_engines.empty()) benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  print_table();
  return 0;
}
