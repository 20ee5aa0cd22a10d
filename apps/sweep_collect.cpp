#include "sweep_collect.hpp"

#include <filesystem>

#include <fmt/format.h>

#include "dmbd/base/error.hpp"
#include "dmbd/scenario/run_parts.hpp"
#include "sweep_plan.hpp"

namespace dmbd::apps {

namespace {

namespace fs = std::filesystem;

// The plan's jobs must be the scenario's variants, in order.
void check_jobs(const scenario::Scenario& s, const SweepPlan& p, const std::string& dir) {
  bool same = p.jobs.size() == s.variants.size();
  for (std::size_t k = 0; same && k < p.jobs.size(); ++k) same = p.jobs[k].variant == s.variants[k].name;
  if (!same)
    throw InputError(fmt::format("{}: its {} jobs are not the {} variants of {} (was the scenario changed after planning?)",
                                 (fs::path(dir) / "plan.json").string(), p.jobs.size(), s.variants.size(), s.file));
}

// Every job whose part.json is not there, named, in one line.
void check_finished(const SweepPlan& p, const std::string& dir) {
  std::string missing;
  std::size_t n = 0;
  for (std::size_t k = 0; k < p.jobs.size(); ++k) {
    std::error_code ec;
    if (fs::is_regular_file(fs::path(dir) / p.jobs[k].part / "part.json", ec)) continue;
    missing += fmt::format("{}job {} '{}' ({}/part.json)", n++ ? ", " : "", k + 1, p.jobs[k].variant, p.jobs[k].part);
  }
  if (n > 0)
    throw InputError(fmt::format("{}: {} of {} jobs did not finish: {}; run those lines of jobs.txt again", dir, n, p.jobs.size(), missing));
}

}  // namespace

scenario::ScenarioRun collect_sweep(const std::string& dir, const std::string& out) {
  const SweepPlan p = read_sweep_plan(dir);
  const scenario::Scenario s = scenario::load_scenario((fs::path(dir) / p.scenario).string());
  check_jobs(s, p, dir);
  check_finished(p, dir);
  std::vector<sim::VariantResult> runs;
  for (std::size_t k = 0; k < p.jobs.size(); ++k) runs.push_back(scenario::read_part(s, s.variants[k], (fs::path(dir) / p.jobs[k].part).string()));
  return scenario::write_run(s, std::move(runs), out);
}

}  // namespace dmbd::apps
