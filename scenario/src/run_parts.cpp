// A sweep's parts: one variant's log and run facts, written and read back.
#include "engine_names.hpp"
#include "dmbd/scenario/run_parts.hpp"

#include "run_facts.hpp"
#include "variant_controllers.hpp"

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <optional>
#include <vector>

#include "dmbd/base/error.hpp"
#include "dmbd/base/file.hpp"
#include "dmbd/scenario/run_directory.hpp"

namespace dmbd::scenario {

namespace fs = std::filesystem;

namespace {

std::string byte_order() {
  const std::uint16_t one = 1;
  unsigned char first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1 ? "little" : "big";
}

// The log's values, column after column, as the machine's doubles; part.json's "log"
// names the columns and their units.
std::vector<unsigned char> log_bytes(const Log& log) {
  std::vector<unsigned char> bytes(log.columns() * log.rows() * sizeof(double));
  for (std::size_t c = 0; c < log.columns(); ++c)
    if (log.rows() > 0) std::memcpy(bytes.data() + c * log.rows() * sizeof(double), log.column(static_cast<int>(c)).data(), log.rows() * sizeof(double));
  return bytes;
}

nlohmann::json log_json(const Log& log) {
  nlohmann::json columns = nlohmann::json::array();
  for (std::size_t c = 0; c < log.columns(); ++c) columns.push_back({log.name(static_cast<int>(c)), log.unit(static_cast<int>(c))});
  return {{"file", "log.bin"}, {"format", "float64, column after column"}, {"byte_order", byte_order()}, {"rows", log.rows()}, {"columns", columns}};
}

// log.bin read back as part.json's "log" describes it.
Log read_log(const nlohmann::json& j, const std::string& pfile, const std::string& lfile) {
  const auto columns = j.at("columns");
  const std::size_t rows = j.at("rows").get<std::size_t>(), n = columns.size();
  if (j.value("byte_order", "") != byte_order())
    throw InputError(pfile + ": the log was written on a machine of " + j.value("byte_order", "?") + "-endian doubles, this one is " + byte_order());
  const std::string bytes = read_file(lfile);
  if (n == 0 || bytes.size() != n * rows * sizeof(double))
    throw InputError(lfile + ": " + std::to_string(bytes.size()) + " bytes, expected " + std::to_string(n * rows * sizeof(double)) +
                     " (" + std::to_string(n) + " columns of " + std::to_string(rows) + " doubles, as " + pfile + " says)");
  Log log;
  for (std::size_t c = 1; c < n; ++c) log.add_column(columns[c].at(0).get<std::string>(), columns[c].at(1).get<std::string>());
  log.reserve(rows);
  std::vector<double> v(n);
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < n; ++c) std::memcpy(&v[c], bytes.data() + (c * rows + r) * sizeof(double), sizeof(double));
    log.begin_row(v[0]);
    for (std::size_t c = 1; c < n; ++c) log.set(static_cast<int>(c), v[c]);
  }
  return log;
}

}  // namespace

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
  write_file_atomic((fs::path(dir) / "log.bin").string(), log_bytes(r.log));
  const nlohmann::json part = {{"scenario", s.name}, {"variant", r.name}, {"log", log_json(r.log)}, {"run", finite_json(run_json(r))}};
  write_file_atomic((fs::path(dir) / "part.json").string(), part.dump(2) + "\n");  // last: the part is complete
}

VariantResult read_part(const Scenario& s, const VariantSetup& v, const std::string& dir) {
  const std::string pfile = (fs::path(dir) / "part.json").string(), lfile = (fs::path(dir) / "log.bin").string();
  std::string text;
  if (const auto reason = try_read_file(pfile, text))
    throw InputError(pfile + ": missing (the run of variant '" + v.name + "' did not finish: " + *reason + ")");
  nlohmann::json part;
  try {
    part = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(pfile + ": not a part of a sweep: " + e.what());
  }
  if (!part.is_object() || !part.contains("run") || !part["run"].is_object() || !part.contains("variant") || !part.contains("log"))
    throw InputError(pfile + ": not a part of a sweep (expected 'scenario', 'variant', 'log' and 'run'; written by dmbd simulate --variant)");
  if (part.value("scenario", "") != s.name || part.value("variant", "") != v.name)
    throw InputError(pfile + ": holds variant '" + part.value("variant", "") + "' of scenario '" + part.value("scenario", "") +
                     "', expected variant '" + v.name + "' of '" + s.name + "'");
  VariantResult r;
  r.name = v.name;
  r.axes = v.axes;
  try {
    r.log = read_log(part["log"], pfile, lfile);
    read_run_json(part["run"], r);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(pfile + ": not a part of a sweep: " + e.what());
  }
  return r;
}

}  // namespace dmbd::scenario
