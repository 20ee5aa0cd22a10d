// run_scenario: runs the variants and writes log.csv, metrics.json, plots, frames,
// video and report.html.
#include "dmbd/sim/outputs.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "dmbd/blocks/error.hpp"
#include "dmbd/viz/plot.hpp"

namespace dmbd::sim {

namespace fs = std::filesystem;

namespace {

void write_text(const fs::path& p, const std::string& s) { viz::write_file_atomic(p.string(), std::vector<unsigned char>(s.begin(), s.end())); }

std::string num(double v) { return std::isfinite(v) ? fmt::format("{:.17g}", v) : (std::isnan(v) ? "NaN" : (v > 0 ? "inf" : "-inf")); }

// JSON cannot hold inf/NaN: they become strings.
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

}  // namespace

std::string combined_csv(const std::vector<VariantResult>& runs) {
  if (runs.size() == 1) return runs.front().log.to_csv();
  std::size_t longest = 0;
  for (std::size_t k = 0; k < runs.size(); ++k)
    if (runs[k].log.rows() > runs[longest].log.rows()) longest = k;
  std::string out = "t [s]";
  for (const auto& r : runs)
    for (std::size_t c = 1; c < r.log.columns(); ++c)
      out += fmt::format(",{}/{} [{}]", r.name, r.log.name(static_cast<int>(c)), r.log.unit(static_cast<int>(c)));
  out += '\n';
  const auto& t = runs[longest].log.time();
  for (std::size_t row = 0; row < t.size(); ++row) {
    out += fmt::format("{:.17g}", t[row]);
    for (const auto& r : runs)
      for (std::size_t c = 1; c < r.log.columns(); ++c) {
        out += ',';
        if (row < r.log.rows()) out += fmt::format("{:.17g}", r.log.column(static_cast<int>(c))[row]);
      }
    out += '\n';
  }
  return out;
}

ScenarioRunResult run_scenario(const Scenario& s, const std::string& out_dir, const ScenarioRunOptions& options) {
  ScenarioRunResult res;
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec || !fs::is_directory(out_dir)) throw InputError("--out '" + out_dir + "': cannot create the folder: " + ec.message());
  const fs::path dir(out_dir);

  double total = 0;
  for (const auto& v : s.variants) total += options.duration_s.value_or(v.duration_s);
  double done = 0;
  for (const auto& v : s.variants) {
    RunOptions ro;
    ro.duration_s = options.duration_s;
    const double d = options.duration_s.value_or(v.duration_s);
    if (options.on_progress) ro.on_progress = [&](double f) { options.on_progress((done + f * d) / total, v.name); };
    try {
      res.runs.push_back(run_variant(s, v, ro));
    } catch (const DivergenceError& e) {
      throw InputError(s.file + ": variant '" + v.name + "': " + e.what());
    }
    done += d;
  }
  res.experiment = evaluate_experiment(s, res.runs);

  write_text(dir / "log.csv", combined_csv(res.runs));
  res.files.push_back("log.csv");
  nlohmann::json metrics = res.experiment.metrics;
  metrics["scenario"] = s.name;
  for (const auto& r : res.runs) {
    nlohmann::json& j = metrics["runs"][r.name];
    j["duration_s"] = r.log.time().empty() ? 0.0 : r.log.time().back();
    j["wall_s"] = r.wall_s;
    j["real_time_factor"] = r.real_time_factor;
    j["integrator_steps"] = r.integrator_steps;
    j["controller_steps"] = r.controller_steps;
    j["controller_clamp_events"] = r.clamp_events;
  }
  write_text(dir / "metrics.json", finite_json(metrics).dump(2) + "\n");
  res.files.push_back("metrics.json");
  fs::create_directories(dir / "plots");
  for (const auto& [file, fig] : res.experiment.figures) {
    fig.save_png((dir / "plots" / file).string());
    res.files.push_back("plots/" + file);
  }
  return res;
}

}  // namespace dmbd::sim
