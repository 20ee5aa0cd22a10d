// What the balance experiments read of a balancing run (balance_runs.hpp).
#include "balance_runs.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "dmbd/control/balance_controller.hpp"
#include "dmbd/wholebody/capture.hpp"
#include "dmbd/wholebody/phase_machine.hpp"

namespace dmbd::experiments::detail {

BalanceRun analyse_run(const VariantResult& r, const BalanceParams& p, const std::string& file) {
  BalanceRun run{r, r.log.time(), p.prefix};
  const auto& t = run.t;
  const auto& z = signal(r, "base.z", file);
  const auto& tilt = signal(r, "base.tilt", file);
  run.start = static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), p.start_s) - t.begin());
  run.fall = t.size();
  for (std::size_t k = 0; k < t.size() && run.fall == t.size(); ++k)
    if (z[k] < p.fall_height_m || tilt[k] > p.fall_tilt_rad) run.fall = k;
  const auto& td = signal(r, p.prefix + "touch_downs", file);
  const auto& landed = signal(r, p.prefix + "landings", file);
  for (std::size_t k = 1; k < run.fall; ++k) {
    if (td[k] > td[k - 1]) run.touch_downs.push_back(k);
    if (landed[k] > landed[k - 1]) run.landings.push_back(k);
  }
  return run;
}

SwingPeaks swing_peaks(const BalanceRun& run, const std::string& file) {
  const auto& x = signal(run.r, run.prefix + "swing_x", file);
  const auto& y = signal(run.r, run.prefix + "swing_y", file);
  const auto& phase = signal(run.r, run.prefix + "phase", file);
  const auto& step = signal(run.r, run.prefix + "step", file);
  const auto& t = run.t;
  const double swing = static_cast<double>(static_cast<int>(wholebody::Phase::Swing));
  SwingPeaks out{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  for (std::size_t k = std::max<std::size_t>(run.start, 2); k + 2 < run.fall; ++k) {
    bool inside = true;
    for (std::size_t j = k - 2; j <= k + 2; ++j) inside = inside && phase[j] == swing && step[j] == step[k];
    if (!inside) continue;
    const double h1 = t[k + 1] - t[k - 1], h2 = 0.5 * (t[k + 2] - t[k - 2]);
    const double v = std::hypot(x[k + 1] - x[k - 1], y[k + 1] - y[k - 1]) / h1;
    const double a = std::hypot(x[k + 2] - 2 * x[k] + x[k - 2], y[k + 2] - 2 * y[k] + y[k - 2]) / (h2 * h2);
    out.speed_m_s = std::isnan(out.speed_m_s) ? v : std::max(out.speed_m_s, v);
    out.accel_m_s2 = std::isnan(out.accel_m_s2) ? a : std::max(out.accel_m_s2, a);
  }
  return out;
}

std::map<std::string, KeyKind> balance_keys() {
  return {{"start_s", KeyKind::Number},
          {"fall_height_m", KeyKind::Number},
          {"fall_tilt_rad", KeyKind::Number},
          {"swing_speed_max_m_s", KeyKind::Number},
          {"swing_accel_max_m_s2", KeyKind::Number}};
}

BalanceParams read_balance_params(const ExperimentSetup& e, const std::vector<VariantFacts>& variants) {
  std::string prefix = "balance.";  // the balancing controller's signals: from the first variant that has one
  for (const auto& v : variants)
    if (const auto* b = v.bus_controller<control::BalanceSetup>()) {
      prefix = b->name + ".";
      break;
    }
  BalanceParams p{text_or(e, "leg", ""), number_or(e, "start_s", 4.0), number_or(e, "fall_height_m", 0.6), number_or(e, "fall_tilt_rad", 0.5),
                  prefix, {}, std::nullopt, std::nullopt, std::nullopt, &e};
  if (const auto it = e.names.find("winding_joints"); it != e.names.end()) p.winding_joints = it->second;
  if (e.number.count("winding_cooled_below_C") && e.number.count("winding_uncooled_above_C")) {  // checked before the run
    p.cooled_below_C = e.number.at("winding_cooled_below_C");
    p.uncooled_above_C = e.number.at("winding_uncooled_above_C");
  }
  if (e.number.count("swing_speed_max_m_s") != e.number.count("swing_accel_max_m_s2"))
    throw InputError(e.file + ": experiment " + e.type + ": give swing_speed_max_m_s and swing_accel_max_m_s2 together (the swing foot's reach)");
  if (e.number.count("swing_speed_max_m_s")) {
    p.reach = SwingLimits{e.number.at("swing_speed_max_m_s"), e.number.at("swing_accel_max_m_s2")};
    if (!(p.reach->speed_m_s > 0) || !(p.reach->accel_m_s2 > 0))
      throw InputError(e.where.at("swing_speed_max_m_s") + ": experiment " + e.type + ": the swing foot's speed and acceleration limits must be > 0");
  }
  return p;
}

namespace {

// The scenario's pushes up to the variant's duration, also those a run ended (by a fall)
// before reaching: they were not survived.
struct Push {
  double start_s, end_s, peak_N = 0;
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // of the force at its peak, unit
};

void switch_times(const Source& s, std::vector<double>& out) {
  out.push_back(s.start_s);
  if (s.duration_s > 0) out.push_back(s.start_s + s.duration_s);
  for (const auto& step : s.steps) out.push_back(step.first);
  for (const auto& p : s.plus) switch_times(p, out);
}

// The times (on the run's clock) a source started at `start` is read at: the log's
// samples from `start` on, the source's own switching times moved by `start` up to t_end
// (a step's exact start and end however coarse the log, and the pushes of a run that
// ended early), `start` and t_end.
std::vector<double> push_grid(const std::vector<double>& t, const Source& s, double start, double t_end) {
  std::vector<double> g, extra{start, t_end};
  switch_times(s, extra);
  for (double x : t)
    if (x >= start) g.push_back(x);
  for (std::size_t k = 2; k < extra.size(); ++k) extra[k] += start;
  for (double x : extra)
    if (x >= std::max(start, t.front()) && x <= t_end) g.push_back(x);
  std::sort(g.begin(), g.end());
  g.erase(std::unique(g.begin(), g.end()), g.end());
  return g;
}

// Each interval up to t_end over which the force's source is nonzero (one still on at
// t_end ends there). A force started by a trigger runs its source from `start` (the
// logged forces.K.start_s); one never started pushed nothing.
void find_pushes(const ForceSpec& f, const std::vector<double>& t, double t_end, double start, std::vector<Push>& out) {
  const double scale = f.direction_W.norm();
  if (scale == 0 || t.empty() || !std::isfinite(start)) return;
  const auto g = push_grid(t, f.source, start, t_end);
  bool on = false;
  for (double x : g) {
    const double v = f.source.value(x - start);
    if (v == 0) {
      if (on) out.back().end_s = x;
      on = false;
      continue;
    }
    if (!on) out.push_back({x, g.back()});
    on = true;
    if (std::abs(v) * scale > out.back().peak_N) {
      out.back().peak_N = std::abs(v) * scale;
      out.back().direction = f.direction_W * (v > 0 ? 1.0 : -1.0) / scale;
    }
  }
}

// The pendulum's verdict at the push's end (push_capture.hpp) and the capture point's
// shift by the push itself, F/(mω²)(e^{ωτ} − 1) with the horizontal part of F and the
// robot's total mass.
nlohmann::json push_lipm(const BalanceRun& run, const VariantFacts& v, const Push& p, const std::optional<SwingLimits>& reach,
                         const std::string& file) {
  const auto mass = run.r.truth.find("total_mass_kg");
  const auto* balance = v.bus_controller<control::BalanceSetup>();
  if (!balance || mass == run.r.truth.end()) return nullptr;
  nlohmann::json out = push_capture(run.r, *balance, v.gravity_m_s2, p.end_s, file, reach);
  if (out.is_null()) out = {{"capturable", nullptr}};  // the run ended before, or not stepping
  const double force = p.peak_N * p.direction.head<2>().norm();
  out["push_cp_shift_m"] = wholebody::push_capture_point_shift(force, p.end_s - p.start_s, mass->second, pendulum_omega(*balance, v.gravity_m_s2));
  return out;
}

}  // namespace

nlohmann::json push_metrics(const BalanceRun& run, const VariantFacts& v, const std::optional<SwingLimits>& reach, const std::string& file) {
  std::vector<Push> pushes;
  for (std::size_t k = 0; k < v.forces.size(); ++k) {
    double start = 0.0;  // on the run's clock
    if (v.forces[k].trigger) {
      const int c = run.r.log.find(fmt::format("forces.{}.start_s", k));
      start = c < 0 ? NAN : run.r.log.column(c).back();
    }
    find_pushes(v.forces[k], run.t, std::max(run.t.back(), v.duration_s), start, pushes);
  }
  std::sort(pushes.begin(), pushes.end(), [](const Push& a, const Push& b) { return a.start_s < b.start_s; });
  nlohmann::json out = nlohmann::json::array();
  for (const auto& p : pushes) {
    const double until = p.end_s + kSurviveAfterPushS;
    const bool survived = run.t.back() >= until - 1e-9 && !(run.fell() && run.end_s() <= until);
    out.push_back({{"start_s", p.start_s},
                   {"duration_s", p.end_s - p.start_s},
                   {"force_N", p.peak_N},
                   {"direction", nlohmann::json::array({p.direction.x(), p.direction.y(), p.direction.z()})},
                   {"survived", survived},
                   {"lipm", push_lipm(run, v, p, reach, file)}});
  }
  return out;
}

}  // namespace dmbd::experiments::detail
