#include "convert.hpp"

#include <cmath>

#include "dmbd/base/error.hpp"

namespace dmbd::python {

namespace {

using RealArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

// A real array of any shape; TypeError for text, objects or complex numbers (their
// imaginary parts would be dropped silently by a cast).
RealArray real_array(const py::handle& x, const std::string& what) {
  const py::module_ np = py::module_::import("numpy");
  py::object a;
  try {
    a = np.attr("asarray")(x);
  } catch (py::error_already_set&) {
    throw py::type_error(what + ": expected real numbers");
  }
  const char kind = a.attr("dtype").attr("kind").cast<std::string>()[0];
  if (kind != 'f' && kind != 'i' && kind != 'u' && kind != 'b')
    throw py::type_error(what + ": expected real numbers, got an array of dtype " + py::str(a.attr("dtype")).cast<std::string>());
  return RealArray::ensure(a);
}

}  // namespace

py::array_t<double> to_array(const std::vector<double>& v) {
  py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

py::array_t<std::complex<double>> to_array(const std::vector<std::complex<double>>& v) {
  py::array_t<std::complex<double>> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

py::array_t<double> to_array(const blocks::Matrix& m) {
  py::array_t<double> a({static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
  auto w = a.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) w(i, j) = m(i, j);
  return a;
}

std::vector<double> to_vector(const py::handle& x, const std::string& what) {
  const RealArray a = real_array(x, what);
  if (a.ndim() > 1) throw InputError(what + ": expected a 1-D sequence of numbers, got " + std::to_string(a.ndim()) + " dimensions");
  return std::vector<double>(a.data(), a.data() + a.size());
}

blocks::Matrix to_matrix(const py::handle& x, const std::string& what, Vector1D as1d) {
  const RealArray a = real_array(x, what);
  if (a.ndim() > 2) throw InputError(what + ": expected a matrix (2-D), got " + std::to_string(a.ndim()) + " dimensions");
  if (a.ndim() == 0) return blocks::Matrix::Constant(1, 1, *a.data());
  if (a.ndim() == 1) {
    const Eigen::Index n = a.shape(0);
    if (as1d == Vector1D::Scalar && n != 1)
      throw InputError(what + ": expected a square matrix (2-D), got a 1-D array of " + std::to_string(n) + " entries");
    blocks::Matrix m = as1d == Vector1D::Row ? blocks::Matrix(1, n) : blocks::Matrix(n, 1);
    for (Eigen::Index k = 0; k < n; ++k) m(k) = a.data()[k];
    return m;
  }
  blocks::Matrix m(a.shape(0), a.shape(1));
  auto r = a.unchecked<2>();
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) m(i, j) = r(i, j);
  return m;
}

blocks::ParameterMap to_parameters(const py::handle& params) {
  blocks::ParameterMap out;
  if (params.is_none()) return out;
  if (!py::isinstance<py::dict>(params)) throw py::type_error("params: expected a dict {name: number}");
  for (const auto& [k, v] : params.cast<py::dict>()) {
    const std::string name = py::str(k).cast<std::string>();
    try {
      out[name] = v.cast<double>();
    } catch (py::cast_error&) {
      throw py::type_error("params: '" + name + "' is not a number");
    }
  }
  return out;
}

std::string to_path(const py::handle& path) {
  return py::module_::import("os").attr("fspath")(path).cast<std::string>();
}

py::object optional_float(const std::optional<double>& v) { return v ? py::object(py::float_(*v)) : py::object(py::none()); }

py::object to_python(const nlohmann::json& j, bool nonfinite_numbers) {
  switch (j.type()) {
    case nlohmann::json::value_t::null: return py::none();
    case nlohmann::json::value_t::boolean: return py::bool_(j.get<bool>());
    case nlohmann::json::value_t::number_integer: return py::int_(j.get<long long>());
    case nlohmann::json::value_t::number_unsigned: return py::int_(j.get<unsigned long long>());
    case nlohmann::json::value_t::number_float: return py::float_(j.get<double>());
    case nlohmann::json::value_t::string: {
      const std::string& t = j.get_ref<const std::string&>();
      if (nonfinite_numbers && (t == "inf" || t == "-inf" || t == "NaN"))
        return py::float_(t == "NaN" ? std::nan("") : (t == "inf" ? HUGE_VAL : -HUGE_VAL));
      return py::str(t);
    }
    case nlohmann::json::value_t::array: {
      py::list l;
      for (const auto& e : j) l.append(to_python(e, nonfinite_numbers));
      return std::move(l);
    }
    case nlohmann::json::value_t::object: {
      py::dict d;
      for (auto it = j.begin(); it != j.end(); ++it) d[py::str(it.key())] = to_python(it.value(), nonfinite_numbers);
      return std::move(d);
    }
    case nlohmann::json::value_t::binary:
    case nlohmann::json::value_t::discarded: break;
  }
  return py::none();
}

}  // namespace dmbd::python
