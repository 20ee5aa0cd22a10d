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

double parse_cell(const std::string& cell, const std::string& file, std::size_t line) {
  char* end = nullptr;
  const double v = std::strtod(cell.c_str(), &end);
  if (cell.empty() || end != cell.c_str() + cell.size())
    throw InputError(fmt::format("{}:{}: expected a number, got '{}'", file, line, cell));
  return v;
}

// "name [unit]" -> name, unit.
std::pair<std::string, std::string> header_cell(const std::string& cell) {
  const auto open = cell.rfind(" [");
  if (open == std::string::npos || cell.back() != ']') return {cell, ""};
  return {cell.substr(0, open), cell.substr(open + 2, cell.size() - open - 3)};
}

std::vector<std::string> cells_of(const std::string& line) {
  std::vector<std::string> cells(1);
  for (char c : line) {
    if (c == ',') cells.emplace_back();
    else if (c != '\r') cells.back() += c;
  }
  return cells;
}

}  // namespace

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

std::string combined_csv(const std::vector<VariantResult>& runs) {
  if (runs.size() == 1) return runs.front().log.to_csv();
  // The time base: every instant any run logged, in order. Log times are whole
  // nanoseconds times 1e-9, so runs that logged the same instant hold the same double.
  std::vector<double> t;
  for (const auto& r : runs) t.insert(t.end(), r.log.time().begin(), r.log.time().end());
  std::sort(t.begin(), t.end());
  t.erase(std::unique(t.begin(), t.end()), t.end());
  std::string out = "t [s]";
  for (const auto& r : runs)
    for (std::size_t c = 1; c < r.log.columns(); ++c)
      out += fmt::format(",{}/{} [{}]", r.name, r.log.name(static_cast<int>(c)), r.log.unit(static_cast<int>(c)));
  out += '\n';
  std::vector<std::size_t> next(runs.size(), 0);  // each run's first row not yet written
  for (double ts : t) {
    out += fmt::format("{:.17g}", ts);
    for (std::size_t k = 0; k < runs.size(); ++k) {
      const Log& log = runs[k].log;
      const bool has = next[k] < log.rows() && log.time()[next[k]] == ts;
      for (std::size_t c = 1; c < log.columns(); ++c) {
        out += ',';
        if (has) out += fmt::format("{:.17g}", log.column(static_cast<int>(c))[next[k]]);  // empty: no sample at ts
      }
      if (has) ++next[k];
    }
    out += '\n';
  }
  return out;
}

std::vector<Log> split_csv(const std::string& csv, const std::vector<std::string>& variants, const std::string& file) {
  std::vector<Log> logs(variants.size());
  std::vector<std::pair<int, int>> where;  // per CSV column: its log and its column there
  std::size_t pos = 0, line = 0;
  auto next_line = [&]() {
    const auto nl = csv.find('\n', pos);
    std::string l = csv.substr(pos, nl == std::string::npos ? std::string::npos : nl - pos);
    pos = nl == std::string::npos ? csv.size() : nl + 1;
    ++line;
    return l;
  };
  const std::vector<std::string> header = cells_of(next_line());
  where.emplace_back(-1, 0);
  for (std::size_t c = 1; c < header.size(); ++c) {
    const auto [full, unit] = header_cell(header[c]);
    const auto slash = full.rfind('/');
    const std::string v = variants.size() == 1 ? variants[0] : (slash == std::string::npos ? "" : full.substr(0, slash));
    const auto it = std::find(variants.begin(), variants.end(), v);
    if (it == variants.end()) throw InputError(fmt::format("{}:1: column '{}' belongs to no variant of the run", file, full));
    const auto k = static_cast<std::size_t>(it - variants.begin());
    where.emplace_back(static_cast<int>(k), logs[k].add_column(variants.size() == 1 ? full : full.substr(slash + 1), unit));
  }
  while (pos < csv.size()) {
    const std::vector<std::string> cells = cells_of(next_line());
    if (cells.size() == 1 && cells[0].empty()) continue;
    if (cells.size() != header.size())
      throw InputError(fmt::format("{}:{}: {} cells, the header has {}", file, line, cells.size(), header.size()));
    const double t = parse_cell(cells[0], file, line);
    std::vector<bool> begun(logs.size(), false);
    for (std::size_t c = 1; c < cells.size(); ++c) {
      if (cells[c].empty()) continue;  // that variant logged nothing at t
      const auto [k, col] = where[c];
      if (!begun[static_cast<std::size_t>(k)]) logs[static_cast<std::size_t>(k)].begin_row(t);
      begun[static_cast<std::size_t>(k)] = true;
      logs[static_cast<std::size_t>(k)].set(col, parse_cell(cells[c], file, line));
    }
  }
  return logs;
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
    res.metrics = nlohmann::json::parse(read_file(mfile));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(mfile + ": not the metrics of a run: " + e.what());
  }
  if (!res.metrics.contains("scenario_file") || !res.metrics["scenario_file"].is_string() || !res.metrics.contains("runs"))
    throw InputError(mfile + ": not the metrics of a run (expected 'scenario_file' and 'runs'; written by dmbd simulate)");
  res.scenario = load_scenario(res.metrics["scenario_file"].get<std::string>());
  std::vector<std::string> names;
  for (const auto& v : res.scenario.variants)
    if (res.metrics["runs"].contains(v.name)) names.push_back(v.name);
  if (names.empty()) throw InputError(mfile + ": its runs are not variants of " + res.scenario.file);
  std::vector<Log> logs = split_csv(read_file(lfile), names, lfile);
  for (std::size_t k = 0; k < names.size(); ++k) {
    const nlohmann::json& j = res.metrics["runs"][names[k]];
    VariantResult r;
    r.name = names[k];
    for (const auto& v : res.scenario.variants)
      if (v.name == r.name) r.axes = v.axes;
    r.log = std::move(logs[k]);
    read_run_json(j, r);
    res.runs.push_back(std::move(r));
  }
  res.experiment = evaluate_experiment(res.scenario, res.runs);
  res.files = {"log.csv", "metrics.json"};
  return res;
}

}  // namespace dmbd::scenario
