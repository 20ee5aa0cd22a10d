#pragma once
// The record of a simulation: one row per logged sample, one named column per signal,
// each with its unit. Time is column 0 ("t", "s"). Columns are declared before the
// first row; rows are appended without allocation once reserve() has sized them.
#include <cstddef>
#include <string>
#include <vector>

namespace dmbd::sim {

// Columns of doubles by name, all the same length (one entry per row); column 0 is time.
// A Simulation fills one at its log rate, in its bus order (simulation.hpp).
class Log {
 public:
  Log();  // just the time column "t" [s], no rows
  // Declare a column; returns its index. Throws std::logic_error after the first row
  // or when the name is taken.
  int add_column(const std::string& name, const std::string& unit);
  // Room for this many rows in every column declared so far (append without allocating).
  void reserve(std::size_t rows);
  // Start a row at time t (s); every other column of the row is NaN until set.
  void begin_row(double t_s);
  // Writes the current (last) row's cell of a column (an index from add_column or find;
  // not checked: a row must have begun and the index be valid).
  void set(int column, double value) { columns_[static_cast<std::size_t>(column)].back() = value; }

  std::size_t rows() const { return columns_.front().size(); }  // rows begun so far
  std::size_t columns() const { return names_.size(); }         // including time (column 0)
  // Column k's name (0 <= k < columns(), not checked): "t" for k = 0, else a bus signal.
  const std::string& name(int column) const { return names_[static_cast<std::size_t>(column)]; }
  // Column k's unit as declared ("s", "rad", "N m", ...; "" for a reference).
  const std::string& unit(int column) const { return units_[static_cast<std::size_t>(column)]; }
  int find(const std::string& name) const;  // the index of the column of that name, or -1
  // The column of that name; throws std::out_of_range naming it when missing.
  const std::vector<double>& column(const std::string& name) const;
  // Column k by index (not checked), rows() values.
  const std::vector<double>& column(int index) const { return columns_[static_cast<std::size_t>(index)]; }
  const std::vector<double>& time() const { return columns_.front(); }  // column 0: each row's time, s

  // CSV with a header line "t [s],name [unit],..." and one line per row, every value
  // printed with 17 significant digits (round-trips exactly).
  std::string to_csv() const;
  // to_csv() into the file at path, written atomically (a temporary file renamed);
  // OutputError when it cannot be written.
  void write_csv(const std::string& path) const;

 private:
  std::vector<std::string> names_, units_;
  std::vector<std::vector<double>> columns_;
};

}  // namespace dmbd::sim
