// A sweep's parts: one variant's log and run facts, written and read back.
#include "engine_names.hpp"
#include "dmbd/scenario/run_parts.hpp"

#include "run_facts.hpp"
#include "variant_controllers.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <optional>
#include <set>
#include <vector>

#include <fmt/format.h>

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

// part.json's "log.columns": [name, unit] pairs of strings, time first, each name once.
std::vector<std::pair<std::string, std::string>> log_columns(const nlohmann::json& j, const std::string& pfile) {
  const nlohmann::json& columns = j.contains("columns") ? j["columns"] : nlohmann::json();
  if (!columns.is_array() || columns.empty())
    throw InputError(pfile + ": log.columns: expected a list of [name, unit] pairs, time first");
  std::vector<std::pair<std::string, std::string>> out;
  std::set<std::string> seen;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const nlohmann::json& e = columns[c];
    if (!e.is_array() || e.size() != 2 || !e[0].is_string() || !e[1].is_string() || e[0].get<std::string>().empty())
      throw InputError(fmt::format("{}: log.columns[{}]: expected a [name, unit] pair of strings", pfile, c));
    out.emplace_back(e[0].get<std::string>(), e[1].get<std::string>());
    if ((c == 0) != (out.back().first == "t"))
      throw InputError(fmt::format("{}: log.columns[{}]: '{}' (expected time 't' first and only first)", pfile, c, out.back().first));
    if (!seen.insert(out.back().first).second)
      throw InputError(fmt::format("{}: log.columns[{}]: '{}' appears twice (expected each signal once)", pfile, c, out.back().first));
  }
  return out;
}

// part.json's "log.rows": at least one, and no more than a part's log may hold with
// `n` columns (checked without overflow).
std::size_t log_rows(const nlohmann::json& j, std::size_t n, const std::string& pfile) {
  const nlohmann::json& rows = j.contains("rows") ? j["rows"] : nlohmann::json();
  if (!rows.is_number_unsigned() || rows.get<std::uint64_t>() == 0)
    throw InputError(pfile + ": log.rows: " + rows.dump() + " (expected a whole number of rows, at least 1)");
  const std::uint64_t r = rows.get<std::uint64_t>(), most = kMaxDataFileBytes / (n * sizeof(double));
  if (r > most)
    throw InputError(fmt::format("{}: log.rows: {} rows of {} columns exceed the limit of a part's log ({} bytes: at most {} rows)",
                                 pfile, r, n, kMaxDataFileBytes, most));
  return static_cast<std::size_t>(r);
}

// log.bin's bytes: exactly `expected` of them.
std::string log_file_bytes(const std::string& lfile, std::size_t expected, const std::string& what) {
  std::string bytes;
  const auto reason = try_read_file(lfile, bytes, expected);
  if (reason && bytes.size() <= expected) throw InputError(lfile + ": cannot read: " + *reason);
  if (bytes.size() != expected)
    throw InputError(fmt::format("{}: {} bytes{}, expected {} ({})", lfile, bytes.size(), reason ? " or more" : "", expected, what));
  return bytes;
}

// log.bin read back as part.json's "log" describes it, every field checked first.
Log read_log(const nlohmann::json& j, const std::string& pfile, const std::string& lfile) {
  if (!j.is_object()) throw InputError(pfile + ": log: expected an object with 'columns' and 'rows'");
  if (j.value("byte_order", "") != byte_order())
    throw InputError(pfile + ": the log was written on a machine of " + j.value("byte_order", "?") + "-endian doubles, this one is " + byte_order());
  const auto columns = log_columns(j, pfile);
  const std::size_t n = columns.size(), rows = log_rows(j, n, pfile);
  const std::string bytes = log_file_bytes(lfile, n * rows * sizeof(double),
                                           fmt::format("{} columns of {} doubles, as {} says", n, rows, pfile));
  Log log;
  for (std::size_t c = 1; c < n; ++c) log.add_column(columns[c].first, columns[c].second);
  log.reserve(rows);
  std::vector<double> v(n);
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < n; ++c) std::memcpy(&v[c], bytes.data() + (c * rows + r) * sizeof(double), sizeof(double));
    if (!std::isfinite(v[0]) || (r > 0 && !(v[0] > log.time().back())))
      throw InputError(fmt::format("{}: row {}'s time {} is not after the previous row's (expected finite, increasing times)", lfile,
                                   r + 1, v[0]));
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
  if (const auto reason = try_read_text_file(pfile, text))
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
  } catch (const nlohmann::json::exception& e) {
    throw InputError(pfile + ": not a part of a sweep: " + e.what());
  }
  try {
    read_run_json(part["run"], r);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(pfile + ": run: not the facts of a run: " + e.what());
  } catch (InputError& e) {  // "run.FIELD: ..."
    e.prepend(pfile + ": ");
    throw;
  }
  return r;
}

}  // namespace dmbd::scenario
