#pragma once
// pybind11 with the casters the module uses (NumPy arrays, Eigen matrices, complex
// numbers, standard containers). Included before anything else of the module's.
#include <pybind11/complex.h>
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace dmbd::python {
namespace py = pybind11;
}  // namespace dmbd::python
