// Code generation (docs/python.md, "Code generation"): the header `dmbd codegen` writes,
// as text, from a diagram file or a transfer function. The program's warnings (a delay
// rounded to whole samples, a pole above the loop's Nyquist frequency) become Python
// UserWarnings.
#include "bindings.hpp"
#include "convert.hpp"
#include "systems.hpp"

#include <cctype>
#include <cmath>
#include <optional>

#include "dmbd/base/error.hpp"
#include "dmbd/codegen/emit.hpp"
#include "dmbd/codegen/fixed.hpp"
#include "dmbd/codegen/loop_program.hpp"
#include "dmbd/diagrams/diagram.hpp"

namespace dmbd::python {

namespace b = dmbd::blocks;
namespace cg = dmbd::codegen;
using namespace pybind11::literals;

namespace {

using Range = std::pair<double, double>;

// The lowered program, what it came from (for the header's comment) and the ranges of
// its inputs (for a fixed-point program's formats).
struct Lowered {
  cg::LoopProgram program;
  std::string source;
  std::vector<Range> input_ranges;
};

cg::LowerOptions lower_options(double rate_hz, const py::object& method, const py::object& block_methods) {
  cg::LowerOptions lo;
  lo.rate_hz = rate_hz;
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz)) throw InputError("rate_hz " + std::to_string(rate_hz) + ": expected a rate > 0 Hz");
  if (!method.is_none()) lo.method = b::parse_c2d_method(method.cast<std::string>());
  if (!block_methods.is_none()) {
    if (!py::isinstance<py::dict>(block_methods)) throw py::type_error("block_methods: expected a dict {block path: method}");
    for (const auto& [k, v] : block_methods.cast<py::dict>())
      lo.block_methods.push_back({k.cast<std::string>(), b::parse_c2d_method(v.cast<std::string>())});
  }
  return lo;
}

Lowered lower(const py::object& source, const cg::LowerOptions& lo, bool method_given, const std::optional<Range>& range,
              const py::object& params) {
  if (py::isinstance<b::TransferFunction>(source)) {
    if (!params.is_none()) throw InputError("params apply to a diagram, not to a TransferFunction");
    Lowered out{cg::lower(source.cast<const b::TransferFunction&>(), "tf", lo), {}, {}};
    out.source = "the transfer function " + py::repr(source).cast<std::string>();
    out.input_ranges.push_back(range.value_or(Range{-1.0, 1.0}));
    return out;
  }
  const std::string file = to_path(source);
  const auto d = diagrams::Diagram::load(file, to_parameters(params));
  cg::LowerOptions o = lo;
  if (!method_given && d->discretization()) o.method = *d->discretization();  // the diagram's own, unless given
  Lowered out{cg::lower(*d, o), "the diagram " + file, {}};
  for (const auto& in : d->inputs())
    for (int k = 0; k < in.size; ++k) out.input_ranges.push_back(in.range.value_or(range.value_or(Range{-1.0, 1.0})));
  return out;
}

std::string generate_code(const py::object& source, double rate_hz, const py::object& method, const py::object& block_methods,
                          const std::string& scalar, int word_bits, const py::object& input_range, const py::object& name,
                          const py::object& params) {
  if (scalar != "double" && scalar != "float" && scalar != "fixed")
    throw InputError("scalar '" + scalar + "': expected double, float or fixed");
  if (word_bits != 32 && word_bits != 16) throw InputError("word_bits " + std::to_string(word_bits) + ": expected 16 or 32");
  std::optional<Range> range;
  if (!input_range.is_none()) {
    const std::vector<double> r = to_vector(input_range, "input_range");
    if (r.size() != 2 || !(r[0] < r[1])) throw InputError("input_range: expected (lo, hi) with lo < hi");
    range = Range{r[0], r[1]};
  }
  Lowered l = lower(source, lower_options(rate_hz, method, block_methods), !method.is_none(), range, params);
  cg::LoopProgram& p = l.program;
  if (!name.is_none()) p.name = name.cast<std::string>();
  if (p.name.empty()) throw InputError("name: expected a C++ identifier, got an empty name");
  for (char c : p.name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_'))
      throw InputError("name '" + p.name + "': expected a C++ identifier");
  for (const std::string& w : p.warnings)
    if (PyErr_WarnEx(PyExc_UserWarning, (p.name + ": " + w).c_str(), 1) != 0) throw py::error_already_set();
  const cg::EmitOptions eo{scalar == "float" ? cg::Scalar::Float : cg::Scalar::Double, l.source};
  if (scalar != "fixed") return cg::emit_header(p, eo);
  const cg::FixedProgram fx = cg::make_fixed(p, l.input_ranges, word_bits);
  return cg::emit_fixed_header(p, fx, eo);
}

}  // namespace

void bind_codegen(py::module_& m) {
  m.def("generate_code", &generate_code, "source"_a, "rate_hz"_a, "method"_a = py::none(), "block_methods"_a = py::none(),
        "scalar"_a = "double", "word_bits"_a = 32, "input_range"_a = py::none(), "name"_a = py::none(),
        "params"_a = py::none(), R"doc(
The C++ header `dmbd codegen` generates (docs/codegen.md), as text: `source` is a diagram
file (str or path) or a TransferFunction, run at rate_hz. method: "tustin", "zoh" or
"backward-euler" for continuous blocks (default: the diagram's `discretization`, else
tustin); block_methods {block path: method}; scalar "double", "float" or "fixed" (with
word_bits 16 or 32 and input_range (lo, hi) for inputs the diagram gives no range);
name: the namespace (default: the diagram's name, "tf" for a TransferFunction); params:
the diagram's parameter overrides. The program's warnings are issued as UserWarnings.)doc");
}

}  // namespace dmbd::python
