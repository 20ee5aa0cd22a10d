// log.csv written and read back (run_directory.hpp: combined_csv, split_csv). Read back,
// every field is checked before use (issue 28): the header's time column and its
// columns each once, every row's cell count, numbers, increasing times, each variant's
// cells all or none, and at least one row per variant.
#include "engine_names.hpp"
#include "dmbd/scenario/run_directory.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>

#include <fmt/format.h>

#include "dmbd/base/error.hpp"

namespace dmbd::scenario {

namespace {

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

// The text's lines one after the other, counted.
class Lines {
 public:
  explicit Lines(const std::string& text) : text_(text) {}
  bool done() const { return pos_ >= text_.size(); }
  std::size_t number() const { return line_; }
  std::string next() {
    const auto nl = text_.find('\n', pos_);
    std::string l = text_.substr(pos_, nl == std::string::npos ? std::string::npos : nl - pos_);
    pos_ = nl == std::string::npos ? text_.size() : nl + 1;
    ++line_;
    return l;
  }

 private:
  const std::string& text_;
  std::size_t pos_ = 0, line_ = 0;
};

// Where each CSV column goes: its variant and its column in that variant's log.
struct Columns {
  std::vector<std::pair<std::size_t, int>> where;  // per CSV column after time
  std::vector<std::size_t> count;                   // per variant: its columns
};

Columns read_header(const std::vector<std::string>& header, const std::vector<std::string>& variants, std::vector<Log>& logs,
                    const std::string& file) {
  if (header[0] != "t [s]") throw InputError(fmt::format("{}:1: the first column is '{}', expected 't [s]'", file, header[0]));
  Columns c;
  c.count.assign(variants.size(), 0);
  std::set<std::string> seen{"t"};
  for (std::size_t k = 1; k < header.size(); ++k) {
    const auto [full, unit] = header_cell(header[k]);
    const auto slash = full.rfind('/');
    const std::string v = variants.size() == 1 ? variants[0] : (slash == std::string::npos ? "" : full.substr(0, slash));
    const auto it = std::find(variants.begin(), variants.end(), v);
    if (it == variants.end()) throw InputError(fmt::format("{}:1: column '{}' belongs to no variant of the run", file, full));
    const std::string name = variants.size() == 1 ? full : full.substr(slash + 1);
    if (name.empty()) throw InputError(fmt::format("{}:1: column {} has no name (expected 'signal [unit]')", file, k + 1));
    if (!seen.insert(variants.size() == 1 ? name : full).second || name == "t")
      throw InputError(fmt::format("{}:1: column '{}' appears twice (expected each signal once, time first)", file, full));
    const auto n = static_cast<std::size_t>(it - variants.begin());
    c.where.emplace_back(n, logs[n].add_column(name, unit));
    c.count[n] += 1;
  }
  return c;
}

// One row's cells into the logs: each variant's cells all or none; a variant with no
// columns but time has a row at every line.
void read_row(const std::vector<std::string>& cells, const Columns& c, const std::vector<std::string>& variants,
              std::vector<Log>& logs, const std::string& file, std::size_t line) {
  const double t = parse_cell(cells[0], file, line);
  std::vector<std::size_t> present(logs.size(), 0);
  for (std::size_t k = 1; k < cells.size(); ++k) present[c.where[k - 1].first] += !cells[k].empty();
  for (std::size_t n = 0; n < logs.size(); ++n) {
    if (present[n] != 0 && present[n] != c.count[n])
      throw InputError(fmt::format("{}:{}: variant '{}' has {} of its {} values (expected all or none)", file, line, variants[n],
                                   present[n], c.count[n]));
    if (present[n] == 0 && (c.count[n] > 0 || variants.size() > 1)) continue;
    const auto& time = logs[n].time();
    if (!std::isfinite(t)) throw InputError(fmt::format("{}:{}: time '{}' is not a finite number", file, line, cells[0]));
    if (!time.empty() && !(t > time.back()))
      throw InputError(fmt::format("{}:{}: time {} is not after the previous row's {} (expected increasing times)", file, line,
                                   cells[0], time.back()));
    logs[n].begin_row(t);
  }
  for (std::size_t k = 1; k < cells.size(); ++k)
    if (!cells[k].empty()) logs[c.where[k - 1].first].set(c.where[k - 1].second, parse_cell(cells[k], file, line));
}

}  // namespace

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
  Lines lines(csv);
  const std::vector<std::string> header = cells_of(lines.next());
  const Columns columns = read_header(header, variants, logs, file);
  bool any_row = false;
  while (!lines.done()) {
    const std::vector<std::string> cells = cells_of(lines.next());
    if (cells.size() == 1 && cells[0].empty()) continue;
    if (cells.size() != header.size())
      throw InputError(fmt::format("{}:{}: {} cells, the header has {}", file, lines.number(), cells.size(), header.size()));
    read_row(cells, columns, variants, logs, file, lines.number());
    any_row = true;
  }
  if (!any_row) throw InputError(fmt::format("{}:{}: no rows after the header (expected at least one row of values)", file, lines.number()));
  for (std::size_t n = 0; n < logs.size(); ++n)
    if (logs[n].rows() == 0)
      throw InputError(fmt::format("{}: variant '{}' has no values in any row (expected at least one row of its columns)", file, variants[n]));
  return logs;
}

}  // namespace dmbd::scenario
