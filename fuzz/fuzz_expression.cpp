// Fuzz target: the expression parser and evaluator (blocks/src/expression.cpp).
// Any exception other than dmbd::InputError, a crash or a sanitizer report is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/expression.hpp"

namespace b = dmbd::blocks;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const b::Expression e = b::Expression::parse(text);
    b::ParameterMap params;
    double v = 0.5;
    for (const std::string& p : e.parameters()) params[p] = (v += 0.75);
    (void)e.uses('s');
    (void)e.uses('z');
    for (const char variable : {'s', 'z'}) {
      try {
        (void)e.evaluate_rational(params, variable);
      } catch (const dmbd::InputError&) {
      }
    }
    (void)e.evaluate(params);
  } catch (const dmbd::InputError&) {
  }
  return 0;
}
