// A sweep's parts: one variant's log and run facts, written and read back.
#include "dmbd/sim/run_parts.hpp"

#include "run_facts.hpp"
#include "variant_controllers.hpp"

#include <filesystem>
#include <optional>

#include "dmbd/base/error.hpp"
#include "dmbd/base/file.hpp"
#include "dmbd/sim/run_directory.hpp"

namespace dmbd::sim {

namespace fs = std::filesystem;

const VariantSetup& find_variant(const Scenario& s, const std::string& name) {
  std::string names;
  for (const auto& v : s.variants) {
    if (v.name == name) return v;
    names += (names.empty() ? "" : ", ") + v.name;
  }
  throw InputError(s.file + ": no variant '" + name + "' (expected one of: " + names + ")");
}

void build_controllers(const Scenario& s) { build_generated_controllers(s); }

void write_part(const Scenario& s, const VariantResult& r, const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw OutputError("cannot create the folder '" + dir + "': " + (ec ? ec.message() : "a file is in the way"));
  write_file_atomic((fs::path(dir) / "log.csv").string(), r.log.to_csv());
  const nlohmann::json part = {{"scenario", s.name}, {"variant", r.name}, {"run", finite_json(run_json(r))}};
  write_file_atomic((fs::path(dir) / "part.json").string(), part.dump(2) + "\n");  // last: the part is complete
}

VariantResult read_part(const Scenario& s, const VariantSetup& v, const std::string& dir) {
  const std::string pfile = (fs::path(dir) / "part.json").string(), lfile = (fs::path(dir) / "log.csv").string();
  std::string text;
  if (const auto reason = try_read_file(pfile, text))
    throw InputError(pfile + ": missing (the run of variant '" + v.name + "' did not finish: " + *reason + ")");
  nlohmann::json part;
  try {
    part = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(pfile + ": not a part of a sweep: " + e.what());
  }
  if (!part.is_object() || !part.contains("run") || !part["run"].is_object() || !part.contains("variant"))
    throw InputError(pfile + ": not a part of a sweep (expected 'scenario', 'variant' and 'run'; written by dmbd simulate --variant)");
  if (part.value("scenario", "") != s.name || part.value("variant", "") != v.name)
    throw InputError(pfile + ": holds variant '" + part.value("variant", "") + "' of scenario '" + part.value("scenario", "") +
                     "', expected variant '" + v.name + "' of '" + s.name + "'");
  VariantResult r;
  r.name = v.name;
  r.axes = v.axes;
  r.log = std::move(split_csv(read_file(lfile), {v.name}, lfile).front());
  read_run_json(part["run"], r);
  return r;
}

}  // namespace dmbd::sim
