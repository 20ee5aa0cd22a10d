// A diagram or a transfer function lowered to a loop program (lowering.hpp).
#include "lowering.hpp"

#include "convert.hpp"
#include "systems.hpp"

#include <cmath>

#include "dmbd/base/error.hpp"
#include "dmbd/diagrams/diagram.hpp"

namespace dmbd::python {

namespace b = dmbd::blocks;
namespace cg = dmbd::codegen;

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

}  // namespace dmbd::python
