// The result classes of the python-control verbs (docs/python.md, "python-control's
// verbs"): python-control 0.10's TimeResponseData, NyquistResponseData and PoleZeroData,
// their attributes, squeeze rules and legacy tuple unpacking.
#include "control_results.hpp"

namespace dmbd::python {

using namespace pybind11::literals;

namespace {

int ndim(const py::object& a) { return py::cast<py::array>(a).ndim(); }

// python-control's _process_time_response: squeeze=None drops the signal index (and the
// trace index) of a SISO response; True squeezes every unit dimension; False none.
py::object squeezed(const TimeResponseData& r, const py::object& a) {
  if (a.is_none()) return a;
  if (r.squeeze.is_none()) {
    if (!r.issiso) return a;
    return ndim(a) == 3 ? a[py::int_(0)][py::int_(0)] : a[py::int_(0)];
  }
  if (r.squeeze.cast<bool>()) return py::module_::import("numpy").attr("squeeze")(a);
  return a;
}

int rows(const py::object& a) { return a.is_none() ? 0 : static_cast<int>(py::cast<py::array>(a).shape(0)); }

// The states as the legacy tuple gives them: one trace of a SISO response without its
// trace index, whatever `squeeze` says.
py::object legacy_states(const TimeResponseData& r) {
  if (r.x.is_none()) return r.x;
  if (rows(r.u) == 1 && rows(r.y) == 1 && r.ntraces == 1 && ndim(r.x) == 3)
    return r.x[py::make_tuple(py::slice(py::none(), py::none(), py::none()), 0)];
  return r.x;
}

py::object states(const TimeResponseData& r) {
  if (r.x.is_none()) return r.x;
  if (!r.squeeze.is_none() && r.squeeze.cast<bool>()) return py::module_::import("numpy").attr("squeeze")(r.x);
  if (!r.squeeze.is_none()) return r.x;
  return legacy_states(r);
}

py::tuple unpacked(const TimeResponseData& r) {
  if (r.return_x) return py::make_tuple(r.t, squeezed(r, r.y), legacy_states(r));
  return py::make_tuple(r.t, squeezed(r, r.y));
}

py::tuple unpacked(const NyquistResponseData& r) {
  return r.return_contour ? py::make_tuple(r.count, r.contour) : py::make_tuple(r.count);
}

// response(squeeze=..., return_x=...): a copy with those changed; TypeError for any other keyword.
TimeResponseData with_keywords(const TimeResponseData& r, const py::kwargs& kw) {
  TimeResponseData c = r;
  for (const auto& [k, v] : kw) {
    const std::string key = py::str(k).cast<std::string>();
    if (key == "squeeze")
      c.squeeze = py::reinterpret_borrow<py::object>(v);
    else if (key == "return_x")
      c.return_x = v.cast<bool>();
    else
      throw py::type_error("TimeResponseData: unrecognised keyword '" + key + "' (squeeze, return_x)");
  }
  return c;
}

void bind_time_response(py::module_& m) {
  py::class_<TimeResponseData>(m, "TimeResponseData", R"doc(
A time response, as python-control's TimeResponseData: time, outputs, states, inputs
(squeezed: a SISO response's outputs and inputs are 1-D; outputs x samples otherwise,
outputs x traces x samples for the step and impulse responses of several inputs), the
raw t, y, x, u, and the legacy unpacking t, y = response (t, y, x with return_x=True).)doc")
      .def_property_readonly("time", [](const TimeResponseData& r) { return r.t; }, "Times (s), 1-D.")
      .def_property_readonly("outputs", [](const TimeResponseData& r) { return squeezed(r, r.y); })
      .def_property_readonly("states", &states)
      .def_property_readonly("inputs", [](const TimeResponseData& r) { return squeezed(r, r.u); })
      .def_readonly("t", &TimeResponseData::t)
      .def_readonly("y", &TimeResponseData::y)
      .def_readonly("x", &TimeResponseData::x)
      .def_readonly("u", &TimeResponseData::u)
      .def_readonly("issiso", &TimeResponseData::issiso)
      .def_readonly("ntraces", &TimeResponseData::ntraces)
      .def_readonly("squeeze", &TimeResponseData::squeeze)
      .def_readonly("return_x", &TimeResponseData::return_x)
      .def_readonly("title", &TimeResponseData::title)
      .def_property_readonly("noutputs", [](const TimeResponseData& r) { return rows(r.y); })
      .def_property_readonly("nstates", [](const TimeResponseData& r) { return rows(r.x); })
      .def_property_readonly("ninputs", [](const TimeResponseData& r) { return rows(r.u); })
      .def("__iter__", [](const TimeResponseData& r) { return py::iter(unpacked(r)); })
      .def("__len__", [](const TimeResponseData& r) { return r.return_x ? 3 : 2; })
      .def("__call__", &with_keywords, "A copy with other squeeze or return_x (python-control's response(squeeze=...)).")
      .def("__getitem__", [](const TimeResponseData& r, const py::object& i) {
        const py::tuple all = py::make_tuple(r.t, squeezed(r, r.y), legacy_states(r));
        return py::object(all[i]);
      })
      .def("__repr__", [](const TimeResponseData& r) { return "<TimeResponseData: " + r.title + ">"; });
}

}  // namespace

void bind_control_results(py::module_& m) {
  bind_time_response(m);
  py::class_<NyquistResponseData>(m, "NyquistResponseData", R"doc(
Nyquist data, as python-control's NyquistResponseData: count (clockwise encirclements of
-1), contour (the points of the s- or z-plane), response (the loop there), dt. Unpacks
as (count,), or (count, contour) with return_contour=True.)doc")
      .def_readonly("count", &NyquistResponseData::count)
      .def_readonly("contour", &NyquistResponseData::contour)
      .def_readonly("response", &NyquistResponseData::response)
      .def_readonly("dt", &NyquistResponseData::dt)
      .def_readonly("return_contour", &NyquistResponseData::return_contour)
      .def("__iter__", [](const NyquistResponseData& r) { return py::iter(unpacked(r)); })
      .def("__len__", [](const NyquistResponseData& r) { return r.return_contour ? 2 : 1; })
      .def("__getitem__", [](const NyquistResponseData& r, const py::object& i) { return py::object(unpacked(r)[i]); });
  py::class_<PoleZeroData>(m, "PoleZeroData", R"doc(
Poles and zeros, as python-control's PoleZeroData: poles, zeros, and for a root locus
gains and loci (one row per gain, one column per branch), dt. Unpacks as (poles, zeros).)doc")
      .def_readonly("poles", &PoleZeroData::poles)
      .def_readonly("zeros", &PoleZeroData::zeros)
      .def_readonly("gains", &PoleZeroData::gains)
      .def_readonly("loci", &PoleZeroData::loci)
      .def_readonly("dt", &PoleZeroData::dt)
      .def("__iter__", [](const PoleZeroData& r) { return py::iter(py::make_tuple(r.poles, r.zeros)); });
}

}  // namespace dmbd::python
