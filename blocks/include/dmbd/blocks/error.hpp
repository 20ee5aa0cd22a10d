#pragma once
// Errors shared by every module.
#include <stdexcept>
#include <string>

namespace dmbd {

// A mistake in what the user gave (a file, an expression, an option, a parameter).
// The message is one line that names where (file:line:column, option, column) and
// what was expected; the CLI prints it and exits with status 2.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace blocks {

// A malformed or unevaluable rational expression. `column()` is 1-based within the
// expression text; the message already mentions it.
class ExpressionError : public InputError {
 public:
  ExpressionError(const std::string& message, int column)
      : InputError("column " + std::to_string(column) + ": " + message), column_(column) {}
  int column() const { return column_; }

 private:
  int column_;
};

}  // namespace blocks
}  // namespace dmbd
