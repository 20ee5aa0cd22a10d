// The step_response experiment (paper Fig. 5b,c): step and sinusoid tracking of a joint's loop.
#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "experiment_support.hpp"

namespace dmbd::experiments {

namespace {

using detail::number_or;
using detail::signal;
using detail::text_or;

// ---------------------------------------------------------------- step response
ExperimentResult step_response(const ExperimentSetup& e, const std::vector<sim::VariantResult>& runs) {
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
    const auto& rv = signal(r, ref, e.file);
    const auto& y = signal(r, out, e.file);
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

}  // namespace

std::shared_ptr<const Experiment> step_response_experiment() {
  return std::make_shared<detail::FunctionExperiment>(
      std::map<std::string, KeyKind>{{"reference", KeyKind::Text}, {"output", KeyKind::Text}, {"step_start_s", KeyKind::Number}, {"step_end_s", KeyKind::Number}, {"sine_start_s", KeyKind::Number}, {"sine_end_s", KeyKind::Number}}, true,
      [](const ExperimentSetup& e, const std::vector<VariantResult>& runs, const std::vector<VariantFacts>&) { return step_response(e, runs); });
}

}  // namespace dmbd::experiments
