// The thermal experiment: a joint's winding temperature with the liquid cooling on and off.
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

// ---------------------------------------------------------------- thermal
ExperimentResult thermal(const ExperimentSetup& e, const std::vector<sim::VariantResult>& runs) {
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
    c.series.push_back({"applied current", t, signal(r, e.joint + ".current_applied", e.file)});
    // The RMS over the whole run from the exact integral of i^2 (the log's 50 Hz samples
    // of a 1 kHz current would alias its ripple).
    const auto& i2t = signal(r, e.joint + ".i2t", e.file);
    res.metrics["rms_current_A"] = t.back() > 0 ? std::sqrt(i2t.back() / t.back()) : 0.0;
  }
  if (!res.metrics.contains("peak_winding_C"))
    throw InputError(e.file + ": experiment thermal needs `thermal: {cooling: both}` (logs " + e.joint + ".T_winding_cooled and _uncooled)");
  res.figures.emplace_back("winding_temperature.png", fig);
  res.notes.push_back("Under current control the motor current does not depend on the winding temperature, so one run drives both "
                      "thermal models (cooling on and off) with the same current.");
  return res;
}

}  // namespace

std::shared_ptr<const Experiment> thermal_experiment() {
  return std::make_shared<detail::FunctionExperiment>(
      std::map<std::string, KeyKind>{}, true,
      [](const ExperimentSetup& e, const std::vector<VariantResult>& runs, const std::vector<VariantFacts>&) { return thermal(e, runs); });
}

}  // namespace dmbd::experiments
