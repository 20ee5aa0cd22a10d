// The standing experiment: a floating robot standing (and pushed).
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

// ---------------------------------------------------------------- standing
// A floating robot standing (and pushed): from the logged torso pose, per variant,
// fell (the torso dropped more than 0.2 m below its start or tilted beyond 0.5 rad),
// the largest tilt, the largest drop, and the tilt at the end (the push recovered).
ExperimentResult standing(const ExperimentSetup& e, const std::vector<sim::VariantResult>& runs) {
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
    const auto& tl = signal(r, "base.tilt", e.file);
    const auto& z = signal(r, "base.z", e.file);
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
    lateral.series.push_back({label, t, signal(r, "base.y", e.file)});
  }
  res.figures.emplace_back("standing.png", fig);
  res.notes.push_back(fmt::format("fell: the torso dropped more than {} m below its start or tilted beyond {} rad.", kFallDrop, kFallTilt));
  return res;
}

}  // namespace

std::shared_ptr<const Experiment> standing_experiment() {
  return std::make_shared<detail::FunctionExperiment>(
      std::map<std::string, KeyKind>{}, false,
      [](const ExperimentSetup& e, const std::vector<VariantResult>& runs, const std::vector<VariantFacts>&) { return standing(e, runs); });
}

}  // namespace dmbd::experiments
