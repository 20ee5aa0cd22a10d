// A variant's run facts as JSON (metrics.json runs.RUN, a sweep part's part.json) and back.
#include "engine_names.hpp"
#include "run_facts.hpp"

#include <climits>
#include <cmath>

#include "dmbd/base/error.hpp"

namespace dmbd::scenario {

namespace {

// A number written by finite_json ("inf", "NaN" as strings) read back.
double number_of(const nlohmann::json& j) {
  if (j.is_number()) return j.get<double>();
  const std::string t = j.is_string() ? j.get<std::string>() : "NaN";
  return t == "inf" ? HUGE_VAL : (t == "-inf" ? -HUGE_VAL : std::nan(""));
}

// A count read back: a whole number that fits (a float such as 1e300 would not convert).
long long whole(const nlohmann::json& v, const std::string& field) {
  const bool fits = v.is_number_integer() && !(v.is_number_unsigned() && v.get<unsigned long long>() > LLONG_MAX);
  if (!fits) throw InputError("run." + field + ": " + v.dump() + " (expected a whole number)");
  return v.get<long long>();
}

int small_whole(const nlohmann::json& v, const std::string& field) {
  const long long n = whole(v, field);
  if (n < INT_MIN || n > INT_MAX) throw InputError("run." + field + ": " + v.dump() + " (expected a whole number of int's range)");
  return static_cast<int>(n);
}

// run_json's "sil" read back.
SilFacts sil_facts(const nlohmann::json& j) {
  SilFacts f{j.value("compiler", ""), j.value("version", ""), j.value("flags", ""), {}};
  for (const auto& c : j.value("controllers", nlohmann::json::array())) {
    SilController e{c.value("controller", ""), c.value("scalar", ""), c.value("object", ""), number_of(c.value("compile_s", nlohmann::json())), {}};
    if (c.contains("saturations") && c["saturations"].is_number_unsigned()) e.saturations = c["saturations"].get<unsigned long long>();
    f.controllers.push_back(e);
  }
  return f;
}

}  // namespace

nlohmann::json run_json(const VariantResult& r) {
  nlohmann::json j;
  j["duration_s"] = r.log.time().empty() ? 0.0 : r.log.time().back();
  j["wall_s"] = r.wall_s;
  j["real_time_factor"] = r.real_time_factor;
  j["integrator_steps"] = r.integrator_steps;
  j["controller_steps"] = r.controller_steps;
  j["controller_clamp_events"] = nlohmann::json::array();
  for (const auto& c : r.clamp_events) j["controller_clamp_events"].push_back(c ? nlohmann::json(*c) : nlohmann::json());
  j["truth"] = nlohmann::json::object();
  for (const auto& [k, v] : r.truth) j["truth"][k] = v;
  if (!r.timing_us.empty())
    for (const auto& [k, v] : r.timing_us) j["timing_us"][k] = v;
  for (const auto& f : r.fixed_point)
    j["fixed_point"].push_back({{"controller", f.controller}, {"output", f.output}, {"unit", f.unit}, {"word_bits", f.word_bits},
                                {"error_bound", f.bound}, {"range", f.range}});
  if (!r.warnings.empty()) j["warnings"] = r.warnings;
  for (const auto& [joint, n] : r.effort_clamp_events) j["effort_clamp_events"][joint] = n;
  for (const auto& [joint, e] : r.velocity_limit_exceeded)
    j["velocity_limit_exceeded"][joint] = {{"limit", e.limit}, {"peak", e.peak}, {"samples", e.samples}};
  if (r.sil) {
    nlohmann::json& sil = j["sil"];
    sil = {{"compiler", r.sil->compiler}, {"version", r.sil->version}, {"flags", r.sil->flags}, {"controllers", nlohmann::json::array()}};
    for (const auto& c : r.sil->controllers) {
      nlohmann::json e = {{"controller", c.controller}, {"scalar", c.scalar}, {"object", c.object}, {"compile_s", c.compile_s}};
      if (c.saturations) e["saturations"] = *c.saturations;
      sil["controllers"].push_back(e);
    }
  }
  return j;
}

void read_run_json(const nlohmann::json& j, VariantResult& r) {
  if (!j.is_object()) throw InputError("run: " + j.dump().substr(0, 40) + " (expected an object)");
  r.wall_s = number_of(j.value("wall_s", nlohmann::json(0.0)));
  r.real_time_factor = number_of(j.value("real_time_factor", nlohmann::json(0.0)));
  r.integrator_steps = j.contains("integrator_steps") ? whole(j["integrator_steps"], "integrator_steps") : 0;
  for (const auto& c : j.value("controller_steps", nlohmann::json::array())) r.controller_steps.push_back(whole(c, "controller_steps"));
  for (const auto& c : j.value("controller_clamp_events", nlohmann::json::array()))
    r.clamp_events.push_back(c.is_number_unsigned() ? std::optional<unsigned long long>(c.get<unsigned long long>()) : std::nullopt);
  if (j.contains("sil") && j["sil"].is_object()) r.sil = sil_facts(j["sil"]);
  for (const char* key : {"truth", "timing_us", "effort_clamp_events", "velocity_limit_exceeded"})
    if (j.contains(key) && !j[key].is_object()) throw InputError(std::string("run.") + key + ": expected an object");
  if (j.contains("truth"))
    for (auto it = j["truth"].begin(); it != j["truth"].end(); ++it) r.truth[it.key()] = number_of(it.value());
  if (j.contains("timing_us"))
    for (auto it = j["timing_us"].begin(); it != j["timing_us"].end(); ++it) r.timing_us[it.key()] = number_of(it.value());
  if (j.contains("fixed_point"))
    for (const auto& f : j["fixed_point"])
      r.fixed_point.push_back({f.value("controller", ""), f.value("output", ""), f.value("unit", ""),
                               f.contains("word_bits") ? small_whole(f["word_bits"], "fixed_point.word_bits") : 0,
                               number_of(f.value("error_bound", nlohmann::json())), number_of(f.value("range", nlohmann::json()))});
  r.warnings = j.value("warnings", std::vector<std::string>{});
  if (j.contains("effort_clamp_events"))
    for (auto it = j["effort_clamp_events"].begin(); it != j["effort_clamp_events"].end(); ++it)
      r.effort_clamp_events[it.key()] = it.value().is_number_integer() ? it.value().get<long long>() : 0;
  if (j.contains("velocity_limit_exceeded"))
    for (auto it = j["velocity_limit_exceeded"].begin(); it != j["velocity_limit_exceeded"].end(); ++it) {
      const nlohmann::json& e = it.value();
      if (!e.is_object()) throw InputError("run.velocity_limit_exceeded." + it.key() + ": expected an object");
      r.velocity_limit_exceeded[it.key()] = {number_of(e.value("limit", nlohmann::json())), number_of(e.value("peak", nlohmann::json())),
                                             e.contains("samples") ? whole(e["samples"], "velocity_limit_exceeded.samples") : 0};
    }
}

}  // namespace dmbd::scenario
