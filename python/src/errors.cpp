// The project's errors as Python exceptions (docs/python.md, "Errors"): one class per
// kind, under InputError, itself a ValueError. The message is the library's own text
// (file:line:column: ... for a diagram, a scenario or a model file), unchanged.
#include "bindings.hpp"
#include "py_controller.hpp"

#include <exception>

#include "dmbd/base/error.hpp"
#include "dmbd/blocks/error.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "dmbd/model/error.hpp"
#include "dmbd/sim/simulation.hpp"

namespace dmbd::python {

namespace {

// The Python classes, made once when the module is imported and kept for the life of
// the interpreter (never released: a translator may run until the very end).
struct Classes {
  py::handle input, output, expression, diagram, model, divergence, controller;
};
Classes classes;

py::handle make_class(py::module_& m, const char* name, py::handle base, const char* doc) {
  py::object cls = py::reinterpret_steal<py::object>(
      PyErr_NewExceptionWithDoc((std::string("dmbd.") + name).c_str(), doc, base.ptr(), nullptr));
  if (!cls) throw py::error_already_set();
  m.attr(name) = cls;
  return cls.release();
}

// Raises an instance of `cls` with the message, after setting its attributes.
void raise(py::handle cls, const InputError& e, const py::dict& attributes = py::dict()) {
  py::object exc = cls(py::str(e.what()));
  for (const auto& [k, v] : attributes) exc.attr(k) = v;
  PyErr_SetObject(cls.ptr(), exc.ptr());
}

void translate(std::exception_ptr p) {
  try {
    if (p) std::rethrow_exception(p);
  } catch (const blocks::ExpressionError& e) {
    py::dict a;
    a["column"] = e.column();
    raise(classes.expression, e, a);
  } catch (const diagrams::DiagramError& e) {
    py::list ds;
    for (const Diagnostic& d : e.diagnostics())
      ds.append(py::make_tuple(d.where.file, d.where.line, d.where.column, d.message));
    py::dict a;
    a["diagnostics"] = ds;
    raise(classes.diagram, e, a);
  } catch (const model::ModelError& e) {
    raise(classes.model, e);
  } catch (const sim::DivergenceError& e) {
    raise(classes.divergence, e);
  } catch (const PythonControllerError& e) {
    py::dict a;
    a["controller"] = e.controller();
    a["time_s"] = e.time_s();
    a["traceback"] = e.traceback();
    raise(classes.controller, e, a);
  } catch (const OutputError& e) {
    raise(classes.output, e);
  } catch (const InputError& e) {
    raise(classes.input, e);
  }
}

}  // namespace

void bind_errors(py::module_& m) {
  classes.input = make_class(m, "InputError", PyExc_ValueError,
                             "A mistake in what was given (a file, an expression, a value, a model that diverges).\n"
                             "str(e) is the library's one-line message (one line per problem for a diagram),\n"
                             "naming where: file:line:column, the signal, the parameter.");
  classes.output = make_class(m, "OutputError", classes.input, "An output that cannot be written; the message names the path and the reason.");
  classes.expression = make_class(m, "ExpressionError", classes.input,
                                  "A malformed or unevaluable rational expression; `column` is the 1-based column in it.");
  classes.diagram = make_class(m, "DiagramError", classes.input,
                               "Every problem found in a diagram file, one line each ('file:line:column: error: ...');\n"
                               "`diagnostics` lists them as (file, line, column, message) tuples.");
  classes.model = make_class(m, "ModelError", classes.input,
                             "A mistake in a model file (URDF, actuator table) or a plant that diverged.");
  classes.divergence = make_class(m, "DivergenceError", classes.input,
                                  "A simulation that diverged; the message names the time and the state.");
  classes.controller = make_class(m, "ControllerError", classes.input,
                                  "A Python controller's step() or reset() raised (run_scenario(controllers=...)): the message\n"
                                  "ends with the traceback's last line; `controller` names it, `time_s` is the tick's time,\n"
                                  "`traceback` the whole formatted traceback.");
  py::register_exception_translator(&translate);
}

}  // namespace dmbd::python
