#pragma once
// How a reader of user files turns a scalar's text into a number. base reads plain
// numbers (plain_number); a module that knows expressions supplies its own parser
// (blocks/expression_numbers.hpp: `2*1000`, `pi/4`, parameters), so that base depends on
// nothing (docs/architecture.md, "The located YAML reader").
#include <functional>
#include <stdexcept>
#include <string>

namespace dmbd {

// The text is not a number: `column` (1-based within the text, 0 for the whole text)
// and what is wrong. A reader reports it at the scalar's place plus the column.
class NumberError : public std::runtime_error {
 public:
  NumberError(int column, const std::string& message) : std::runtime_error(message), column_(column) {}
  int column() const { return column_; }

 private:
  int column_;
};

// Returns the number, or throws NumberError.
using NumberParser = std::function<double(const std::string& text)>;

// One number in C notation (strtod: 12, -1.5, 1e-3, inf) and nothing else around it.
double plain_number(const std::string& text);

}  // namespace dmbd
