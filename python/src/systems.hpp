#pragma once
// What the functions of the module accept as a system: a TransferFunction, a
// StateSpace, or (where a static gain makes sense) a number.
#include "pybind.hpp"

#include <string>

#include "dmbd/blocks/state_space.hpp"
#include "dmbd/blocks/transfer_function.hpp"

namespace dmbd::python {

bool is_number(const py::handle& x);
// A TransferFunction, or a number as a static gain (of sample time ts).
bool is_tf_like(const py::handle& x);
blocks::TransferFunction as_tf(const py::handle& x, double ts = 0.0);
// A StateSpace, a proper TransferFunction realised (StateSpace::from_tf), or a number
// as a 1 x 1 gain (of sample time ts). TypeError naming `what` otherwise.
blocks::StateSpace as_ss(const py::handle& x, const std::string& what, double ts = 0.0);
// The sample time of a system argument (0 for a number).
double sample_time(const py::handle& x);

}  // namespace dmbd::python
