#pragma once
// The record of a simulation: one row per logged sample, one named column per signal,
// each with its unit. Time is column 0 ("t", "s"). Columns are declared before the
// first row; rows are appended without allocation once reserve() has sized them.
#include <cstddef>
#include <string>
#include <vector>

namespace dmbd::sim {

class Log {
 public:
  Log();
  // Declare a column; returns its index. Throws std::logic_error after the first row
  // or when the name is taken.
  int add_column(const std::string& name, const std::string& unit);
  void reserve(std::size_t rows);
  // Start a row at time t (s); every other column of the row is NaN until set.
  void begin_row(double t_s);
  void set(int column, double value) { columns_[static_cast<std::size_t>(column)].back() = value; }

  std::size_t rows() const { return columns_.front().size(); }
  std::size_t columns() const { return names_.size(); }
  const std::string& name(int column) const { return names_[static_cast<std::size_t>(column)]; }
  const std::string& unit(int column) const { return units_[static_cast<std::size_t>(column)]; }
  int find(const std::string& name) const;  // or -1
  // The column of that name; throws std::out_of_range naming it when missing.
  const std::vector<double>& column(const std::string& name) const;
  const std::vector<double>& column(int index) const { return columns_[static_cast<std::size_t>(index)]; }
  const std::vector<double>& time() const { return columns_.front(); }

  // CSV with a header line "t [s],name [unit],..." and one line per row, every value
  // printed with 17 significant digits (round-trips exactly). Written atomically.
  std::string to_csv() const;
  void write_csv(const std::string& path) const;

 private:
  std::vector<std::string> names_, units_;
  std::vector<std::vector<double>> columns_;
};

}  // namespace dmbd::sim
