// A scenario's runs turned into metrics and figures (evaluate.hpp).
#include "dmbd/scenario/evaluate.hpp"

#include "engine_names.hpp"
#include "sweep_plots.hpp"

#include "dmbd/base/error.hpp"
#include "dmbd/control/registry.hpp"
#include "dmbd/experiments/registry.hpp"

namespace dmbd::scenario {

namespace {

const VariantResult& find_run(const std::vector<VariantResult>& runs, const std::string& name, const std::string& file) {
  for (const auto& r : runs)
    if (r.name == name) return r;
  throw InputError(file + ": no variant is named '" + name + "'");
}

const std::vector<double>& signal(const VariantResult& r, const std::string& name, const std::string& file) {
  if (r.log.find(name) < 0) throw InputError(file + ": variant '" + r.name + "' logged no signal '" + name + "'");
  return r.log.column(name);
}

// The scenario's own plots: "signal" (every variant) or "variant:signal".
void add_plots(const Scenario& s, const std::vector<VariantResult>& runs, experiments::ExperimentResult& res) {
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
}

}  // namespace

experiments::VariantFacts variant_facts(const VariantSetup& v) {
  return {v.name, v.duration_s, v.forces, v.cooling, v.bus_controllers, v.robot.gravity_m_s2};
}

experiments::ExperimentResult evaluate_experiment(const Scenario& s, const std::vector<VariantResult>& runs) {
  experiments::ExperimentResult res;
  if (const experiments::Experiment* e = experiments::find_experiment(s.experiment.type)) {
    std::vector<experiments::VariantFacts> facts;
    for (const auto& r : runs) {
      const auto v = std::find_if(s.variants.begin(), s.variants.end(), [&](const VariantSetup& x) { return x.name == r.name; });
      facts.push_back(v == s.variants.end() ? experiments::VariantFacts{r.name, 0, {}, Cooling::On, {}} : variant_facts(*v));
    }
    res = e->evaluate(s.experiment, runs, facts);
  }
  add_plots(s, runs, res);
  detail::add_sweep_plots(s, res);
  return res;
}

std::vector<sim::Overlay> variant_overlays(const Scenario& s, const VariantSetup& v) {
  std::vector<sim::Overlay> out;
  for (const auto& o : v.bus_controllers)
    if (const control::BusControllerType* t = control::find_bus_controller(o->type)) {
      const auto more = t->overlays(*o);
      out.insert(out.end(), more.begin(), more.end());
    }
  if (const experiments::Experiment* e = experiments::find_experiment(s.experiment.type)) {
    const auto more = e->overlays(s.experiment);
    out.insert(out.end(), more.begin(), more.end());
  }
  return out;
}

}  // namespace dmbd::scenario
