// The push-recovery map (issue 27): a matrix of balancing runs, each pushed once on the
// torso (docs/scenario-format.md, `push`), against the pendulum's capture verdict. Per
// group of runs (the values of the matrix axis `group_axis`, e.g. the joint model; one
// group without it), into metrics.push_map.GROUP:
//   pushes [{run, direction_deg, force_N, phase_s, duration_s, survived, capturable,
//           margin_m, reachable}]   each pushed run: its push's direction (deg from +x,
//                                   counter-clockwise), peak force, phase (the trigger's
//                                   after_s when the force is triggered, else the time since
//                                   the last logged touch-down), survival (no fall within
//                                   3 s of its end) and the verdict at its end, in its own
//                                   run (push_capture.hpp; the swing's reach with the limits)
//   certified {margin_m, pushes, survived, survived_fraction, at_least, min_pushes, verdict}
//                                   the pushes whose verdict says capturable with at least
//                                   margin_m (`map_margin_m`, 0.03 m): "holds" when at
//                                   least min_pushes (`map_min_pushes`, 50) of them and the
//                                   survived fraction ≥ at_least (`map_survived_at_least`,
//                                   0.95); "fails" when enough and below; else "undecided"
//   directions {DEG: {largest_force_survived_at_every_phase_N, by_phase [{phase_s,
//           largest_survived_N, boundary_N}]}}  the largest force such that it and every
//                                   smaller one was survived at every phase (null: not the
//                                   smallest); per phase the largest survived and the
//                                   analytic boundary below
//   boundary {reference, trigger_time_s, phase_s [..], by_direction {DEG: [F_max ..]}}
//   swing_foot {runs, peak_speed_m_s, peak_accel_m_s2}  the swing foot's largest speed and
//                                   acceleration over the runs that stood (survived pushes,
//                                   an unpushed run that did not fall): what it did while
//                                   balancing, a measured lower bound on its limits
// The boundary F_max(phase): on the group's unpushed run (its `push` with force_N 0, the
// reference), the pendulum's verdict at the end of a push starting `phase` after the
// pushes' phase origin, and the largest force along the direction that keeps the capture
// point inside the capture intervals: a push of F shifts it by F (e^{ωτ} − 1)/(m ω²)
// (wholebody/capture.hpp), so F_max is where that ray leaves the box; 0 where the
// unpushed orbit itself is not capturable. Figure push_map_GROUP.png: one panel per
// direction, force against phase, survived and fallen pushes and F_max.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "balance_runs.hpp"
#include "dmbd/control/balance_controller.hpp"
#include "dmbd/wholebody/capture.hpp"

namespace dmbd::experiments {

namespace {

using detail::BalanceParams;
using detail::BalanceRun;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kBoundaryStepS = 0.005;  // the boundary's phase grid

struct MapPush {
  std::string run;
  double direction_deg = 0, force_N = 0, phase_s = 0, duration_s = 0, origin_s = 0;
  bool survived = false;
  nlohmann::json lipm;
};

struct Group {
  std::vector<MapPush> pushes;
  // The swing foot's peaks over the runs that stood (the survived pushes and an unpushed
  // run that did not fall): what the robot's swing foot did while balancing.
  double swing_speed_m_s = 0, swing_accel_m_s2 = 0;
  int stood = 0;
  const BalanceRun* reference = nullptr;
  const VariantFacts* reference_facts = nullptr;
};

struct MapParams {
  std::string group_axis;
  double margin_m, min_pushes, survived_at_least;
};

// Directions to a tenth of a degree in [0, 360): the panels' keys.
double direction_deg(const Eigen::Vector3d& d) {
  const double a = std::round(10.0 * std::atan2(d.y(), d.x()) * 180.0 / M_PI) / 10.0;
  return a < 0 ? a + 360.0 : a;
}

// The phase origin of a push starting at start_s: the trigger's time when its force is
// triggered (start − after_s), else the last logged touch-down at or before it.
double phase_origin(const BalanceRun& run, const VariantFacts& v, double start_s) {
  for (const auto& f : v.forces)
    if (f.trigger && f.direction_W.norm() > 0) return start_s - f.trigger->after_s;
  double origin = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t k : run.touch_downs)
    if (run.t[k] <= start_s + 1e-9) origin = run.t[k];
  return origin;
}

std::string group_of(const VariantResult& r, const MapParams& mp, const ExperimentSetup& e) {
  if (mp.group_axis.empty()) return "all";
  for (const auto& [axis, value] : r.axes)
    if (axis == mp.group_axis) return value;
  const auto at = e.where.find("group_axis");
  throw InputError(fmt::format("{}: experiment push_map: group_axis '{}' is not a matrix axis of run '{}'", at == e.where.end() ? e.file : at->second,
                               mp.group_axis, r.name));
}

// F_max along the unit direction d (xy) from the capture-point offset e inside the box
// [ix] x [iy], with `shift` metres of capture-point shift per newton.
double ray_exit_N(const nlohmann::json& v, const Eigen::Vector2d& d, double shift) {
  if (v.is_null() || !v.value("capturable", false)) return 0.0;
  const auto e = v.at("cp_offset_m").get<std::vector<double>>();
  const auto ix = v.at("interval_x_m").get<std::vector<double>>(), iy = v.at("interval_y_m").get<std::vector<double>>();
  const double lo[2] = {ix[0], iy[0]}, hi[2] = {ix[1], iy[1]};
  double f = kInf;
  for (int a = 0; a < 2; ++a) {
    const double step = shift * d[a];
    if (step > 0) f = std::min(f, (hi[a] - e[a]) / step);
    if (step < 0) f = std::min(f, (lo[a] - e[a]) / step);
  }
  return f;
}

// Why the group has no boundary ("" when it has one): it needs an unpushed run, the
// controller's options and mass, and one phase origin and duration shared by its pushes
// (to a microsecond).
std::string no_boundary_reason(const Group& g) {
  if (g.pushes.empty()) return "no push";
  if (!g.reference) return "no unpushed run (push force_N 0) in the group";
  if (!g.reference_facts->bus_controller<control::BalanceSetup>() || !g.reference->r.truth.count("total_mass_kg"))
    return "its unpushed run has no balancing controller";
  for (const auto& p : g.pushes)
    if (std::abs(p.origin_s - g.pushes.front().origin_s) > 1e-6 || std::abs(p.duration_s - g.pushes.front().duration_s) > 1e-6)
      return fmt::format("its pushes do not share one phase origin and duration ('{}': {} s and {} s, '{}': {} s and {} s)", g.pushes.front().run,
                         g.pushes.front().origin_s, g.pushes.front().duration_s, p.run, p.origin_s, p.duration_s);
  return "";
}

// The boundary over the phase grid [0, one step period], per direction of the group's
// pushes (no_boundary_reason empty).
nlohmann::json boundary(const Group& g, const BalanceParams& p, const std::vector<double>& dirs, const std::string& file) {
  const auto* b = g.reference_facts->bus_controller<control::BalanceSetup>();
  const auto mass = g.reference->r.truth.find("total_mass_kg");
  const double origin = g.pushes.front().origin_s, tau = g.pushes.front().duration_s;
  const double shift = wholebody::push_capture_point_shift(1.0, tau, mass->second, detail::pendulum_omega(*b, g.reference_facts->gravity_m_s2));
  nlohmann::json out = {{"reference", g.reference->r.name}, {"trigger_time_s", origin}, {"duration_s", tau}};
  std::vector<double> phases;
  std::map<double, std::vector<double>> by_dir;
  const auto n = static_cast<int>(std::floor(b->phases.step_period_s() / kBoundaryStepS + 1e-9));
  for (int k = 0; k <= n; ++k) {
    const double ph = k * kBoundaryStepS;
    const nlohmann::json v = detail::push_capture(g.reference->r, *b, g.reference_facts->gravity_m_s2, origin + ph + tau, file, p.reach);
    phases.push_back(ph);
    for (double deg : dirs) {
      const Eigen::Vector2d d(std::cos(deg * M_PI / 180.0), std::sin(deg * M_PI / 180.0));
      by_dir[deg].push_back(ray_exit_N(v, d, shift));
    }
  }
  out["phase_s"] = phases;
  for (const auto& [deg, f] : by_dir) out["by_direction"][fmt::format("{:g}", deg)] = f;
  return out;
}

// The boundary at a phase: the grid's nearest point.
double boundary_at(const nlohmann::json& bnd, double deg, double phase) {
  if (bnd.is_null()) return std::numeric_limits<double>::quiet_NaN();
  const auto k = static_cast<std::size_t>(std::lround(phase / kBoundaryStepS));
  const auto& f = bnd.at("by_direction").at(fmt::format("{:g}", deg));
  return k < f.size() ? f[k].get<double>() : std::numeric_limits<double>::quiet_NaN();
}

std::vector<double> directions(const Group& g) {
  std::vector<double> d;
  for (const auto& p : g.pushes) d.push_back(p.direction_deg);
  std::sort(d.begin(), d.end());
  d.erase(std::unique(d.begin(), d.end()), d.end());
  return d;
}

// Per direction: the largest force survived at every phase, and per phase.
nlohmann::json direction_metrics(const Group& g, double deg, const nlohmann::json& bnd) {
  std::map<double, std::map<double, bool>> by_force;  // force -> phase -> survived
  std::map<double, double> best;                      // phase -> largest survived
  for (const auto& p : g.pushes) {
    if (p.direction_deg != deg) continue;
    by_force[p.force_N][p.phase_s] = p.survived;
    if (p.survived) best[p.phase_s] = std::max(best[p.phase_s], p.force_N);
    else best.emplace(p.phase_s, 0.0);
  }
  nlohmann::json every = nullptr;
  for (const auto& [force, phases] : by_force) {
    if (std::any_of(phases.begin(), phases.end(), [](const auto& x) { return !x.second; })) break;
    every = force;
  }
  nlohmann::json by_phase = nlohmann::json::array();
  for (const auto& [phase, force] : best)
    by_phase.push_back({{"phase_s", phase}, {"largest_survived_N", force}, {"boundary_N", boundary_at(bnd, deg, phase)}});
  return {{"largest_force_survived_at_every_phase_N", every}, {"by_phase", by_phase}};
}

nlohmann::json certified(const Group& g, const MapParams& mp) {
  int n = 0, ok = 0;
  for (const auto& p : g.pushes) {
    const auto& l = p.lipm;
    if (l.is_null() || !l.value("capturable", false) || !l.contains("margin_m") || !l.at("margin_m").is_number()) continue;
    if (l.at("margin_m").get<double>() < mp.margin_m) continue;
    ++n;
    ok += p.survived;
  }
  const double fraction = n ? static_cast<double>(ok) / n : std::numeric_limits<double>::quiet_NaN();
  const char* verdict = n < mp.min_pushes ? "undecided" : fraction >= mp.survived_at_least ? "holds" : "fails";
  return {{"margin_m", mp.margin_m},   {"pushes", n},           {"survived", ok}, {"survived_fraction", fraction},
          {"at_least", mp.survived_at_least}, {"min_pushes", mp.min_pushes}, {"verdict", verdict}};
}

plot::Figure map_figure(const ExperimentSetup& e, const std::string& name, const Group& g, const std::vector<double>& dirs,
                        const nlohmann::json& bnd) {
  plot::Figure fig(1000, 100 + 330 * static_cast<int>(dirs.size()));
  fig.title = labelled(e, "push_map", "Push-recovery map" + (name == "all" ? std::string() : ": " + name));
  for (double deg : dirs) {
    auto& a = fig.axes().emplace_back();
    a.title = fmt::format("push towards {:g} deg", deg);
    a.x_label = "phase: time after the touch-down (s)";
    a.y_label = "force (N)";
    plot::Series ok{"survived", {}, {}, plot::Color{40, 160, 40}, 1.0, false, true};
    plot::Series fell{"fell", {}, {}, plot::Color{210, 40, 40}, 1.0, false, true};
    for (const auto& p : g.pushes) {
      if (p.direction_deg != deg) continue;
      auto& s = p.survived ? ok : fell;
      s.x.insert(s.x.end(), {p.phase_s, NAN});
      s.y.insert(s.y.end(), {p.force_N, NAN});
    }
    a.series = {ok, fell};
    if (!bnd.is_null())
      a.series.push_back({"F_max (pendulum, unpushed orbit)", bnd.at("phase_s").get<std::vector<double>>(),
                          bnd.at("by_direction").at(fmt::format("{:g}", deg)).get<std::vector<double>>(), plot::Color{20, 20, 20}, 2.0});
  }
  return fig;
}

void add_swing_peaks(const BalanceRun& run, const std::string& file, Group& g) {
  const detail::SwingPeaks s = detail::swing_peaks(run, file);
  if (std::isnan(s.speed_m_s)) return;
  g.swing_speed_m_s = std::max(g.swing_speed_m_s, s.speed_m_s);
  g.swing_accel_m_s2 = std::max(g.swing_accel_m_s2, s.accel_m_s2);
  ++g.stood;
}

// One run into its group: its push, or (no force at all) the group's unpushed reference.
// A run whose force pushed nothing (a trigger that never fired) or came before any
// touch-down (no phase) is left out with a warning.
void add_push(const BalanceRun& run, const VariantFacts& v, const BalanceParams& p, const std::string& file, Group& g,
              std::vector<std::string>& warnings) {
  const nlohmann::json pushes = detail::push_metrics(run, v, p.reach, file);
  if (pushes.empty()) {
    if (std::any_of(v.forces.begin(), v.forces.end(), [](const ForceSpec& f) { return f.direction_W.norm() > 0; })) {
      warnings.push_back(fmt::format("variant '{}': its push was never applied (its trigger did not fire): not in the map", run.r.name));
      return;
    }
    if (!run.fell()) add_swing_peaks(run, file, g);
    if (!g.reference) g.reference = &run, g.reference_facts = &v;
    return;
  }
  if (pushes.size() > 1) throw InputError(fmt::format("{}: experiment push_map: run '{}' has {} pushes (one per run)", file, run.r.name, pushes.size()));
  const auto& j = pushes[0];
  const auto dir = j.at("direction").get<std::vector<double>>();
  MapPush m{run.r.name, direction_deg({dir[0], dir[1], dir[2]}), j.at("force_N").get<double>(), 0, j.at("duration_s").get<double>(), 0,
            j.at("survived").get<bool>(), j.at("lipm")};
  const double start = j.at("start_s").get<double>();
  m.origin_s = phase_origin(run, v, start);
  if (std::isnan(m.origin_s)) {
    warnings.push_back(fmt::format("variant '{}': its push at {} s comes before any touch-down (no phase): not in the map", run.r.name, start));
    return;
  }
  m.phase_s = std::round((start - m.origin_s) * 1e6) / 1e6;
  if (m.survived) add_swing_peaks(run, file, g);
  g.pushes.push_back(std::move(m));
}

nlohmann::json push_json(const MapPush& p) {
  const auto& l = p.lipm;
  return {{"run", p.run},
          {"direction_deg", p.direction_deg},
          {"force_N", p.force_N},
          {"phase_s", p.phase_s},
          {"duration_s", p.duration_s},
          {"survived", p.survived},
          {"capturable", l.is_null() ? nlohmann::json(nullptr) : l.value("capturable", nlohmann::json(nullptr))},
          {"margin_m", l.is_null() ? nlohmann::json(nullptr) : l.value("margin_m", nlohmann::json(nullptr))},
          {"reachable", l.is_null() ? nlohmann::json(nullptr) : l.value("reachable", nlohmann::json(nullptr))}};
}

// The map's own keys, each within its range (a located InputError otherwise).
MapParams read_map_params(const ExperimentSetup& e) {
  const MapParams mp{detail::text_or(e, "group_axis", ""), detail::number_or(e, "map_margin_m", 0.03), detail::number_or(e, "map_min_pushes", 50),
                     detail::number_or(e, "map_survived_at_least", 0.95)};
  auto check = [&](bool ok, const char* key, const char* expected, double got) {
    if (ok) return;
    const auto at = e.where.find(key);
    throw InputError(fmt::format("{}: experiment push_map: {}: expected {}, got {}", at == e.where.end() ? e.file : at->second, key, expected, got));
  };
  check(mp.margin_m >= 0, "map_margin_m", "a margin of 0 m or more", mp.margin_m);
  check(mp.min_pushes >= 1 && mp.min_pushes == std::floor(mp.min_pushes), "map_min_pushes", "a whole number of pushes, at least 1", mp.min_pushes);
  check(mp.survived_at_least > 0 && mp.survived_at_least <= 1, "map_survived_at_least", "a fraction in (0, 1]", mp.survived_at_least);
  return mp;
}

ExperimentResult push_map(const ExperimentSetup& e, const std::vector<VariantResult>& runs, const std::vector<VariantFacts>& variants) {
  const BalanceParams p = detail::read_balance_params(e, variants);
  const MapParams mp = read_map_params(e);
  ExperimentResult res;
  std::vector<BalanceRun> analysed;
  analysed.reserve(runs.size());  // Groups point into it
  std::map<std::string, Group> groups;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    if (runs[k].log.rows() == 0) {
      res.warnings.push_back(fmt::format("variant '{}' logged no samples: not in the map", runs[k].name));
      continue;
    }
    analysed.push_back(detail::analyse_run(runs[k], p, e.file));
    add_push(analysed.back(), variants[k], p, e.file, groups[group_of(runs[k], mp, e)], res.warnings);
  }
  for (const auto& [name, g] : groups) {
    const auto dirs = directions(g);
    const std::string why = no_boundary_reason(g);
    const nlohmann::json bnd = why.empty() ? boundary(g, p, dirs, e.file) : nlohmann::json(nullptr);
    if (!why.empty() && !g.pushes.empty()) res.warnings.push_back(fmt::format("push map '{}': {}: no boundary drawn", name, why));
    nlohmann::json& m = res.metrics["push_map"][name];
    m["pushes"] = nlohmann::json::array();
    for (const auto& push : g.pushes) m["pushes"].push_back(push_json(push));
    m["certified"] = certified(g, mp);
    for (double deg : dirs) m["directions"][fmt::format("{:g}", deg)] = direction_metrics(g, deg, bnd);
    m["boundary"] = bnd;
    m["swing_foot"] = {{"runs", g.stood}, {"peak_speed_m_s", g.stood ? nlohmann::json(g.swing_speed_m_s) : nlohmann::json(nullptr)},
                       {"peak_accel_m_s2", g.stood ? nlohmann::json(g.swing_accel_m_s2) : nlohmann::json(nullptr)}};
    res.figures.emplace_back("push_map_" + detail::file_safe(name) + ".png", map_figure(e, name, g, dirs, bnd));
    const auto& c = m["certified"];
    res.notes.push_back(fmt::format("Push map '{}': {} of {} pushes capturable with a margin of at least {} m were survived: {}.", name,
                                    c["survived"].get<int>(), c["pushes"].get<int>(), mp.margin_m, c["verdict"].get<std::string>()));
  }
  return res;
}

}  // namespace

std::shared_ptr<const Experiment> push_map_experiment() {
  std::map<std::string, KeyKind> keys = detail::balance_keys();
  keys.insert({{"group_axis", KeyKind::Text}, {"map_margin_m", KeyKind::Number}, {"map_min_pushes", KeyKind::Number}, {"map_survived_at_least", KeyKind::Number}});
  return std::make_shared<detail::FunctionExperiment>(keys, false, &push_map);
}

}  // namespace dmbd::experiments
