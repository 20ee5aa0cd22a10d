// The balance experiment (paper Fig. 7): unsupported stepping in place, from each
// variant's log of the balancing controller's outputs (balance_controller.hpp), the
// torso's true pose and the actuators' windings. Per variant (metrics.balance.NAME):
//   fell, fall_time_s                 torso below fall_height_m (base.z) or tilted beyond
//                                     fall_tilt_rad (base.tilt) at a log sample; the first
//   balanced_s                        from start_s (stepping starts) to the fall or the end
//   steps                             balance.touch_downs at the last sample before the fall
//   landing_error_rms_m               |landed − planned| (x, y) at each landing (balance.landings)
//                                     before the fall, RMS over them
//   com_max_distance_m, com_max_distance_at_s
//                                     the largest horizontal distance of balance.com (x, y)
//                                     from where it was at the first touch-down, before the
//                                     fall, and when (stepping in place: it stays near its start)
//   swing_foot_peak_speed_m_s, swing_foot_peak_accel_m_s2
//                                     the swing foot's largest horizontal speed and
//                                     acceleration in its swings (balance_runs.hpp)
//   com_lateral_velocity_reversals    fraction of the steps between consecutive touch-downs
//                                     (before the fall) in which balance.com_vy changes sign
//   peak_winding_C {cooled, uncooled} largest knee winding temperature (both knees)
//   uncooled_passes_s, thermal_contrast
//                                     with winding_uncooled_above_C: when an uncooled winding
//                                     first passed it (null: never); with winding_cooled_below_C
//                                     too: holds or fails (Fig. 7d's contrast over the run)
//   wbc_tick_us {median, max}, real_time_factor, qp_failures (the last count)
//   pushes [{start_s, duration_s, force_N, direction, survived, lipm}]  each interval a force's
//                                     source is nonzero, up to the variant's duration; force
//                                     at its peak (unit direction); survived: no fall within
//                                     3 s of its end and the run lasted that long; lipm: the
//                                     pendulum's verdict at its end (push_capture.hpp) and
//                                     push_cp_shift_m, the capture point's shift by the push
// Figures: balance_com_phase.png (Fig. 7c), balance_joints.png (Fig. 7d),
// balance_knee_temperature.png, balance_footsteps.png and balance_phases.png.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "balance_runs.hpp"
#include "damping_replay.hpp"
#include "experiment_support.hpp"
#include "push_capture.hpp"
#include "dmbd/wholebody/capture.hpp"
#include "dmbd/control/balance_controller.hpp"
#include "dmbd/experiments/experiment.hpp"

namespace dmbd::experiments {

namespace {

using detail::BalanceParams;
using detail::BalanceRun;
using detail::signal;
using detail::stacked_axes;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// RMS over the landings of the distance between the latched landed and planned points.
double landing_error_rms(const BalanceRun& run, const std::string& file) {
  const auto& lx = signal(run.r, run.prefix + "landed_x", file);
  const auto& ly = signal(run.r, run.prefix + "landed_y", file);
  const auto& px = signal(run.r, run.prefix + "planned_x", file);
  const auto& py = signal(run.r, run.prefix + "planned_y", file);
  double sq = 0;
  for (std::size_t k : run.landings) sq += (lx[k] - px[k]) * (lx[k] - px[k]) + (ly[k] - py[k]) * (ly[k] - py[k]);
  return run.landings.empty() ? kNaN : std::sqrt(sq / static_cast<double>(run.landings.size()));
}

// The fraction of the steps [touch-down i, touch-down i+1] whose samples hold both a
// positive and a negative com_vy (a sign change between two of its samples; a change
// across a touch-down belongs to the step it ends).
double reversal_fraction(const BalanceRun& run, const std::string& file) {
  const auto& vy = signal(run.r, run.prefix + "com_vy", file);
  const std::size_t n = run.touch_downs.size() < 2 ? 0 : run.touch_downs.size() - 1;
  std::size_t reversed = 0;
  for (std::size_t i = 0; i < n; ++i) {
    bool pos = false, neg = false;
    for (std::size_t k = run.touch_downs[i]; k <= run.touch_downs[i + 1]; ++k) {
      pos = pos || vy[k] > 0;
      neg = neg || vy[k] < 0;
    }
    if (pos && neg) ++reversed;
  }
  return n ? static_cast<double>(reversed) / static_cast<double>(n) : kNaN;
}

// The largest horizontal distance of the CoM from where it was at the first touch-down,
// up to the fall, into m (com_max_distance_m and _at_s; null without a touch-down).
void com_excursion(const BalanceRun& run, const std::string& file, nlohmann::json& m) {
  m["com_max_distance_m"] = nullptr;
  m["com_max_distance_at_s"] = nullptr;
  if (run.touch_downs.empty()) return;
  const auto& x = signal(run.r, run.prefix + "com_x", file);
  const auto& y = signal(run.r, run.prefix + "com_y", file);
  const std::size_t k0 = run.touch_downs.front();
  double best = 0.0;
  std::size_t at = k0;
  for (std::size_t k = k0; k < run.fall; ++k) {
    const double d = std::hypot(x[k] - x[k0], y[k] - y[k0]);
    if (d > best) best = d, at = k;
  }
  m["com_max_distance_m"] = best;
  m["com_max_distance_at_s"] = run.t[at];
}

double peak(const std::vector<double>& x) {
  double m = -std::numeric_limits<double>::infinity();
  for (double v : x)
    if (v > m) m = v;  // NaN skipped
  return m;
}

// The windings' largest temperature (over `joints`) per thermal model: J.T_winding_cooled and
// _uncooled, or J.T_winding under the variant's one cooling mode. Nothing without them.
void winding_metrics(const VariantResult& r, Cooling cooling, const std::vector<std::string>& joints, nlohmann::json& m) {
  const std::pair<const char*, const char*> modes[] = {
      {"_cooled", "cooled"}, {"_uncooled", "uncooled"}, {"", cooling == Cooling::Off ? "uncooled" : "cooled"}};
  for (const auto& [suffix, mode] : modes)
    for (const auto& joint : joints) {
      const int c = r.log.find(joint + ".T_winding" + suffix);
      if (c < 0) continue;
      nlohmann::json& slot = m["peak_winding_C"][mode];
      const double p = peak(r.log.column(c));
      slot = slot.is_null() ? p : std::max(slot.get<double>(), p);
    }
}

// When the uncooled windings (any of `joints`) first passed `above_C`, null if never; and
// Fig. 7d's contrast over the run: holds when the cooled peak stayed below `below_C` and
// the uncooled one passed `above_C` (the simulated temperatures decide it exactly).
// Nothing for a run without uncooled windings logged (ideal joints).
void thermal_contrast(const VariantResult& r, const BalanceParams& p, nlohmann::json& m) {
  if (!p.uncooled_above_C) return;
  double first = std::numeric_limits<double>::infinity();
  bool logged = false;
  for (const auto& joint : p.winding_joints) {
    const int c = r.log.find(joint + ".T_winding_uncooled");
    if (c < 0) continue;
    logged = true;
    const auto& T = r.log.column(c);
    for (std::size_t k = 0; k < T.size(); ++k)
      if (T[k] > *p.uncooled_above_C) {
        first = std::min(first, r.log.time()[k]);
        break;
      }
  }
  if (!logged) return;
  m["uncooled_passes_s"] = std::isfinite(first) ? nlohmann::json(first) : nlohmann::json(nullptr);
  const nlohmann::json& peaks = m.value("peak_winding_C", nlohmann::json::object());
  if (!p.cooled_below_C || !peaks.contains("cooled") || !peaks.contains("uncooled")) return;
  const bool holds = peaks["cooled"].get<double>() < *p.cooled_below_C && std::isfinite(first);
  m["thermal_contrast"] = holds ? "holds" : "fails";
}

// ---------------------------------------------------------------- metrics
// A logged count as a JSON integer (null if not finite).
nlohmann::json count(double x) { return std::isfinite(x) ? nlohmann::json(std::llround(x)) : nlohmann::json(nullptr); }

void run_metrics(const BalanceRun& run, const BalanceParams& p, const VariantFacts& v, const std::string& file, nlohmann::json& m) {
  m["fell"] = run.fell();
  if (run.fell()) m["fall_time_s"] = run.end_s();
  m["balanced_s"] = std::max(0.0, run.end_s() - p.start_s);
  const auto& td = signal(run.r, run.prefix + "touch_downs", file);
  m["steps"] = count(td[run.fell() ? (run.fall ? run.fall - 1 : 0) : td.size() - 1]);
  m["landing_error_rms_m"] = landing_error_rms(run, file);
  m["com_lateral_velocity_reversals"] = reversal_fraction(run, file);
  com_excursion(run, file, m);
  const detail::SwingPeaks swing = detail::swing_peaks(run, file);
  m["swing_foot_peak_speed_m_s"] = swing.speed_m_s;
  m["swing_foot_peak_accel_m_s2"] = swing.accel_m_s2;
  winding_metrics(run.r, v.cooling, p.winding_joints, m);
  thermal_contrast(run.r, p, m);
  for (const char* stat : {"median", "max"})
    if (const auto it = run.r.timing_us.find(std::string("wbc_tick_us_") + stat); it != run.r.timing_us.end()) m["wbc_tick_us"][stat] = it->second;
  m["real_time_factor"] = run.r.real_time_factor;
  m["qp_failures"] = count(signal(run.r, run.prefix + "qp_failures", file).back());
  m["pushes"] = detail::push_metrics(run, v, p.reach, file);
}

// ---------------------------------------------------------------- figures
plot::Series part(const std::string& label, const std::vector<double>& x, const std::vector<double>& y, std::size_t from,
                  std::size_t to, plot::Color color, double width = 2.0) {
  plot::Series s{label, {}, {}, color, width};
  for (std::size_t k = from; k < to && k < x.size(); ++k) {
    s.x.push_back(x[k]);
    s.y.push_back(y[k]);
  }
  return s;
}

// The step boundaries from the start: stepping's start, then each touch-down after it.
std::vector<std::size_t> step_bounds(const BalanceRun& run) {
  std::vector<std::size_t> b{run.start};
  for (std::size_t k : run.touch_downs)
    if (k > run.start) b.push_back(k);
  return b;
}

// The lateral CoM phase portrait of each variant's stepping (before the fall), steps 5
// and 6 (or the last two) highlighted.
plot::Figure com_phase_figure(const std::vector<BalanceRun>& runs, const BalanceParams& p, const std::string& file) {
  plot::Figure fig(1000, 100 + 550 * static_cast<int>(runs.size()));
  fig.title = labelled(*p.setup, "balance_com_phase", "Lateral CoM phase portrait, stepping in place");
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const BalanceRun& run = runs[i];
    auto& a = fig.axes().emplace_back();
    a.title = run.r.name;
    a.x_label = "CoM y (m)";
    a.y_label = "CoM vy (m/s)";
    const auto& y = signal(run.r, run.prefix + "com_y", file);
    const auto& vy = signal(run.r, run.prefix + "com_vy", file);
    a.series.push_back(part("stepping", y, vy, run.start, run.fall, plot::Color{170, 170, 170}, 1.0));
    const auto b = step_bounds(run);
    const std::size_t n = b.size() - 1, first = n >= 6 ? 5 : std::max<std::size_t>(n, 2) - 1;
    for (std::size_t j = first; j <= std::min(n, first + 1); ++j)
      a.series.push_back(part(fmt::format("step {}", j), y, vy, b[j - 1], b[j] + 1, plot::palette_color(j - first), 2.5));
  }
  return fig;
}

// The leg's joints: those with a target in the log whose names start with `leg`.
std::vector<std::string> leg_joints(const VariantResult& r, const std::string& leg) {
  std::vector<std::string> out;
  for (int c = 0; c < static_cast<int>(r.log.columns()); ++c)
    if (const std::string& name = r.log.name(c); name.rfind(leg, 0) == 0 && name.size() > 6 && name.compare(name.size() - 6, 6, ".q_des") == 0)
      out.push_back(name.substr(0, name.size() - 6));
  return out;
}

plot::Figure joints_figure(const std::vector<BalanceRun>& runs, const BalanceParams& p, const std::string& file) {
  const auto joints = leg_joints(runs.front().r, p.leg);
  plot::Figure fig(1200, 200 * static_cast<int>(std::max<std::size_t>(joints.size(), 1)) + 100);
  fig.title = labelled(*p.setup, "balance_joints", "Joint positions of the leg, desired (dashed) and measured");
  for (std::size_t j = 0; j < joints.size(); ++j) {
    auto& a = stacked_axes(fig, joints[j] + " (rad)", j + 1 == joints.size());
    a.legend = j == 0;
    for (std::size_t i = 0; i < runs.size(); ++i) {
      const auto& r = runs[i].r;
      const std::string prefix = runs.size() > 1 ? r.name + " " : "";
      a.series.push_back({prefix + "desired", r.log.time(), signal(r, joints[j] + ".q_des", file), plot::palette_color(i), 1.5, true});
      a.series.push_back({prefix + "measured", r.log.time(), signal(r, joints[j] + ".q", file), plot::palette_color(i)});
    }
  }
  return fig;
}

// The knees' winding temperatures (every thermal column of both knees); none: no figure.
std::optional<plot::Figure> knee_temperature_figure(const std::vector<BalanceRun>& runs, const BalanceParams& p) {
  plot::Figure fig(1200, 600);
  fig.title = labelled(*p.setup, "balance_knee_temperature", "Winding temperature");
  auto& a = fig.add_axes();
  a.x_label = "Time (s)";
  a.y_label = "Winding (deg C)";
  a.h_lines = {130};
  a.h_line_labels = {"130 C rating"};
  for (const auto& run : runs)
    for (const auto& knee : p.winding_joints)
      for (const char* suffix : {"_cooled", "_uncooled", ""}) {
        const std::string col = knee + ".T_winding" + suffix;
        if (run.r.log.find(col) < 0) continue;
        const std::string mode = *suffix ? std::string(" ") + (suffix + 1) : "";
        a.series.push_back({(runs.size() > 1 ? run.r.name + ": " : "") + knee + mode, run.t, run.r.log.column(col)});
      }
  if (a.series.empty()) return std::nullopt;
  return fig;
}

// Isolated points (markers only): NaN between them breaks the line.
plot::Series points(const std::string& label, const std::vector<double>& x, const std::vector<double>& y,
                    const std::vector<std::size_t>& at, plot::Color color) {
  plot::Series s{label, {}, {}, color, 1.0, false, true};
  for (std::size_t k : at) {
    s.x.insert(s.x.end(), {x[k], kNaN});
    s.y.insert(s.y.end(), {y[k], kNaN});
  }
  return s;
}

plot::Figure footsteps_figure(const std::vector<BalanceRun>& runs, const BalanceParams& p, const std::string& file) {
  plot::Figure fig(1000, 100 + 600 * static_cast<int>(runs.size()));
  fig.title = labelled(*p.setup, "balance_footsteps", "Footsteps from above: planned and landed at each landing, and the CoM");
  for (const auto& run : runs) {
    auto& a = fig.axes().emplace_back();
    a.title = run.r.name;
    a.x_label = "x (m)";
    a.y_label = "y (m)";
    a.series.push_back(part("CoM", signal(run.r, run.prefix + "com_x", file), signal(run.r, run.prefix + "com_y", file), run.start, run.fall,
                            plot::Color{150, 150, 150}, 1.0));
    a.series.push_back(points("planned", signal(run.r, run.prefix + "planned_x", file), signal(run.r, run.prefix + "planned_y", file),
                              run.landings, plot::palette_color(0)));
    a.series.push_back(points("landed", signal(run.r, run.prefix + "landed_x", file), signal(run.r, run.prefix + "landed_y", file),
                              run.landings, plot::palette_color(3)));
  }
  return fig;
}

plot::Figure phases_figure(const std::vector<BalanceRun>& runs, const BalanceParams& p, const std::string& file) {
  plot::Figure fig(1200, 1000);
  fig.title = labelled(*p.setup, "balance_phases", "Balancing: phase, swing side, torso height and tilt");
  struct Row {
    std::string signal;
    const char* label;
    double limit;
  };
  const Row rows[] = {{p.prefix + "phase", "Phase", kNaN},
                      {p.prefix + "swing_side", "Swing side (0 l, 1 r)", kNaN},
                      {"base.z", "Torso z (m)", p.fall_height_m},
                      {"base.tilt", "Tilt (rad)", p.fall_tilt_rad}};
  for (const auto& row : rows) {
    auto& a = stacked_axes(fig, row.label, &row == &rows[3]);
    a.legend = &row == &rows[0];
    a.v_lines = {p.start_s};
    a.v_line_labels = {"stepping"};
    if (!std::isnan(row.limit)) {
      a.h_lines = {row.limit};
      a.h_line_labels = {"fall"};
    }
    for (std::size_t i = 0; i < runs.size(); ++i)
      a.series.push_back({runs[i].r.name, runs[i].t, signal(runs[i].r, row.signal, file), plot::palette_color(i)});
  }
  return fig;
}

void add_figures(const std::vector<BalanceRun>& runs, const BalanceParams& p, const std::string& file, ExperimentResult& res) {
  if (runs.empty()) return;
  res.figures.emplace_back("balance_com_phase.png", com_phase_figure(runs, p, file));
  res.figures.emplace_back("balance_joints.png", joints_figure(runs, p, file));
  if (auto fig = knee_temperature_figure(runs, p)) res.figures.emplace_back("balance_knee_temperature.png", std::move(*fig));
  res.figures.emplace_back("balance_footsteps.png", footsteps_figure(runs, p, file));
  res.figures.emplace_back("balance_phases.png", phases_figure(runs, p, file));
}

// The knees' output damping replayed (`replay_scales`: damping_replay.hpp) on a run that
// stood: its metrics under balance.RUN.damping_replay, a figure, the verdict as a note.
void add_replay(const BalanceRun& run, const ExperimentSetup& e, const BalanceParams& p, ExperimentResult& res) {
  const auto scales = e.numbers.find("replay_scales");
  if (scales == e.numbers.end()) return;
  if (run.fell()) {
    res.warnings.push_back(fmt::format("variant '{}' fell: its motion is not replayed with other output damping", run.r.name));
    return;
  }
  detail::ReplayParams rp{p.winding_joints, scales->second, detail::number_or(e, "replay_duration_s", 600.0),
                          detail::number_or(e, "replay_from_s", p.start_s), std::nullopt, std::nullopt};
  if (e.number.count("replay_cooled_below_C")) rp.cooled_below_C = e.number.at("replay_cooled_below_C");
  if (e.number.count("replay_uncooled_above_C")) rp.uncooled_above_C = e.number.at("replay_uncooled_above_C");
  const auto out = detail::replay_damping(run.r, rp, e.file);
  if (!out) return;  // no actuator on the windings' joints (ideal joints)
  res.metrics["balance"][run.r.name]["damping_replay"] = out->metrics;
  res.figures.emplace_back("balance_damping_replay_" + detail::file_safe(run.r.name) + ".png", out->figure);
  res.notes.push_back(out->note);
}

ExperimentResult balance(const ExperimentSetup& e, const std::vector<VariantResult>& runs, const std::vector<VariantFacts>& variants) {
  const BalanceParams p = detail::read_balance_params(e, variants);
  ExperimentResult res;
  std::vector<BalanceRun> analysed;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const VariantResult& r = runs[k];
    if (r.log.rows() == 0) {
      res.warnings.push_back(fmt::format("variant '{}' logged no samples: no metrics", r.name));
      continue;
    }
    analysed.push_back(detail::analyse_run(r, p, e.file));
    const BalanceRun& run = analysed.back();
    if (run.t.back() < p.start_s)
      res.warnings.push_back(fmt::format("variant '{}': the run ends before stepping starts ({} s)", r.name, p.start_s));
    if (run.fell()) res.warnings.push_back(fmt::format("variant '{}' fell at t = {:.3f} s", r.name, run.end_s()));
    run_metrics(run, p, variants[k], e.file, res.metrics["balance"][r.name]);
    add_replay(run, e, p, res);
  }
  add_figures(analysed, p, e.file, res);
  res.notes.push_back(fmt::format("Fell: torso below {} m or tilted beyond {} rad; stepping from t = {} s; steps, landing errors and CoM "
                                  "velocity reversals up to the fall. A push survived when the robot did not fall within {} s of its end "
                                  "and the run lasted that long.",
                                  p.fall_height_m, p.fall_tilt_rad, p.start_s, detail::kSurviveAfterPushS));
  return res;
}

}  // namespace

namespace {

// Fig. 7d's thresholds come together and judge named windings (before the run: a
// mistake there is found before minutes of stepping).
void check_winding_thresholds(const ExperimentSetup& e) {
  const bool below = e.number.count("winding_cooled_below_C"), above = e.number.count("winding_uncooled_above_C");
  if (!below && !above) return;
  const std::string at = e.where.at(below ? "winding_cooled_below_C" : "winding_uncooled_above_C");
  if (below != above)
    throw InputError(at + ": experiment " + e.type + ": give winding_cooled_below_C and winding_uncooled_above_C together (Fig. 7d's contrast)");
  if (!e.names.count("winding_joints"))
    throw InputError(at + ": experiment " + e.type + ": winding_cooled_below_C needs winding_joints (whose windings are judged)");
}

// Its keys: the shared ones (balance_runs.hpp) and its own.
std::map<std::string, KeyKind> balance_experiment_keys() {
  std::map<std::string, KeyKind> k = detail::balance_keys();
  k.insert({{"leg", KeyKind::Text},
            {"winding_joints", KeyKind::Joints},
            {"replay_scales", KeyKind::Numbers},
            {"replay_duration_s", KeyKind::Number},
            {"replay_from_s", KeyKind::Number},
            {"replay_cooled_below_C", KeyKind::Number},
            {"replay_uncooled_above_C", KeyKind::Number},
            {"winding_cooled_below_C", KeyKind::Number},
            {"winding_uncooled_above_C", KeyKind::Number}});
  return k;
}

// The balance experiment records what the damping replay needs of the windings' actuators.
class BalanceExperiment : public detail::FunctionExperiment {
 public:
  BalanceExperiment()
      : FunctionExperiment(balance_experiment_keys(),
                           false,
                           [](const ExperimentSetup& e, const std::vector<VariantResult>& runs, const std::vector<VariantFacts>& variants) {
                             return balance(e, runs, variants);
                           }) {}
  void record(const ExperimentSetup& e, const RecordContext& c, std::map<std::string, double>& truth) const override {
    Experiment::record(e, c, truth);
    check_winding_thresholds(e);
    const auto scales = e.numbers.find("replay_scales");
    if (scales == e.numbers.end()) return;
    const std::string at = e.where.count("replay_scales") ? e.where.at("replay_scales") : e.file;
    for (double s : scales->second)
      if (!(s >= 0)) throw InputError(fmt::format("{}: experiment.replay_scales: expected factors >= 0, got {}", at, s));
    if (detail::number_or(e, "replay_duration_s", 600.0) <= 0)
      throw InputError(e.where.at("replay_duration_s") + ": experiment.replay_duration_s: expected a duration > 0");
    const auto joints = e.names.find("winding_joints");
    if (joints == e.names.end()) throw InputError(at + ": experiment.replay_scales: expected winding_joints too (the joints replayed)");
    detail::record_replay(joints->second, c, truth);
  }
};

}  // namespace

std::shared_ptr<const Experiment> balance_experiment() { return std::make_shared<BalanceExperiment>(); }

}  // namespace dmbd::experiments
