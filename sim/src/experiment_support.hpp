#pragma once
// Helpers shared by the experiment analyses (experiments.cpp, sysid_experiment.cpp,
// osc_experiment.cpp, balance_experiment.cpp).
#include <string>
#include <vector>

#include "dmbd/blocks/error.hpp"
#include "dmbd/sim/experiments.hpp"
#include "dmbd/sim/scenario.hpp"

namespace dmbd::sim::detail {

// A logged signal of a run; InputError naming the scenario file when it was not logged.
inline const std::vector<double>& signal(const VariantResult& r, const std::string& name, const std::string& file) {
  if (r.log.find(name) < 0) throw InputError(file + ": variant '" + r.name + "' logged no signal '" + name + "'");
  return r.log.column(name);
}

// An experiment's optional text / numeric field.
inline std::string text_or(const ExperimentSetup& e, const std::string& key, const std::string& fallback) {
  const auto it = e.text.find(key);
  return it == e.text.end() ? fallback : it->second;
}
inline double number_or(const ExperimentSetup& e, const std::string& key, double fallback) {
  const auto it = e.number.find(key);
  return it == e.number.end() ? fallback : it->second;
}

// The next of a figure's stacked axes sharing one x axis, labelled y_label; only the
// last one shows the x labels.
inline plot::Axes& stacked_axes(plot::Figure& fig, const std::string& y_label, bool last, const std::string& x_label = "Time (s)") {
  auto& a = fig.axes().emplace_back();
  a.y_label = y_label;
  a.x_tick_labels = last;
  if (last) a.x_label = x_label;
  return a;
}

}  // namespace dmbd::sim::detail
