// Reading a scenario's experiment map (docs/scenario-format.md, "experiment"): its type
// found in the registry (experiments/registry.hpp) and the keys that type reads.
#include "dmbd/base/strings.hpp"
#include "engine_names.hpp"
#include "scenario_reader.hpp"

#include "dmbd/experiments/registry.hpp"

namespace dmbd::scenario::detail {

void Reader::experiment(const YAML::Node& e, experiments::ExperimentSetup& x) const {
  using experiments::KeyKind;
  if (!e.IsMap() || !e["type"]) fail(e, "experiment: expected a map with 'type'");
  x.type = text(e["type"], "experiment.type");
  x.where["type"] = at(e["type"]);
  const experiments::Experiment* exp = experiments::find_experiment(x.type);
  if (!exp) fail(e["type"], "experiment.type: expected one of " + join(experiments::experiment_types()) + ", got '" + x.type + "'");
  const auto allowed = exp->keys();
  for (const auto& kv : e) {
    rd.guard([&] {
      const std::string k = key(kv.first, "experiment");
      if (k == "type") return;
      x.where[k] = at(kv.second);
      if (k == "joint") return void(x.joint = text(kv.second, "experiment.joint"));
      if (k == "figure_labels") {
        if (!kv.second.IsMap()) fail(kv.second, "experiment.figure_labels: expected a map of figure: label");
        for (const auto& f : kv.second) x.figure_labels[key(f.first, "experiment.figure_labels")] = text(f.second, "experiment.figure_labels");
        return;
      }
      const auto it = allowed.find(k);
      if (it == allowed.end()) {
        std::string list = "type, joint, figure_labels";
        for (const auto& [name, kind] : allowed) list += ", " + name;
        fail(kv.first, "experiment " + x.type + ": unknown key '" + k + "' (expected one of: " + list + ")");
      }
      if (it->second == KeyKind::Number) x.number[k] = number(kv.second, "experiment." + k);
      else if (it->second == KeyKind::Joints) x.names[k] = names(kv.second, "experiment." + k);
      else if (it->second == KeyKind::Numbers) x.numbers[k] = number_list(kv.second, "experiment." + k);
      else x.text[k] = text(kv.second, "experiment." + k);
    });
  }
}

}  // namespace dmbd::scenario::detail
