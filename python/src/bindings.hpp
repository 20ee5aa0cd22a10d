#pragma once
// The Python module's parts (docs/python.md), one file each, registered by module.cpp in
// this order: errors first (every other part's exceptions are translated by it), then
// the systems, their analysis, diagrams, code generation and scenarios.
#include "pybind.hpp"

namespace dmbd::python {

void bind_errors(py::module_& m);    // errors.cpp: InputError and its kinds as Python exceptions
void bind_lti(py::module_& m);       // lti.cpp: TransferFunction, StateSpace, interconnection, c2d/d2c
void bind_analysis(py::module_& m);  // analysis.cpp: poles, zeros, Bode, step, margins
// control_verbs.cpp (+ control_results.cpp): python-control's verbs (margin, lqr, place, forced_response, ...)
void bind_control_verbs(py::module_& m);
void bind_diagrams(py::module_& m);  // diagrams.cpp: load_diagram, Diagram.linearize
void bind_codegen(py::module_& m);   // codegen.cpp: generate_code
void bind_loop_program(py::module_& m);  // loop_program.cpp: loop_program, LoopProgram (the interpreter)
void bind_sim(py::module_& m);       // sim.cpp: run_scenario, ScenarioRun
void bind_model(py::module_& m);     // model.cpp: load_robot, RobotModel (the robot's rigid-body model)

}  // namespace dmbd::python
