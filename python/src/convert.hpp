#pragma once
// Values between Python and the libraries: NumPy arrays to and from vectors and
// matrices, parameter dicts, optional numbers, JSON documents as Python objects.
#include "pybind.hpp"

#include <complex>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dmbd/blocks/expression.hpp"
#include "dmbd/blocks/state_space.hpp"

namespace dmbd::python {

// NumPy copies of library values.
py::array_t<double> to_array(const std::vector<double>& v);
py::array_t<std::complex<double>> to_array(const std::vector<std::complex<double>>& v);
py::array_t<double> to_array(const blocks::Matrix& m);

// A 1-D sequence of real numbers (a list, a tuple, a 1-D array, or a scalar as one
// entry). `what` names it in messages: TypeError for anything not real numbers,
// InputError for more than one dimension.
std::vector<double> to_vector(const py::handle& x, const std::string& what);

// How a 1-D array becomes a matrix: a column (B), a row (C, D) or either only when it
// has one entry (A).
enum class Vector1D { Column, Row, Scalar };
// A real matrix from a 2-D array-like (a scalar is 1 x 1; a 1-D one as `as1d` says).
blocks::Matrix to_matrix(const py::handle& x, const std::string& what, Vector1D as1d);

// A dict {name: number} (or None) as parameter values.
blocks::ParameterMap to_parameters(const py::handle& params);

// A file name from a str or an os.PathLike (pathlib.Path).
std::string to_path(const py::handle& path);

// None when empty.
py::object optional_float(const std::optional<double>& v);

// A JSON document as dicts, lists, str, int, float, bool and None. With
// `nonfinite_numbers`, the strings "inf", "-inf" and "NaN" (what scenario::finite_json writes
// for those numbers, JSON having none) become the floats again.
py::object to_python(const nlohmann::json& j, bool nonfinite_numbers = false);

// Applies f to a complex number, or to every entry of an array-like (the result has
// its shape): what evaluations at points of the s- or z-plane accept.
template <typename F>
py::object map_complex(const py::handle& x, F f) {
  if (py::isinstance<py::float_>(x) || py::isinstance<py::int_>(x) || PyComplex_Check(x.ptr()))
    return py::cast(f(x.cast<std::complex<double>>()));
  auto a = py::array_t<std::complex<double>, py::array::c_style | py::array::forcecast>::ensure(x);
  if (!a) throw py::type_error("expected a complex number or an array of them");
  py::array_t<std::complex<double>> out(std::vector<py::ssize_t>(a.shape(), a.shape() + a.ndim()));
  const std::complex<double>* in = a.data();
  std::complex<double>* o = out.mutable_data();
  for (py::ssize_t k = 0; k < a.size(); ++k) o[k] = f(in[k]);
  return std::move(out);
}

}  // namespace dmbd::python
