// run_scenario and read_run: a scenario's run directory (log.csv, metrics.json).
#include "engine_names.hpp"
#include "dmbd/scenario/run_directory.hpp"

#include "run_facts.hpp"
#include "variant_controllers.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>

#include <fmt/format.h>

#include "dmbd/base/error.hpp"
#include "dmbd/base/file.hpp"
#include "dmbd/base/temporaries.hpp"
#include "dmbd/scenario/evaluate.hpp"

namespace dmbd::scenario {

namespace fs = std::filesystem;

namespace {

std::string num(double v) { return std::isfinite(v) ? fmt::format("{:.17g}", v) : (std::isnan(v) ? "NaN" : (v > 0 ? "inf" : "-inf")); }

void make_dir(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw OutputError("cannot create the folder '" + dir + "': " + (ec ? ec.message() : "a file is in the way"));
}

nlohmann::json metrics_json(const Scenario& s, const std::vector<VariantResult>& runs, const experiments::ExperimentResult& e) {
  nlohmann::json m = e.metrics;
  m["scenario"] = s.name;
  m["scenario_file"] = fs::absolute(s.file).lexically_normal().string();
  for (const auto& r : runs) m["runs"][r.name] = run_json(r);
  return finite_json(m);
}

}  // namespace

void forget_earlier_report(const std::string& dir) {
  const fs::path page = fs::path(dir) / "report.html";
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(page, ec))) fs::remove(page, ec);  // a folder in the way: its writer says so
  if (ec) throw OutputError("cannot remove the earlier report '" + page.string() + "': " + ec.message());
  remove_stale_temporaries(dir);
  remove_stale_temporaries((fs::path(dir) / "plots").string());
}

nlohmann::json finite_json(const nlohmann::json& j) {
  if (j.is_object()) {
    nlohmann::json o = nlohmann::json::object();
    for (auto it = j.begin(); it != j.end(); ++it) o[it.key()] = finite_json(it.value());
    return o;
  }
  if (j.is_array()) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& e : j) a.push_back(finite_json(e));
    return a;
  }
  if (j.is_number_float() && !std::isfinite(j.get<double>())) return num(j.get<double>());
  return j;
}

VariantResult run_scenario_variant(const Scenario& s, const VariantSetup& v, const ScenarioRunOptions& o, double done, double total) {
  RunOptions ro;
  ro.duration_s = o.duration_s;
  const double d = o.duration_s.value_or(v.duration_s);
  if (o.on_progress) ro.on_progress = [&o, &v, done, d, total](double f) { o.on_progress((done + f * d) / total, v.name); };
  try {
    return run_variant(s, v, ro);
  } catch (InputError& e) {  // a divergence or a mistake found while building: where, then the same error
    e.prepend(s.file + ": variant '" + v.name + "': ");
    throw;
  }
}

ScenarioRun write_run(const Scenario& s, std::vector<VariantResult> runs, const std::string& dir) {
  ScenarioRun res;
  res.scenario = s;
  res.runs = std::move(runs);
  // The log first: it is there to look at even when the experiment's analysis fails.
  make_dir(dir);
  forget_earlier_report(dir);
  write_file_atomic((fs::path(dir) / "log.csv").string(), combined_csv(res.runs));
  res.files.push_back("log.csv");
  res.experiment = evaluate_experiment(s, res.runs);
  res.metrics = metrics_json(s, res.runs, res.experiment);
  write_file_atomic((fs::path(dir) / "metrics.json").string(), res.metrics.dump(2) + "\n");
  res.files.push_back("metrics.json");
  return res;
}

ScenarioRun run_scenario(const Scenario& s, const std::string& dir, const ScenarioRunOptions& options) {
  double total = 0, done = 0;
  for (const auto& v : s.variants) total += options.duration_s.value_or(v.duration_s);
  build_generated_controllers(s);  // every generated controller compiled first, several at once
  std::vector<VariantResult> runs;
  for (const auto& v : s.variants) {
    runs.push_back(run_scenario_variant(s, v, options, done, total));
    done += options.duration_s.value_or(v.duration_s);
  }
  // Only now the folder: a scenario that fails to build or diverges leaves none behind.
  return write_run(s, std::move(runs), dir);
}

ScenarioRun read_run(const std::string& dir) {
  const std::string mfile = (fs::path(dir) / "metrics.json").string(), lfile = (fs::path(dir) / "log.csv").string();
  ScenarioRun res;
  try {
    res.metrics = nlohmann::json::parse(read_text_file(mfile));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(mfile + ": not the metrics of a run: " + e.what());
  }
  if (!res.metrics.is_object() || !res.metrics.contains("scenario_file") || !res.metrics["scenario_file"].is_string() ||
      !res.metrics.contains("runs") || !res.metrics["runs"].is_object())
    throw InputError(mfile + ": not the metrics of a run (expected 'scenario_file' and 'runs'; written by dmbd simulate)");
  res.scenario = load_scenario(res.metrics["scenario_file"].get<std::string>());
  std::vector<std::string> names;
  for (const auto& v : res.scenario.variants)
    if (res.metrics["runs"].contains(v.name)) names.push_back(v.name);
  if (names.empty()) throw InputError(mfile + ": its runs are not variants of " + res.scenario.file);
  std::vector<Log> logs = split_csv(read_text_file(lfile, kMaxDataFileBytes), names, lfile);
  for (std::size_t k = 0; k < names.size(); ++k) {
    const nlohmann::json& j = res.metrics["runs"][names[k]];
    VariantResult r;
    r.name = names[k];
    for (const auto& v : res.scenario.variants)
      if (v.name == r.name) r.axes = v.axes;
    r.log = std::move(logs[k]);
    try {
      read_run_json(j, r);
    } catch (const nlohmann::json::exception& e) {
      throw InputError(mfile + ": runs." + r.name + ": not the facts of a run: " + e.what());
    } catch (InputError& e) {
      e.prepend(mfile + ": runs." + r.name + ": ");
      throw;
    }
    res.runs.push_back(std::move(r));
  }
  res.experiment = evaluate_experiment(res.scenario, res.runs);
  res.files = {"log.csv", "metrics.json"};
  return res;
}

}  // namespace dmbd::scenario
