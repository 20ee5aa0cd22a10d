#include "dmbd/sim/log.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "dmbd/base/file.hpp"

namespace dmbd::sim {

Log::Log() : names_{"t"}, units_{"s"}, columns_(1) {}

int Log::add_column(const std::string& name, const std::string& unit) {
  if (rows() > 0) throw std::logic_error("Log: column '" + name + "' declared after the first row");
  if (find(name) >= 0) throw std::logic_error("Log: column '" + name + "' declared twice");
  names_.push_back(name);
  units_.push_back(unit);
  columns_.emplace_back();
  return static_cast<int>(names_.size()) - 1;
}

void Log::reserve(std::size_t rows) {
  for (auto& c : columns_) c.reserve(rows);
}

void Log::begin_row(double t_s) {
  columns_.front().push_back(t_s);
  for (std::size_t k = 1; k < columns_.size(); ++k) columns_[k].push_back(std::numeric_limits<double>::quiet_NaN());
}

int Log::find(const std::string& name) const {
  for (std::size_t k = 0; k < names_.size(); ++k)
    if (names_[k] == name) return static_cast<int>(k);
  return -1;
}

const std::vector<double>& Log::column(const std::string& name) const {
  const int k = find(name);
  if (k < 0) throw std::out_of_range("log has no signal '" + name + "'");
  return columns_[static_cast<std::size_t>(k)];
}

std::string Log::to_csv() const {
  std::string out;
  for (std::size_t k = 0; k < names_.size(); ++k)
    out += fmt::format("{}{} [{}]", k ? "," : "", names_[k], units_[k]);
  out += '\n';
  for (std::size_t r = 0; r < rows(); ++r) {
    for (std::size_t k = 0; k < columns_.size(); ++k) {
      if (k) out += ',';
      out += fmt::format("{:.17g}", columns_[k][r]);
    }
    out += '\n';
  }
  return out;
}

void Log::write_csv(const std::string& path) const {
  const std::string s = to_csv();
  write_file_atomic(path, s);
}

}  // namespace dmbd::sim
