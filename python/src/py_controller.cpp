// Controllers written in Python on the bus (py_controller.hpp): the bus controller that
// calls a Python object's step() once per tick, its type "python", and the options read
// from the object's attributes.
#include "py_controller.hpp"

#include <cmath>

#include <fmt/format.h>

#include "dmbd/control/registry.hpp"
#include "dmbd/sim/event_grid.hpp"

namespace dmbd::python {

PyRef::PyRef(const py::object& o) : p_(o.inc_ref().ptr()) {}

PyRef::~PyRef() {
  if (!Py_IsInitialized()) return;  // the interpreter is gone: nothing left to release
  py::gil_scoped_acquire gil;
  Py_XDECREF(p_);
}

namespace {

std::string where(const std::string& name) { return "run_scenario: controllers['" + name + "']"; }

// A list of bus signal names (a str is refused: it would be read letter by letter).
std::vector<std::string> signal_list(const py::handle& x, const std::string& what) {
  if (py::isinstance<py::str>(x) || !py::isinstance<py::sequence>(x))
    throw InputError(what + ": expected a list of bus signal names, got " + py::repr(x).cast<std::string>());
  std::vector<std::string> out;
  for (const auto& e : x.cast<py::sequence>()) {
    if (!py::isinstance<py::str>(e) || e.cast<std::string>().empty())
      throw InputError(what + ": expected bus signal names (non-empty str), got " + py::repr(e).cast<std::string>());
    out.push_back(e.cast<std::string>());
  }
  return out;
}

double number_attr(const py::object& obj, const char* attr, const std::string& what) {
  const py::object v = obj.attr(attr);
  if (py::isinstance<py::bool_>(v) || !(py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v) || py::hasattr(v, "__float__")))
    throw InputError(what + "." + attr + ": expected a number, got " + py::repr(v).cast<std::string>());
  return v.cast<double>();
}

// obj.outputs: a list of signals (no units) or a dict {signal: unit}.
void read_outputs(const py::object& obj, const std::string& w, PythonControllerOptions& o) {
  const py::object outs = obj.attr("outputs");
  if (py::isinstance<py::dict>(outs)) {
    for (const auto& [k, v] : outs.cast<py::dict>()) {
      if (!py::isinstance<py::str>(k) || !py::isinstance<py::str>(v) || k.cast<std::string>().empty())
        throw InputError(w + ".outputs: expected {bus signal: unit} with str keys and values, got " + py::repr(outs).cast<std::string>());
      o.outputs.push_back(k.cast<std::string>());
      o.units.push_back(v.cast<std::string>());
    }
  } else {
    o.outputs = signal_list(outs, w + ".outputs");
    o.units.assign(o.outputs.size(), "");
  }
  if (o.outputs.empty()) throw InputError(w + ".outputs: expected at least one bus signal to drive");
}

// One tick's returned value into y: a 1-D array-like of n finite numbers (a number
// when n is 1).
void copy_outputs(const py::object& r, const PythonControllerOptions& o, double t, double* y) {
  const std::size_t n = o.outputs.size();
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(r);
  if (!a || a.ndim() > 1 || static_cast<std::size_t>(a.size()) != n) {
    if (!a) PyErr_Clear();
    throw InputError(fmt::format("{} at t = {} s: step returned {}: expected {} number{} ({})", where(o.name), t,
                                 py::repr(r).cast<std::string>(), n, n == 1 ? "" : "s", fmt::join(o.outputs, ", ")));
  }
  const double* d = a.data();
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(d[k]))
      throw InputError(fmt::format("{} at t = {} s: step returned {} for {}: expected a finite number", where(o.name), t, d[k], o.outputs[k]));
    y[k] = d[k];
  }
}

// The error a Python exception becomes: its traceback's last line, and the whole of it.
PythonControllerError python_error(py::error_already_set& e, const std::string& name, double t) {
  const py::module_ tb = py::module_::import("traceback");
  const py::list only = tb.attr("format_exception_only")(e.type(), e.value());
  std::string last = only.empty() ? std::string("an exception") : py::str(only[only.size() - 1]).cast<std::string>();
  while (!last.empty() && (last.back() == '\n' || last.back() == ' ')) last.pop_back();
  const std::string full = py::str("").attr("join")(tb.attr("format_exception")(e.type(), e.value(), e.trace())).cast<std::string>();
  return PythonControllerError(fmt::format("{} at t = {} s: {}", where(name), t, last), name, t, full);
}

// Calls step(t, inputs) once per tick under the GIL; reset() before the run, if it has one.
class PythonController : public control::BusController {
 public:
  PythonController(const PythonControllerOptions& o, const control::BusControllerContext& c)
      : BusController(o, control::ticks_over(c.duration_s, o.rate_hz)), o_(o) {
    for (const auto& s : o.inputs) add_input(s);
    for (std::size_t k = 0; k < o.outputs.size(); ++k) add_output(o.outputs[k], o.units[k]);
    py::gil_scoped_acquire gil;
    const py::handle obj = o.object->get();
    step_ = std::make_unique<PyRef>(obj.attr("step"));
    if (!py::hasattr(obj, "reset")) return;
    try {
      obj.attr("reset")();
    } catch (py::error_already_set& e) {
      throw python_error(e, o_.name, 0.0);
    }
  }
  std::string timing_name() const override { return "python_" + o_.name; }

 protected:
  void tick(const double* u, double* y) override {
    py::gil_scoped_acquire gil;
    const double t = static_cast<double>(ticks()) / rate_hz();
    try {
      py::array_t<double> in(static_cast<py::ssize_t>(o_.inputs.size()));
      std::copy(u, u + o_.inputs.size(), in.mutable_data());
      copy_outputs(step_->get()(t, in), o_, t, y);
    } catch (py::error_already_set& e) {
      throw python_error(e, o_.name, t);
    }
  }

 private:
  PythonControllerOptions o_;
  std::unique_ptr<PyRef> step_;  // the bound method, looked up once
};

class PythonControllerType : public control::BusControllerType {
 public:
  std::shared_ptr<control::BusControllerOptions> read(const yaml::Fields& f, const YAML::Node& n,
                                                      const control::BusControllerOptions*) const override {
    f.fail(n, "bus controller type 'python': a Python controller is given from Python, "
              "run_scenario(..., controllers={name: obj}) (docs/python.md), not in a scenario file");
  }
  std::shared_ptr<control::BusController> make(const control::BusControllerOptions& o,
                                               const control::BusControllerContext& c) const override {
    return std::make_shared<PythonController>(dynamic_cast<const PythonControllerOptions&>(o), c);
  }
};

}  // namespace

std::shared_ptr<PythonControllerOptions> python_controller_options(const std::string& name, const py::object& obj) {
  const std::string w = where(name);
  for (const char* a : {"step", "rate_hz", "inputs", "outputs"})
    if (!py::hasattr(obj, a))
      throw InputError(w + ": " + py::repr(obj).cast<std::string>() + " has no attribute '" + a +
                       "' (expected step(t, inputs) -> outputs, rate_hz, inputs, outputs)");
  if (!PyCallable_Check(obj.attr("step").ptr())) throw InputError(w + ".step: expected a method step(t, inputs) -> outputs");
  auto o = std::make_shared<PythonControllerOptions>();
  o->type = "python";
  o->name = name;
  o->where = w;
  o->rate_hz = number_attr(obj, "rate_hz", w);
  if (const std::string p = sim::rate_problem(o->rate_hz); !p.empty()) throw InputError(w + ".rate_hz: " + p);
  if (py::hasattr(obj, "delay_s")) o->delay_s = number_attr(obj, "delay_s", w);
  if (!(o->delay_s >= 0.0) || o->delay_s > 1.0 / o->rate_hz)
    throw InputError(fmt::format("{}.delay_s: {} s: expected 0 to one period of {} Hz ({} s)", w, o->delay_s, o->rate_hz, 1.0 / o->rate_hz));
  o->inputs = signal_list(obj.attr("inputs"), w + ".inputs");
  read_outputs(obj, w, *o);
  o->object = std::make_shared<const PyRef>(obj);
  return o;
}

void register_python_controller_type() { control::register_bus_controller("python", std::make_shared<PythonControllerType>()); }

}  // namespace dmbd::python
