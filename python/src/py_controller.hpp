#pragma once
// Controllers written in Python, on the simulated robot's bus (docs/python.md,
// "Controllers in Python"): an object with step(t, inputs) -> outputs, its rate, delay
// and ports (bus signals), run by a bus controller type registered under "python"
// (control/registry.hpp) when the module is imported. Given to run_scenario(...,
// controllers={name: obj}); a scenario file cannot name the type.
#include "pybind.hpp"

#include <memory>
#include <string>
#include <vector>

#include "dmbd/base/error.hpp"
#include "dmbd/control/bus_controller.hpp"

namespace dmbd::python {

// A strong reference to a Python object that may be copied and dropped without the
// GIL (the scenario holding it is copied while the simulation runs with the GIL
// released): the reference count is touched only under the GIL, once each way.
class PyRef {
 public:
  explicit PyRef(const py::object& o);  // under the GIL
  ~PyRef();                             // takes the GIL
  PyRef(const PyRef&) = delete;
  PyRef& operator=(const PyRef&) = delete;
  py::handle get() const { return p_; }

 private:
  PyObject* p_;
};

// A Python controller's options: the common ones (name, rate_hz, delay_s) and its ports.
struct PythonControllerOptions : control::BusControllerOptions {
  std::shared_ptr<const PyRef> object;  // has step(t, inputs) and, optionally, reset()
  std::vector<std::string> inputs;      // bus signals, in the order of step's input array
  std::vector<std::string> outputs;     // bus signals, in the order of its returned array
  std::vector<std::string> units;       // each output's unit ("" unless given)
};

// The options of `obj` under `name`: obj.rate_hz (required), obj.delay_s (default 0,
// at most one period), obj.inputs (bus signal names), obj.outputs (bus signal names,
// or a dict {signal: unit}), obj.step callable. Throws InputError naming
// "controllers['NAME']" and what was expected. Under the GIL.
std::shared_ptr<PythonControllerOptions> python_controller_options(const std::string& name, const py::object& obj);

// A Python exception raised by a controller's step() or reset(): the run stops with
// its traceback's last line ("ZeroDivisionError: division by zero"); `traceback` is
// the whole formatted traceback.
class PythonControllerError : public InputError {
 public:
  PythonControllerError(const std::string& message, std::string controller, double time_s, std::string traceback)
      : InputError(message), controller_(std::move(controller)), time_s_(time_s), traceback_(std::move(traceback)) {}
  const std::string& controller() const { return controller_; }
  double time_s() const { return time_s_; }
  const std::string& traceback() const { return traceback_; }

 private:
  std::string controller_;
  double time_s_;
  std::string traceback_;
};

// Registers the type "python" (once, at import).
void register_python_controller_type();

}  // namespace dmbd::python
