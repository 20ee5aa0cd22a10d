// The osc_table experiment (paper Fig. 6): operational space control of the
// table-mounted robot, from each variant's log of the OSC controller's outputs
// (osc_controller.hpp) and the actuators' currents.
//   ankle_rms_error_m {x, y, z}, ankle_max_error_m   the point's error over the window
//   torque_rms_error_Nm {joint}                      τ_d − τ_s (sensed) per joint of the leg
//   torque_peak_Nm {joint}                           largest |τ_d| in the window
//   current_saturation_fraction                      log samples with any of the leg's
//                                                    applied currents at its limit
//   osc_tick_us {median, max}                        one OSC evaluation's wall time
// Figures: osc_ankle.png (Fig. 6c), osc_error.png, and per variant osc_torque_RUN.png
// (Fig. 6b) and osc_current_RUN.png.
#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "experiment_support.hpp"
#include "dmbd/control/osc_controller.hpp"
#include "dmbd/experiments/experiment.hpp"

namespace dmbd::experiments {

namespace {

using detail::signal;
using detail::stacked_axes;

struct Window {
  const std::vector<double>& t;
  double t0;
  bool in(std::size_t k) const { return t[k] >= t0; }
};

// RMS of a − b over the window (experiments.hpp's rms_error from t0 on).
double rms(const Window& w, const std::vector<double>& a, const std::vector<double>& b) {
  return rms_error(w.t, a, b, w.t0, std::numeric_limits<double>::infinity());
}

// The leg's joints: those with a sensed torque in the log whose names start with `leg`.
std::vector<std::string> leg_joints(const VariantResult& r, const std::string& leg) {
  std::vector<std::string> out;
  for (int c = 0; c < static_cast<int>(r.log.columns()); ++c)
    if (const std::string& name = r.log.name(c); name.rfind(leg, 0) == 0 && name.size() > 6 && name.compare(name.size() - 6, 6, ".tau_s") == 0)
      out.push_back(name.substr(0, name.size() - 6));
  return out;
}

double saturation_fraction(const VariantResult& r, const Window& w, const std::vector<std::string>& joints, const std::string& file) {
  std::size_t n = 0, saturated = 0;
  const std::size_t samples = w.t.size();
  for (std::size_t k = 0; k < samples; ++k) {
    if (!w.in(k)) continue;
    ++n;
    for (const auto& j : joints) {
      const auto lim = r.truth.find(j + ".current_limit_A");
      if (lim == r.truth.end()) continue;
      if (std::abs(signal(r, j + ".current_applied", file)[k]) >= lim->second * (1.0 - 1e-9)) {
        ++saturated;
        break;
      }
    }
  }
  return n ? static_cast<double>(saturated) / static_cast<double>(n) : std::nan("");
}

void point_metrics(const VariantResult& r, const Window& w, const std::string& prefix, const std::string& file, nlohmann::json& m) {
  double worst = 0;
  std::vector<double> err2(w.t.size(), 0.0);
  for (const char* axis : {"x", "y", "z"}) {
    const auto& d = signal(r, prefix + axis + "_d", file);
    const auto& y = signal(r, prefix + axis, file);
    m["ankle_rms_error_m"][axis] = rms(w, d, y);
    for (std::size_t k = 0; k < err2.size(); ++k) err2[k] += (d[k] - y[k]) * (d[k] - y[k]);
  }
  for (std::size_t k = 0; k < err2.size(); ++k)
    if (w.in(k)) worst = std::max(worst, std::sqrt(err2[k]));
  m["ankle_max_error_m"] = worst;
}

// The controller's point (its link's name) and the prefix of its signals.
struct Point {
  std::string link, prefix;
};

plot::Figure point_figure(const std::vector<VariantResult>& runs, const Point& pt, const ExperimentSetup& e) {
  plot::Figure fig(1200, 900);
  fig.title = labelled(e, "osc_ankle", "Position of " + pt.link + ": desired (dashed) and measured");
  for (const char* axis : {"x", "y", "z"}) {
    auto& a = stacked_axes(fig, std::string(axis) + " (m)", std::string(axis) == "z");
    for (std::size_t i = 0; i < runs.size(); ++i) {
      const auto& r = runs[i];
      a.series.push_back({r.name + " desired", r.log.time(), signal(r, pt.prefix + axis + "_d", e.file), plot::palette_color(i), 1.5, true});
      a.series.push_back({r.name, r.log.time(), signal(r, pt.prefix + axis, e.file), plot::palette_color(i)});
    }
  }
  return fig;
}

// The point's error per axis, target − measured, every variant (mm).
plot::Figure error_figure(const std::vector<VariantResult>& runs, double t0, const Point& pt, const ExperimentSetup& e) {
  const std::string& file = e.file;
  plot::Figure fig(1200, 900);
  fig.title = labelled(e, "osc_error", "Tracking error of " + pt.link + " (desired - measured)");
  for (const char* axis : {"x", "y", "z"}) {
    auto& a = stacked_axes(fig, std::string(axis) + " error (mm)", std::string(axis) == "z");
    if (t0 > 0) {
      a.v_lines = {t0};
      a.v_line_labels = {"metrics from here"};
    }
    for (std::size_t i = 0; i < runs.size(); ++i) {
      const auto& d = signal(runs[i], pt.prefix + axis + "_d", file);
      const auto& y = signal(runs[i], pt.prefix + axis, file);
      std::vector<double> e(d.size());
      for (std::size_t k = 0; k < e.size(); ++k) e[k] = 1e3 * (d[k] - y[k]);
      a.series.push_back({runs[i].name, runs[i].log.time(), e, plot::palette_color(i)});
    }
  }
  return fig;
}

plot::Figure torque_figure(const VariantResult& r, const std::vector<std::string>& joints, const ExperimentSetup& e) {
  const std::string& file = e.file;
  plot::Figure fig(1200, 200 * static_cast<int>(std::max<std::size_t>(joints.size(), 1)) + 100);
  fig.title = labelled(e, "osc_torque", r.name + ": joint torque, desired (dashed) and sensed");
  for (std::size_t i = 0; i < joints.size(); ++i) {
    auto& a = stacked_axes(fig, joints[i] + " (N m)", i + 1 == joints.size());
    a.series.push_back({"desired", r.log.time(), signal(r, joints[i] + ".tau_d", file), plot::palette_color(0), 1.5, true});
    a.series.push_back({"sensed", r.log.time(), signal(r, joints[i] + ".tau_s", file), plot::palette_color(1)});
  }
  return fig;
}

plot::Figure current_figure(const VariantResult& r, const std::vector<std::string>& joints, const ExperimentSetup& e) {
  const std::string& file = e.file;
  plot::Figure fig(1200, 200 * static_cast<int>(std::max<std::size_t>(joints.size(), 1)) + 100);
  fig.title = labelled(e, "osc_current", r.name + ": motor current and its limit");
  for (std::size_t i = 0; i < joints.size(); ++i) {
    auto& a = stacked_axes(fig, joints[i] + " (A)", i + 1 == joints.size());
    a.series.push_back({"applied", r.log.time(), signal(r, joints[i] + ".current_applied", file), plot::palette_color(2)});
    if (const auto lim = r.truth.find(joints[i] + ".current_limit_A"); lim != r.truth.end()) {
      a.h_lines = {lim->second, -lim->second};
      a.h_line_labels = {"limit", "limit"};
    }
  }
  return fig;
}

// The osc controller's point: from the first variant that has one.
Point osc_point(const std::vector<VariantFacts>& variants) {
  for (const auto& v : variants)
    if (const auto* o = v.bus_controller<control::OscSetup>()) return {o->link, o->name + "."};
  return {"the point", "osc."};
}

ExperimentResult osc_table(const ExperimentSetup& e, const std::vector<VariantResult>& runs, const std::vector<VariantFacts>& variants) {
  ExperimentResult res;
  const std::string leg = detail::text_or(e, "leg", "");
  const double t0 = detail::number_or(e, "window_start_s", 0.0);
  const Point pt = osc_point(variants);
  for (const auto& r : runs) {
    const Window w{r.log.time(), t0};
    if (w.t.empty() || w.t.back() < t0)
      res.warnings.push_back(fmt::format("variant '{}': the run ends before the experiment's window starts ({} s): no metrics", r.name, t0));
    nlohmann::json& m = res.metrics["osc"][r.name];
    point_metrics(r, w, pt.prefix, e.file, m);
    const auto joints = leg_joints(r, leg);
    for (const auto& j : joints) {
      const auto& d = signal(r, j + ".tau_d", e.file);
      m["torque_rms_error_Nm"][j] = rms(w, d, signal(r, j + ".tau_s", e.file));
      double peak = 0;
      for (std::size_t k = 0; k < d.size(); ++k)
        if (w.in(k)) peak = std::max(peak, std::abs(d[k]));
      m["torque_peak_Nm"][j] = peak;
    }
    m["current_saturation_fraction"] = saturation_fraction(r, w, joints, e.file);
    for (const char* stat : {"median", "max"})
      if (const auto it = r.timing_us.find(std::string("osc_tick_us_") + stat); it != r.timing_us.end()) m["osc_tick_us"][stat] = it->second;
    res.figures.emplace_back("osc_torque_" + detail::file_safe(r.name) + ".png", torque_figure(r, joints, e));
    res.figures.emplace_back("osc_current_" + detail::file_safe(r.name) + ".png", current_figure(r, joints, e));
  }
  res.figures.emplace_back("osc_ankle.png", point_figure(runs, pt, e));
  res.figures.emplace_back("osc_error.png", error_figure(runs, t0, pt, e));
  res.notes.push_back(fmt::format("Errors over t >= {} s (after the path's smooth start); torque: desired τ_d against the actuator's "
                                  "sensed force through its transmission, F / N_l(q).", t0));
  return res;
}

}  // namespace

std::shared_ptr<const Experiment> osc_table_experiment() {
  return std::make_shared<detail::FunctionExperiment>(
      std::map<std::string, KeyKind>{{"leg", KeyKind::Text}, {"window_start_s", KeyKind::Number}}, false,
      [](const ExperimentSetup& e, const std::vector<VariantResult>& runs, const std::vector<VariantFacts>& variants) { return osc_table(e, runs, variants); });
}

}  // namespace dmbd::experiments
