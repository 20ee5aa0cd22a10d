// The whole-robot speed benchmark: DRACO standing on flat ground under a 1 kHz joint
// controller (bench/standing_task.hpp), in each engine, 2 s of simulated time per
// iteration. Counters: rtf (simulated s / wall s of the stepping loop, model build not
// timed), steps_per_sim_s, max_tilt_rad, drop_m, fell (0/1). A final table sets the
// engines side by side per variant, with each engine's real-time factor relative to the
// first (the anchor, MuJoCo).
//
// Variants: ideal joint torques (Euler and implicit integrators) and the ten VLCAs as
// elastic joints driven by currents (Euler).
// Engines, in this order: MuJoCo (mujoco_draco.cpp; skipped with a note when MuJoCo was
// not found), DART with the FCL and with the ODE collision detector (dart_draco.cpp;
// ideal_euler only: DART's integrator is its own and the VLCAs are not modelled there;
// skipped with a note when DART was not found), and the project's own plant with its
// fixed step of 1 ms and 0.5 ms (dmbd_standing.cpp). An engine only runs the variants it
// supports: the table then lacks the other rows.
//
// --write_mjcf=DIR writes the generated MuJoCo models to DIR/draco_mujoco_{ideal,elastic}.xml.
// --rounds=N replaces Google Benchmark's runs by N interleaved rounds per variant: in each
// round every engine runs the 2 s task once, in turn (A B C D ... then again), so that slow
// drifts of the machine (clock, other load) hit every engine alike. It prints, per variant
// and engine, the median real-time factor over the rounds, its min-max, the median of the
// per-round ratios engine/anchor (the anchor: the first engine, MuJoCo when available) and
// the median of the per-round ratios Dmbd/engine (our engine against each other one:
// Dmbd/Mujoco, Dmbd/DartOde, ...). --rounds runs every variant and takes no Google
// Benchmark flag. Both flags are taken out of argv before Google Benchmark sees it;
// without --rounds the Google Benchmark mode is as before.
#include "dart_draco.hpp"
#include "dmbd_standing.hpp"
#include "mujoco_draco.hpp"
#include "standing_task.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
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
// Whether an engine runs a variant.
using Supports = bool (*)(bool elastic, Integrator integrator);
bool every_variant(bool, Integrator) { return true; }

struct Engine {
  std::string name;
  Runner run;
  Supports supports;
};

// Everything an engine's runs of one variant added up, for the final table.
struct Tally {
  double sim_s = 0, wall_s = 0, max_tilt_rad = 0, drop_m = 0;
  long long steps = 0;
  bool fell = false, diverged = false;
  double rtf() const { return wall_s > 0 ? sim_s / wall_s : 0; }
};
std::vector<Engine> g_engines;                             // registration order; [0] is the anchor
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

// Adds an engine (after those already added: the first is the anchor).
void add_engine(const std::string& engine, Runner run, Supports supports = every_variant) {
  g_engines.push_back({engine, run, supports});
}

// BM_<engine>Standing/<variant> for every engine and the variants it supports, three
// iterations of 2 s each, timed by the engine's loop.
void register_benchmarks() {
  for (const Engine& e : g_engines)
    for (const Variant& v : kVariants) {
      if (!e.supports(v.elastic, v.integrator)) continue;
      const std::string engine = e.name;
      const Runner run = e.run;
      benchmark::RegisterBenchmark(("BM_" + engine + "Standing/" + v.name).c_str(),
                                   [engine, run, v](benchmark::State& st) { run_standing(st, engine, run, v); })
          ->UseManualTime()
          ->Unit(benchmark::kMillisecond)
          ->Iterations(3);
    }
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
  const std::string& a = g_engines[0].name;
  std::printf("\nDRACO standing, %s real-time factors (rtf = simulated s / wall s)\n", a.c_str());
  for (const Variant& v : kVariants) {
    const auto anchor = g_tally[a].find(v.name);
    for (const Engine& engine : g_engines) {
      const std::string& e = engine.name;
      const auto it = g_tally[e].find(v.name);
      if (it == g_tally[e].end()) continue;  // filtered out, or not supported
      std::printf("  %-15s %-7s rtf %7.2f  %s", v.name, e.c_str(), it->second.rtf(), outcome(it->second).c_str());
      if (e != a && anchor != g_tally[a].end() && anchor->second.rtf() > 0)
        std::printf("  %s/%s = %.3f", e.c_str(), a.c_str(), it->second.rtf() / anchor->second.rtf());
      std::printf("\n");
    }
  }
}

// ---- --rounds=N: interleaved rounds ----

double median(std::vector<double> x) {
  if (x.empty()) return 0;
  std::sort(x.begin(), x.end());
  const std::size_t n = x.size();
  return n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
}

// Median over the rounds of num[r] / den[r] (rounds where den[r] > 0).
double median_ratio(const std::vector<double>& num, const std::vector<double>& den) {
  std::vector<double> r;
  for (std::size_t k = 0; k < num.size() && k < den.size(); ++k)
    if (den[k] > 0) r.push_back(num[k] / den[k]);
  return median(r);
}

// Per variant: N rounds, each engine that supports it once per round, in turn. Then per
// engine: median rtf [min - max], median of the per-round ratios to the anchor and of
// Dmbd's per-round ratios to it, and the outcome over every round.
void run_rounds(int rounds) {
  const std::string& a = g_engines[0].name;
  const bool have_dmbd = std::any_of(g_engines.begin(), g_engines.end(), [](const Engine& e) { return e.name == "Dmbd"; });
  std::printf("DRACO standing, %d interleaved rounds per variant (every engine once per round, in turn; "
              "%.0f s simulated per run)\n", rounds, StandingTask{}.duration_s);
  std::map<std::string, std::map<std::string, std::vector<double>>> rtf;  // variant -> engine -> per round
  std::map<std::string, std::map<std::string, Tally>> tally;               // variant -> engine -> every round
  for (const Variant& v : kVariants) {
    const StandingTask task = task_of(v);
    for (int k = 0; k < rounds; ++k) {
      std::printf("  %s round %d/%d:", v.name, k + 1, rounds);
      for (const Engine& e : g_engines) {
        if (!e.supports(v.elastic, v.integrator)) continue;
        const StandingResult r = e.run(draco(), v.elastic ? &actuators() : nullptr, task);
        rtf[v.name][e.name].push_back(r.rtf);
        add(tally[v.name][e.name], r);
        std::printf(" %s %.2f", e.name.c_str(), r.rtf);
        std::fflush(stdout);
      }
      std::printf("\n");
    }
  }

  std::printf("\nDRACO standing, %d interleaved rounds: rtf = simulated s / wall s, median [min - max] over the rounds;\n"
              "ratios = median of the per-round ratios: X/%s (X = the row's engine; %s is the anchor) and Dmbd/X\n",
              rounds, a.c_str(), a.c_str());
  std::printf("  %-15s %-7s %8s  %-19s %14s %14s  %s\n", "variant", "engine", "rtf", "[min - max]",
              ("X/" + a).c_str(), "Dmbd/X", "outcome");
  for (const Variant& v : kVariants) {
    const auto& per = rtf[v.name];
    const auto anchor = per.find(a);
    const auto dmbd = per.find("Dmbd");
    for (const Engine& e : g_engines) {
      const auto it = per.find(e.name);
      if (it == per.end()) continue;  // not supported
      const std::vector<double>& x = it->second;
      char range[40];
      std::snprintf(range, sizeof range, "[%.2f - %.2f]", *std::min_element(x.begin(), x.end()),
                    *std::max_element(x.begin(), x.end()));
      char vs_anchor[32] = "-", dmbd_vs[32] = "-";
      if (e.name != a && anchor != per.end())
        std::snprintf(vs_anchor, sizeof vs_anchor, "%.3f", median_ratio(x, anchor->second));
      if (e.name != "Dmbd" && dmbd != per.end())
        std::snprintf(dmbd_vs, sizeof dmbd_vs, "%.3f", median_ratio(dmbd->second, x));
      std::printf("  %-15s %-7s %8.2f  %-19s %14s %14s  %s\n", v.name, e.name.c_str(), median(x), range, vs_anchor,
                  dmbd_vs, outcome(tally[v.name][e.name]).c_str());
    }
  }
  if (!have_dmbd) std::printf("  (no Dmbd engine: no Dmbd/X ratios)\n");
}

// --rounds=N (taken out of argv before Google Benchmark sees it): N, or 0 when absent.
int rounds_flag(int& argc, char** argv) {
  const char* flag = "--rounds=";
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], flag, std::strlen(flag)) != 0) continue;
    char* end = nullptr;
    const long n = std::strtol(argv[i] + std::strlen(flag), &end, 10);
    if (!end || *end != '\0' || n < 1 || n > 1000) {
      std::fprintf(stderr, "bench_standing: --rounds wants a whole number from 1 to 1000, not '%s'\n",
                   argv[i] + std::strlen(flag));
      std::exit(1);
    }
    for (int j = i; j + 1 < argc; ++j) argv[j] = argv[j + 1];
    --argc;
    return static_cast<int>(n);
  }
  return 0;
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
  const int rounds = rounds_flag(argc, argv);
  if (dmbd::bench::mujoco_available())
    add_engine("Mujoco", dmbd::bench::run_mujoco_standing);
  else
    std::printf("%s\n", dmbd::bench::kMujocoMissing);
  // DART, the second anchor: with the FCL and with the ODE collision detector, the
  // ideal-torque Euler variant only.
  if (dmbd::bench::dart_available()) {
    add_engine("DartFcl", dmbd::bench::run_dart_fcl_standing, dmbd::bench::dart_supports);
    if (dmbd::bench::dart_ode_available())
      add_engine("DartOde", dmbd::bench::run_dart_ode_standing, dmbd::bench::dart_supports);
    else
      std::printf("%s\n", dmbd::bench::kDartOdeMissing);
  } else {
    std::printf("%s\n", dmbd::bench::kDartMissing);
  }
  // The project's simulator, side by side: its fixed step at the task's 1 ms and at the
  // 0.5 ms the shipped scenarios use.
  add_engine("Dmbd", dmbd::bench::run_dmbd_standing_1ms);
  add_engine("Dmbd05", dmbd::bench::run_dmbd_standing_05ms);
  if (rounds > 0) {
    if (argc > 1) {
      std::fprintf(stderr, "bench_standing: --rounds takes no other argument (got '%s')\n", argv[1]);
      return 1;
    }
    run_rounds(rounds);
    return 0;
  }
  register_benchmarks();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  if (!g_engines.empty()) benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  print_table();
  return 0;
}
