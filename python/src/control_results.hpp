#pragma once
// The result objects of python-control's verbs (control_verbs.cpp), with python-control
// 0.10's attributes and its legacy tuple unpacking: TimeResponseData (t, y = response),
// NyquistResponseData (count = response), PoleZeroData (poles, zeros = data).
#include "pybind.hpp"

#include <string>

namespace dmbd::python {

// A time response as python-control's TimeResponseData keeps it: t (samples), y
// (outputs x samples, or outputs x traces x samples), x (states x [traces x] samples) and u
// (inputs x [traces x] samples, or None); `outputs`, `states` and `inputs` apply the
// squeeze rules (a SISO response's outputs are 1-D).
struct TimeResponseData {
  py::object t, y, x, u;
  bool issiso = false;
  int ntraces = 0;             // 0: one trace, its index left out of the arrays
  py::object squeeze = py::none();
  bool return_x = false;       // unpacks as (t, y, x) instead of (t, y)
  std::string title;
};

struct NyquistResponseData {
  int count = 0;               // clockwise encirclements of -1
  py::object contour, response;
  double dt = 0.0;
  bool return_contour = false; // unpacks as (count, contour) instead of (count,)
};

struct PoleZeroData {
  py::object poles, zeros, gains = py::none(), loci = py::none();
  double dt = 0.0;
};

// Registers the three classes (before the verbs that return them).
void bind_control_results(py::module_& m);

}  // namespace dmbd::python
