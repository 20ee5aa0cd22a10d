#pragma once
// A diagram file or a TransferFunction lowered to a loop program, as `dmbd codegen`
// lowers it (docs/codegen.md): shared by generate_code and loop_program.
#include "pybind.hpp"

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dmbd/codegen/loop_program.hpp"

namespace dmbd::python {

using Range = std::pair<double, double>;

// The lowered program, what it came from (for a header's comment) and the ranges of
// its inputs (for a fixed-point program's formats).
struct Lowered {
  codegen::LoopProgram program;
  std::string source;
  std::vector<Range> input_ranges;
};

// The lowering options from Python's arguments: rate_hz > 0, method (a C2dMethod name
// or None), block_methods ({block path: method} or None).
codegen::LowerOptions lower_options(double rate_hz, const py::object& method, const py::object& block_methods);

// `source` (a TransferFunction, or a diagram file's path with params) lowered with lo;
// a diagram's own discretisation is used unless method_given. `range` is the input
// range of a TransferFunction, and of a diagram input without one (default [-1, 1]).
Lowered lower(const py::object& source, const codegen::LowerOptions& lo, bool method_given, const std::optional<Range>& range,
              const py::object& params);

}  // namespace dmbd::python
