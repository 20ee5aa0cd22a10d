// Block diagrams (docs/python.md, "Diagrams"): a diagram file loaded and evaluated
// (docs/diagram-format.md), its linear model between two signals, its loop transfer at
// a break point, and the transfer between two signals as `dmbd analyze` reports it.
#include "bindings.hpp"
#include "convert.hpp"

#include <memory>

#include "dmbd/base/error.hpp"
#include "dmbd/blocks/siso.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "dmbd/diagrams/diagram_source.hpp"
#include "dmbd/diagrams/linearize.hpp"

namespace dmbd::python {

namespace b = dmbd::blocks;
namespace d = dmbd::diagrams;
using namespace pybind11::literals;

namespace {

// A loaded diagram: its file parsed once (the source) and evaluated at parameter values.
struct LoadedDiagram {
  std::shared_ptr<const d::DiagramSource> source;
  std::shared_ptr<const d::Diagram> diagram;
};

LoadedDiagram load(const py::object& path, const py::object& params) {
  LoadedDiagram l;
  l.source = d::DiagramSource::load(to_path(path));
  l.diagram = l.source->evaluate(to_parameters(params));
  return l;
}

py::list names(const std::vector<d::SignalSpec>& signals) {
  py::list l;
  for (const auto& s : signals) l.append(s.name);
  return l;
}

// The transfer between two signals as a rational function: the diagram's sparse model
// taken apart by blocks::Siso (modes the two signals do not see left out), as the
// numerator and denominator of `dmbd analyze DIAGRAM --from --to`.
b::TransferFunction transfer(const LoadedDiagram& l, const std::string& from, const std::string& to) {
  const b::SparseStateSpace ss = d::linearize_sparse(*l.diagram, from, to);
  if (ss.num_inputs() != 1 || ss.num_outputs() != 1)
    throw InputError("transfer needs scalar signals: the model from '" + from + "' to '" + to + "' has " +
                     std::to_string(ss.num_inputs()) + " inputs and " + std::to_string(ss.num_outputs()) +
                     " outputs (use linearize)");
  const b::Siso g = b::Siso::from_state_space(ss);
  if (!g.tf())
    throw InputError("transfer from '" + from + "' to '" + to + "': its order-" + std::to_string(g.zpk().order()) +
                     " coefficients overflow double precision (use linearize)");
  return *g.tf();
}

}  // namespace

void bind_diagrams(py::module_& m) {
  py::class_<LoadedDiagram>(m, "Diagram", R"doc(
A block diagram loaded from its YAML file (docs/diagram-format.md) and evaluated at its
parameter values. Made by load_diagram().)doc")
      .def_property_readonly("name", [](const LoadedDiagram& l) { return l.diagram->name(); })
      .def_property_readonly("description", [](const LoadedDiagram& l) { return l.diagram->description(); })
      .def_property_readonly("file", [](const LoadedDiagram& l) { return l.diagram->file(); })
      .def_property_readonly("ts", [](const LoadedDiagram& l) { return l.diagram->ts(); }, "Sample time (0: continuous).")
      .def_property_readonly("is_discrete", [](const LoadedDiagram& l) { return l.diagram->is_discrete(); })
      .def_property_readonly("parameters",
                             [](const LoadedDiagram& l) {
                               py::dict p;
                               for (const auto& name : l.diagram->parameter_order()) p[py::str(name)] = l.diagram->parameters().at(name);
                               return p;
                             },
                             "Parameter values (after overrides), in definition order.")
      .def_property_readonly("inputs", [](const LoadedDiagram& l) { return names(l.diagram->inputs()); })
      .def_property_readonly("outputs", [](const LoadedDiagram& l) { return names(l.diagram->outputs()); })
      .def_property_readonly("blocks",
                             [](const LoadedDiagram& l) {
                               py::list bl;
                               for (const auto& blk : l.diagram->blocks()) bl.append(blk.name);
                               return bl;
                             })
      .def_property_readonly("signals", [](const LoadedDiagram& l) { return d::signal_names(*l.diagram); },
                             "Every signal name linearize() accepts.")
      .def("with_parameters", [](const LoadedDiagram& l, const py::object& params) {
             return LoadedDiagram{l.source, l.source->evaluate(to_parameters(params))};
           },
           "params"_a, "The same diagram at other parameter values {name: value} (the file is not read again).")
      .def("linearize", [](const LoadedDiagram& l, const std::string& from, const std::string& to) { return d::linearize(*l.diagram, from, to); },
           "from_signal"_a, "to_signal"_a, R"doc(
The linear model (StateSpace) from an additive input injected at from_signal to the
signal to_signal: a diagram input or output, block.port, subsystem.block.port. Delays
are Padé approximants in a continuous diagram.)doc")
      .def("loop_transfer", [](const LoadedDiagram& l, const std::string& at) { return d::loop_transfer(*l.diagram, at); },
           "at"_a, "The loop transfer (StateSpace) at a break point, L = -(signal before the break)/(injection): for margins().")
      .def("transfer", &transfer, "from_signal"_a, "to_signal"_a, R"doc(
The TransferFunction between two scalar signals, modes they do not see left out (the
num/den `dmbd analyze DIAGRAM --from --to` reports).)doc")
      .def("__repr__", [](const LoadedDiagram& l) { return "<dmbd.Diagram '" + l.diagram->name() + "' from " + l.diagram->file() + ">"; });

  m.def("load_diagram", &load, "path"_a, "params"_a = py::none(), R"doc(
Load and validate a diagram file, with parameter overrides {name: value}. DiagramError
(an InputError) lists every problem, one line each, as file:line:column: error: ...)doc");
}

}  // namespace dmbd::python
