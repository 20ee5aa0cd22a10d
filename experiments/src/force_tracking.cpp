// The force_tracking experiment: RMS force error per variant, nested by the matrix axes.
#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "experiment_support.hpp"

namespace dmbd::experiments {

namespace {

using detail::nest;
using detail::number_or;
using detail::signal;
using detail::text_or;

// ---------------------------------------------------------------- force tracking
ExperimentResult force_tracking(const ExperimentSetup& e, const std::vector<sim::VariantResult>& runs) {
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
    const auto& rv = signal(r, ref, e.file);
    const auto& y = signal(r, out, e.file);
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
  const sim::VariantResult& first = runs.front();
  plot::Figure tf(1200, 500);
  tf.title = "Force tracking, " + first.name;
  auto& a = tf.add_axes();
  a.x_label = "Time (s)";
  a.y_label = "Actuator force (N)";
  a.x_limits = std::make_pair(t0, t0 + t_show);
  a.series.push_back({"F_d", first.log.time(), signal(first, ref, e.file), plot::Color{1, 1, 1}, 1.5, true});
  a.series.push_back({"F (true)", first.log.time(), signal(first, out, e.file)});
  a.series.push_back({"F (sensed)", first.log.time(), signal(first, e.joint + ".force", e.file), plot::Color{}, 1.0});
  res.figures.emplace_back("force_tracking.png", tf);
  res.notes.push_back(fmt::format("RMS of '{}' - '{}' from t = {} s to the end of each run.", out, ref, t0));
  return res;
}

}  // namespace

std::shared_ptr<const Experiment> force_tracking_experiment() {
  return std::make_shared<detail::FunctionExperiment>(
      std::map<std::string, KeyKind>{{"reference", KeyKind::Text}, {"output", KeyKind::Text}, {"start_s", KeyKind::Number}, {"plot_window_s", KeyKind::Number}}, true,
      [](const ExperimentSetup& e, const std::vector<VariantResult>& runs, const std::vector<VariantFacts>&) { return force_tracking(e, runs); });
}

}  // namespace dmbd::experiments
