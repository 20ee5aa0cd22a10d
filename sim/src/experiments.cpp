// The paper's experiments: metrics and figures from a scenario's variant logs.
#include "dmbd/sim/experiments.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <fmt/format.h>

#include "dmbd/blocks/error.hpp"
#include "experiment_support.hpp"

namespace dmbd::sim {

namespace {

const VariantResult& find_run(const std::vector<VariantResult>& runs, const std::string& name, const std::string& file) {
  for (const auto& r : runs)
    if (r.name == name) return r;
  throw InputError(file + ": no variant is named '" + name + "'");
}

using detail::number_or;
using detail::signal;
using detail::text_or;

// Nested JSON position for a run: metrics[a1][a2]... by its matrix axes (its name
// without axes).
nlohmann::json& nest(nlohmann::json& root, const VariantResult& r) {
  nlohmann::json* j = &root;
  if (r.axes.empty()) return (*j)[r.name];
  for (std::size_t k = 0; k + 1 < r.axes.size(); ++k) j = &(*j)[r.axes[k].second];
  return (*j)[r.axes.back().second];
}

double value_at(const std::vector<double>& t, const std::vector<double>& x, double ts) {
  const auto it = std::lower_bound(t.begin(), t.end(), ts - 1e-12);
  return it == t.end() ? x.back() : x[static_cast<std::size_t>(it - t.begin())];
}

// ---------------------------------------------------------------- step response
ExperimentResult step_response(const Scenario& s, const std::vector<VariantResult>& runs) {
  const ExperimentSetup& e = s.experiment;
  const std::string ref = text_or(e, "reference", "q_d"), out = text_or(e, "output", e.joint + ".q");
  const double t_step = number_or(e, "step_start_s", 0.5), t_step_end = number_or(e, "step_end_s", 2.0);
  const double t_sine = number_or(e, "sine_start_s", -1), t_sine_end = number_or(e, "sine_end_s", -1);
  ExperimentResult res;
  plot::Figure step_fig(1200, 700), sine_fig(1200, 800);
  step_fig.title = "Step response, " + e.joint;
  auto& ax = step_fig.add_axes();
  ax.x_label = "Time (s)";
  ax.y_label = "Joint angle (rad)";
  ax.x_limits = std::make_pair(t_step - 0.05, std::min(t_step_end, t_step + 0.6));
  sine_fig.title = "Sinusoid tracking, " + e.joint;
  auto& sx = sine_fig.add_axes();
  sx.x_label = "Time (s)";
  sx.y_label = "Joint angle (rad)";
  auto& sxe = sine_fig.add_axes();
  sxe.x_label = "Time (s)";
  sxe.y_label = "Tracking error (rad)";
  bool ref_drawn = false;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const auto& r = runs[k];
    const plot::Color color = plot::palette_color(k);  // one colour per variant in every figure
    const auto& t = r.log.time();
    const auto& rv = signal(r, ref, s.file);
    const auto& y = signal(r, out, s.file);
    const StepMetrics m = step_metrics(t, rv, y, t_step, t_step_end);
    nlohmann::json& j = res.metrics["controllers"][r.name];
    j["overshoot_pct"] = m.overshoot_pct;
    j["rise_time_s"] = m.rise_time_s;
    j["steady_state_error_rad"] = m.steady_state_error;
    j["rms_error_rad"] = t_sine >= 0 ? rms_error(t, rv, y, t_sine, t_sine_end) : rms_error(t, rv, y, t.front(), t.back());
    if (!ref_drawn) {
      ax.series.push_back({"reference", t, rv, plot::Color{1, 1, 1}, 1.5, true});
      if (t_sine >= 0) sx.series.push_back({"reference", t, rv, plot::Color{1, 1, 1}, 1.5, true});
      ref_drawn = true;
    }
    ax.series.push_back({r.name, t, y, color});
    if (t_sine >= 0) {
      std::vector<double> err(t.size());
      for (std::size_t i = 0; i < t.size(); ++i) err[i] = y[i] - rv[i];
      sx.series.push_back({r.name, t, y, color});
      sxe.series.push_back({r.name, t, err, color});
    }
    if (t.back() < t_step_end || (t_sine >= 0 && t.back() < t_sine_end))
      res.warnings.push_back(fmt::format("variant '{}' ends at {} s, before the end of the experiment's windows ({} s): its step and "
                                         "tracking figures are of the part it ran (inf or NaN where a figure was not reached)",
                                         r.name, t.back(), std::max(t_step_end, t_sine_end)));
  }
  if (t_sine >= 0) {
    sx.x_limits = sxe.x_limits = std::make_pair(t_sine, t_sine_end);
    sx.x_tick_labels = false;
  }
  // The y range of what is shown (the runs go on to a sinusoid outside the window).
  ax.y_limits_from_visible = true;
  res.figures.emplace_back("step_response.png", step_fig);
  if (t_sine >= 0) res.figures.emplace_back("sine_tracking.png", sine_fig);
  res.notes.push_back(fmt::format("Step metrics over [{}, {}] s of '{}' following '{}'; RMS error over [{}, {}] s.", t_step, t_step_end, out, ref,
                                  t_sine, t_sine_end));
  return res;
}

// ---------------------------------------------------------------- force tracking
ExperimentResult force_tracking(const Scenario& s, const std::vector<VariantResult>& runs) {
  const ExperimentSetup& e = s.experiment;
  const std::string ref = text_or(e, "reference", "F_d"), out = text_or(e, "output", e.joint + ".force_true");
  const double t0 = number_or(e, "start_s", 0.0);
  ExperimentResult res;
  // One axes per value of the last matrix axis (the load), a series per first-axis value.
  std::vector<std::string> groups;
  for (const auto& r : runs) {
    const std::string g = r.axes.empty() ? r.name : r.axes.back().second;
    if (std::find(groups.begin(), groups.end(), g) == groups.end()) groups.push_back(g);
  }
  plot::Figure fig(1200, std::max(400, 220 * static_cast<int>(groups.size())));
  fig.title = "Force tracking error F - F_d";
  for (const auto& g : groups) {
    auto& a = fig.add_axes();
    a.title = "load " + g;
    a.y_label = "Error (N)";
    a.x_tick_labels = false;
  }
  fig.axes().back().x_label = "Time (s)";
  fig.axes().back().x_tick_labels = true;
  const double t_show = number_or(e, "plot_window_s", 0.5);
  for (const auto& r : runs) {
    const auto& t = r.log.time();
    const auto& rv = signal(r, ref, s.file);
    const auto& y = signal(r, out, s.file);
    nest(res.metrics["rms_error_N"], r) = rms_error(t, rv, y, t0, t.back());
    const std::string g = r.axes.empty() ? r.name : r.axes.back().second;
    auto& a = fig.axes()[static_cast<std::size_t>(std::find(groups.begin(), groups.end(), g) - groups.begin())];
    std::vector<double> tt, err;
    for (std::size_t k = 0; k < t.size(); ++k)
      if (t[k] >= t0 && t[k] <= t0 + t_show) {
        tt.push_back(t[k]);
        err.push_back(y[k] - rv[k]);
      }
    a.series.push_back({r.axes.empty() ? r.name : r.axes.front().second, tt, err});
  }
  res.figures.emplace_back("force_error.png", fig);
  // The tracking itself for the heaviest finite load and the first controller.
  const VariantResult& first = runs.front();
  plot::Figure tf(1200, 500);
  tf.title = "Force tracking, " + first.name;
  auto& a = tf.add_axes();
  a.x_label = "Time (s)";
  a.y_label = "Actuator force (N)";
  a.x_limits = std::make_pair(t0, t0 + t_show);
  a.series.push_back({"F_d", first.log.time(), signal(first, ref, s.file), plot::Color{1, 1, 1}, 1.5, true});
  a.series.push_back({"F (true)", first.log.time(), signal(first, out, s.file)});
  a.series.push_back({"F (sensed)", first.log.time(), signal(first, e.joint + ".force", s.file), plot::Color{}, 1.0});
  res.figures.emplace_back("force_tracking.png", tf);
  res.notes.push_back(fmt::format("RMS of '{}' - '{}' from t = {} s to the end of each run.", out, ref, t0));
  return res;
}

// ---------------------------------------------------------------- thermal
ExperimentResult thermal(const Scenario& s, const std::vector<VariantResult>& runs) {
  const ExperimentSetup& e = s.experiment;
  ExperimentResult res;
  plot::Figure fig(1200, 800);
  fig.title = "Winding temperature, " + e.joint;
  auto& a = fig.add_axes();
  a.y_label = "Winding (deg C)";
  a.x_tick_labels = false;
  a.h_lines = {60, 100, 130};
  a.h_line_labels = {"60 C", "100 C", "130 C rating"};
  auto& c = fig.add_axes();
  c.x_label = "Time (s)";
  c.y_label = "Current (A)";
  for (const auto& r : runs) {
    const auto& t = r.log.time();
    for (const char* which : {"cooled", "uncooled"}) {
      const std::string col = e.joint + ".T_winding_" + which;
      if (r.log.find(col) < 0) continue;
      const auto& T = r.log.column(col);
      const double peak = *std::max_element(T.begin(), T.end());
      res.metrics["peak_winding_C"][which] = peak;
      a.series.push_back({std::string(which == std::string("cooled") ? "liquid cooling on" : "cooling off"), t, T});
    }
    c.series.push_back({"applied current", t, signal(r, e.joint + ".current_applied", s.file)});
    // The RMS over the whole run from the exact integral of i^2 (the log's 50 Hz samples
    // of a 1 kHz current would alias its ripple).
    const auto& i2t = signal(r, e.joint + ".i2t", s.file);
    res.metrics["rms_current_A"] = t.back() > 0 ? std::sqrt(i2t.back() / t.back()) : 0.0;
  }
  if (!res.metrics.contains("peak_winding_C"))
    throw InputError(s.file + ": experiment thermal needs `thermal: {cooling: both}` (logs " + e.joint + ".T_winding_cooled and _uncooled)");
  res.figures.emplace_back("winding_temperature.png", fig);
  res.notes.push_back("Under current control the motor current does not depend on the winding temperature, so one run drives both "
                      "thermal models (cooling on and off) with the same current.");
  return res;
}

// ---------------------------------------------------------------- standing
// A floating robot standing (and pushed): from the logged torso pose, per variant,
// fell (the torso dropped more than 0.2 m below its start or tilted beyond 0.5 rad),
// the largest tilt, the largest drop, and the tilt at the end (the push recovered).
ExperimentResult standing(const Scenario& s, const std::vector<VariantResult>& runs) {
  constexpr double kFallDrop = 0.2, kFallTilt = 0.5;
  ExperimentResult res;
  plot::Figure fig(1200, 900);
  fig.title = "Standing: torso tilt, height and lateral position";
  auto& tilt = fig.add_axes();
  tilt.y_label = "Tilt (rad)";
  tilt.x_tick_labels = false;
  auto& height = fig.add_axes();
  height.y_label = "Torso height (m)";
  height.x_tick_labels = false;
  auto& lateral = fig.add_axes();
  lateral.x_label = "Time (s)";
  lateral.y_label = "Torso y (m)";
  for (const auto& r : runs) {
    const auto& t = r.log.time();
    const auto& tl = signal(r, "base.tilt", s.file);
    const auto& z = signal(r, "base.z", s.file);
    const double max_tilt = *std::max_element(tl.begin(), tl.end());
    const double drop = z.front() - *std::min_element(z.begin(), z.end());
    nlohmann::json& m = runs.size() > 1 ? nest(res.metrics["standing"], r) : res.metrics["standing"];
    m["fell"] = drop > kFallDrop || max_tilt > kFallTilt;
    m["max_tilt_rad"] = max_tilt;
    m["torso_height_drop_m"] = drop;
    m["final_tilt_rad"] = tl.back();
    const std::string label = runs.size() > 1 ? r.name : "torso";
    tilt.series.push_back({label, t, tl});
    height.series.push_back({label, t, z});
    lateral.series.push_back({label, t, signal(r, "base.y", s.file)});
  }
  res.figures.emplace_back("standing.png", fig);
  res.notes.push_back(fmt::format("fell: the torso dropped more than {} m below its start or tilted beyond {} rad.", kFallDrop, kFallTilt));
  return res;
}

}  // namespace

StepMetrics step_metrics(const std::vector<double>& t, const std::vector<double>& r, const std::vector<double>& y, double t_step,
                         double t_end) {
  StepMetrics m;
  const double r1 = value_at(t, r, t_step), y0 = value_at(t, y, t_step);
  const double d = r1 - y0;
  if (d == 0) return m;
  double peak = -std::numeric_limits<double>::infinity();
  double t10 = -1, t90 = -1;
  double ss = 0;
  int nss = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    // [t_step, t_end): a reference that steps back at t_end is already back there.
    if (t[k] < t_step || t[k] >= t_end) continue;
    const double frac = (y[k] - y0) / d;
    peak = std::max(peak, frac);
    if (t10 < 0 && frac >= 0.1) t10 = t[k];
    if (t90 < 0 && frac >= 0.9) t90 = t[k];
    if (t[k] >= t_end - 0.2 * (t_end - t_step)) {
      ss += y[k] - r[k];
      ++nss;
    }
  }
  m.overshoot_pct = std::max(0.0, (peak - 1.0) * 100.0);
  m.rise_time_s = (t10 >= 0 && t90 >= 0) ? t90 - t10 : std::numeric_limits<double>::infinity();
  m.steady_state_error = nss ? std::abs(ss / nss) : std::numeric_limits<double>::quiet_NaN();
  return m;
}

double rms_error(const std::vector<double>& t, const std::vector<double>& r, const std::vector<double>& y, double t0, double t1) {
  double sq = 0;
  std::size_t n = 0;
  for (std::size_t k = 0; k < t.size(); ++k)
    if (t[k] >= t0 && t[k] <= t1) {
      sq += (y[k] - r[k]) * (y[k] - r[k]);
      ++n;
    }
  return n ? std::sqrt(sq / static_cast<double>(n)) : std::numeric_limits<double>::quiet_NaN();
}

ExperimentResult sysid_rfsea(const Scenario& s, const std::vector<VariantResult>& runs);  // sysid_experiment.cpp
ExperimentResult osc_table(const Scenario& s, const std::vector<VariantResult>& runs);    // osc_experiment.cpp
ExperimentResult balance(const Scenario& s, const std::vector<VariantResult>& runs);      // balance_experiment.cpp

ExperimentResult evaluate_experiment(const Scenario& s, const std::vector<VariantResult>& runs) {
  ExperimentResult res;
  const std::string& type = s.experiment.type;
  if (type == "step_response") res = step_response(s, runs);
  else if (type == "force_tracking") res = force_tracking(s, runs);
  else if (type == "thermal") res = thermal(s, runs);
  else if (type == "sysid_rfsea") res = sysid_rfsea(s, runs);
  else if (type == "standing") res = standing(s, runs);
  else if (type == "osc_table") res = osc_table(s, runs);
  else if (type == "balance") res = balance(s, runs);
  // The scenario's own plots: "signal" (every variant) or "variant:signal".
  for (const auto& p : s.plots) {
    plot::Figure fig(1200, 600);
    fig.title = p.title;
    auto& a = fig.add_axes();
    a.x_label = "Time (s)";
    a.y_label = p.y_label;
    for (const auto& sig : p.signals) {
      const auto colon = sig.find(':');
      if (colon != std::string::npos) {
        const VariantResult& r = find_run(runs, sig.substr(0, colon), s.file);
        a.series.push_back({sig, r.log.time(), signal(r, sig.substr(colon + 1), s.file)});
      } else {
        for (const auto& r : runs) a.series.push_back({runs.size() > 1 ? r.name + ": " + sig : sig, r.log.time(), signal(r, sig, s.file)});
      }
    }
    res.figures.emplace_back(p.file, fig);
  }
  return res;
}

}  // namespace dmbd::sim
