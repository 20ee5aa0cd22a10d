// The Python module dmbd._dmbd (docs/python.md); the package dmbd re-exports it.
#include "bindings.hpp"

#include "dmbd/version.hpp"

PYBIND11_MODULE(_dmbd, m) {
  m.doc() = "draco-mbd: linear systems, block diagrams, code generation and scenarios (docs/python.md)";
  m.attr("__version__") = dmbd::kVersion;
  dmbd::python::bind_errors(m);
  dmbd::python::bind_lti(m);
  dmbd::python::bind_analysis(m);
  dmbd::python::bind_control_verbs(m);
  dmbd::python::bind_diagrams(m);
  dmbd::python::bind_codegen(m);
  dmbd::python::bind_loop_program(m);
  dmbd::python::bind_sim(m);
  dmbd::python::bind_model(m);
}
