// A loop program run from Python (docs/python.md, "Loop programs"): a diagram or a
// transfer function lowered as `dmbd codegen` lowers it, stepped by the interpreter
// that runs it in a scenario (codegen/interpreter.hpp), in double or float: what the
// generated code computes, bit for bit. For replaying logged inputs through a
// controller, or checking a controller written in Python against the diagram's.
#include "bindings.hpp"
#include "convert.hpp"
#include "lowering.hpp"

#include <memory>

#include <fmt/format.h>

#include "dmbd/base/error.hpp"
#include "dmbd/codegen/interpreter.hpp"

namespace dmbd::python {

namespace cg = dmbd::codegen;
using namespace pybind11::literals;

namespace {

class PyLoopProgram {
 public:
  PyLoopProgram(Lowered l, bool single)
      : p_(std::make_shared<const cg::LoopProgram>(std::move(l.program))), single_(single), d_(*p_), f_(*p_),
        u_(p_->inputs.size()), y_(p_->outputs.size()), uf_(u_.size()), yf_(y_.size()) {}

  // One sample: u (one value per input) -> y.
  py::array_t<double> step(const py::handle& u) {
    read_inputs(to_vector(u, "u"));
    advance();
    return to_array(y_);
  }
  // One row per sample of U (ticks x inputs) -> ticks x outputs.
  py::array_t<double> run(const py::handle& inputs) {
    const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(inputs);
    const py::ssize_t n_in = static_cast<py::ssize_t>(u_.size());
    if (!a || a.ndim() != 2 || a.shape(1) != n_in)
      throw InputError("run: expected a 2-D array of shape (ticks, " + std::to_string(n_in) + "): one row of inputs per sample");
    py::array_t<double> out({a.shape(0), static_cast<py::ssize_t>(y_.size())});
    double* o = out.mutable_data();
    for (py::ssize_t k = 0; k < a.shape(0); ++k) {
      std::copy(a.data(k, 0), a.data(k, 0) + n_in, u_.begin());
      advance();
      std::copy(y_.begin(), y_.end(), o + k * static_cast<py::ssize_t>(y_.size()));
    }
    return out;
  }
  void reset() {
    d_.reset();
    f_.reset();
  }
  py::list names(bool inputs) const {
    py::list l;
    for (int s : inputs ? p_->inputs : p_->outputs) l.append(p_->slots[static_cast<std::size_t>(s)].name);
    return l;
  }
  double rate_hz() const { return p_->rate_hz; }
  unsigned long long clamp_events() const { return single_ ? f_.clamp_events() : d_.clamp_events(); }
  const std::string& name() const { return p_->name; }

 private:
  void read_inputs(const std::vector<double>& u) {
    if (u.size() != u_.size())
      throw InputError("step: " + std::to_string(u.size()) + " inputs given: the program has " + std::to_string(u_.size()));
    u_ = u;
  }
  void advance() {
    if (!single_) return d_.step(u_.data(), y_.data());
    for (std::size_t k = 0; k < u_.size(); ++k) uf_[k] = static_cast<float>(u_[k]);
    f_.step(uf_.data(), yf_.data());
    for (std::size_t k = 0; k < y_.size(); ++k) y_[k] = yf_[k];
  }

  std::shared_ptr<const cg::LoopProgram> p_;
  bool single_;
  cg::Interpreter<double> d_;
  cg::Interpreter<float> f_;
  std::vector<double> u_, y_;
  std::vector<float> uf_, yf_;
};

PyLoopProgram make(const py::object& source, double rate_hz, const py::object& method, const py::object& block_methods,
                   const std::string& scalar, const py::object& params) {
  if (scalar != "double" && scalar != "float") throw InputError("scalar '" + scalar + "': expected double or float");
  Lowered l = lower(source, lower_options(rate_hz, method, block_methods), !method.is_none(), std::nullopt, params);
  for (const std::string& w : l.program.warnings)
    if (PyErr_WarnEx(PyExc_UserWarning, (l.program.name + ": " + w).c_str(), 1) != 0) throw py::error_already_set();
  return PyLoopProgram(std::move(l), scalar == "float");
}

}  // namespace

void bind_loop_program(py::module_& m) {
  py::class_<PyLoopProgram>(m, "LoopProgram", R"doc(
A diagram's loop program stepped by the interpreter a scenario runs it with: what the
generated code computes, bit for bit (double), or in float. Made by loop_program().)doc")
      .def("step", &PyLoopProgram::step, "u"_a, "One sample: u, one value per input -> y, one per output (NumPy).")
      .def("run", &PyLoopProgram::run, "inputs"_a, "One sample per row of inputs (ticks x inputs) -> outputs (ticks x outputs).")
      .def("reset", &PyLoopProgram::reset, "Every state to zero, as the generated reset().")
      .def_property_readonly("inputs", [](const PyLoopProgram& p) { return p.names(true); }, "Input slot names (in_NAME), in step's order.")
      .def_property_readonly("outputs", [](const PyLoopProgram& p) { return p.names(false); }, "Output slot names (out_NAME).")
      .def_property_readonly("rate_hz", &PyLoopProgram::rate_hz)
      .def_property_readonly("name", &PyLoopProgram::name)
      .def_property_readonly("clamp_events", &PyLoopProgram::clamp_events, "Saturations engaged since the start or reset().")
      .def("__repr__", [](const PyLoopProgram& p) { return fmt::format("<dmbd.LoopProgram '{}' at {:g} Hz>", p.name(), p.rate_hz()); });
  m.def("loop_program", &make, "source"_a, "rate_hz"_a, "method"_a = py::none(), "block_methods"_a = py::none(),
        "scalar"_a = "double", "params"_a = py::none(), R"doc(
The loop program of a diagram file (with params) or a TransferFunction, lowered at rate_hz
as generate_code and `dmbd codegen` lower it (method: the discretisation of blocks without
their own; default the diagram's, else tustin), run by the interpreter in double or float.)doc");
}

}  // namespace dmbd::python
