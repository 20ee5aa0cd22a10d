#pragma once
// Expressions wherever a user's file has a number: the NumberParser (base) that
// evaluates a scalar as a constant Expression (`2*1000`, `pi/4`, `1/(2*pi*50)`, and the
// parameters given). Readers of YAML files get it from here, since base cannot know
// expressions (docs/architecture.md, "The located YAML reader").
#include <utility>

#include "dmbd/base/number_parser.hpp"
#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/expression.hpp"

namespace dmbd::blocks {

// An ExpressionError's message without its "column N: " (the reader's location has it).
inline std::string without_column(const std::string& message) {
  const auto colon = message.find(": ");
  return (message.rfind("column ", 0) == 0 && colon != std::string::npos) ? message.substr(colon + 2) : message;
}

// A name that is neither a constant nor one of `parameters` is "expected a number" (a
// word where a number belongs), not the expression parser's hint about --param.
inline NumberParser expression_numbers(ParameterMap parameters = {}) {
  return [parameters = std::move(parameters)](const std::string& text) {
    try {
      const Expression e = Expression::parse(text);
      for (const std::string& name : e.parameters())
        if (!parameters.count(name))
          throw NumberError(0, "expected a number, got '" + text + "'" +
                                   (name == text ? std::string() : " ('" + name + "' is not a number or a known constant)"));
      return e.evaluate(parameters);
    } catch (const ExpressionError& e) {
      throw NumberError(e.column(), without_column(e.what()));
    }
  };
}

}  // namespace dmbd::blocks
