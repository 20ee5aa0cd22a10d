#pragma once
// The project's InputError (dmbd/base/error.hpp) and the expression parser's own kind.
#include <string>

#include "dmbd/base/error.hpp"

namespace dmbd {

namespace blocks {

// A malformed or unevaluable rational expression. `column()` is 1-based within the
// expression text; the message already mentions it.
class ExpressionError : public InputError {
 public:
  // what() is "column N: message".
  ExpressionError(const std::string& message, int column)
      : InputError("column " + std::to_string(column) + ": " + message), column_(column) {}
  int column() const { return column_; }  // 1-based column of the problem in the expression

 private:
  int column_;
};

}  // namespace blocks
}  // namespace dmbd
