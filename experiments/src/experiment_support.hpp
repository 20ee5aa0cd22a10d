#pragma once
// Internal to experiments/: helpers the experiments share.
#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dmbd/blocks/error.hpp"
#include "dmbd/experiments/experiment.hpp"

namespace dmbd::experiments {

using sim::Cooling;
using sim::ForceSpec;
using sim::Source;
using sim::VariantResult;

}  // namespace dmbd::experiments

namespace dmbd::experiments::detail {

// A logged signal of a run; InputError naming the scenario file when it was not logged.
inline const std::vector<double>& signal(const VariantResult& r, const std::string& name, const std::string& file) {
  if (r.log.find(name) < 0) throw InputError(file + ": variant '" + r.name + "' logged no signal '" + name + "'");
  return r.log.column(name);
}

// A run's name as part of a file name: anything but letters, digits, '_' and '-' becomes '_'.
inline std::string file_safe(std::string name) {
  std::replace_if(name.begin(), name.end(), [](char c) { return !std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-'; }, '_');
  return name;
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

// Nested JSON position for a run: metrics[a1][a2]... by its matrix axes (its name
// without axes).
inline nlohmann::json& nest(nlohmann::json& root, const VariantResult& r) {
  nlohmann::json* j = &root;
  if (r.axes.empty()) return (*j)[r.name];
  for (std::size_t k = 0; k + 1 < r.axes.size(); ++k) j = &(*j)[r.axes[k].second];
  return (*j)[r.axes.back().second];
}

// An experiment that is one evaluation function and the keys it reads (the built-in ones
// that need nothing else of the interface).
class FunctionExperiment : public Experiment {
 public:
  using Evaluate = ExperimentResult (*)(const ExperimentSetup&, const std::vector<VariantResult>&, const std::vector<VariantFacts>&);
  FunctionExperiment(std::map<std::string, KeyKind> keys, bool needs_joint, Evaluate evaluate)
      : keys_(std::move(keys)), needs_joint_(needs_joint), evaluate_(evaluate) {}
  std::map<std::string, KeyKind> keys() const override { return keys_; }
  bool needs_joint() const override { return needs_joint_; }
  ExperimentResult evaluate(const ExperimentSetup& e, const std::vector<VariantResult>& runs,
                            const std::vector<VariantFacts>& variants) const override {
    return evaluate_(e, runs, variants);
  }

 private:
  std::map<std::string, KeyKind> keys_;
  bool needs_joint_;
  Evaluate evaluate_;
};

// The next of a figure's stacked axes sharing one x axis, labelled y_label; only the
// last one shows the x labels.
inline plot::Axes& stacked_axes(plot::Figure& fig, const std::string& y_label, bool last, const std::string& x_label = "Time (s)") {
  auto& a = fig.axes().emplace_back();
  a.y_label = y_label;
  a.x_tick_labels = last;
  if (last) a.x_label = x_label;
  return a;
}

}  // namespace dmbd::experiments::detail
