// Linear systems (docs/python.md, "Systems"): TransferFunction and StateSpace, made from
// expressions or arrays, their interconnection (series, parallel, feedback, append and
// the operators), and conversion between continuous and discrete time.
#include "bindings.hpp"
#include "convert.hpp"
#include "systems.hpp"

#include "dmbd/base/error.hpp"
#include "dmbd/blocks/discretize.hpp"
#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/expression.hpp"

namespace dmbd::python {

namespace b = dmbd::blocks;
using b::StateSpace;
using b::TransferFunction;
using namespace pybind11::literals;

bool is_number(const py::handle& x) {
  return !py::isinstance<py::bool_>(x) && (py::isinstance<py::float_>(x) || py::isinstance<py::int_>(x) ||
                                           (py::isinstance<py::array>(x) && py::cast<py::array>(x).ndim() == 0 &&
                                            py::cast<py::array>(x).dtype().kind() == 'f'));
}

bool is_tf_like(const py::handle& x) { return py::isinstance<TransferFunction>(x) || is_number(x); }

TransferFunction as_tf(const py::handle& x, double ts) {
  if (py::isinstance<TransferFunction>(x)) return x.cast<TransferFunction>();
  if (is_number(x)) return TransferFunction(x.cast<double>(), ts);
  throw py::type_error("expected a TransferFunction or a number, got " + py::str(py::type::of(x)).cast<std::string>());
}

StateSpace as_ss(const py::handle& x, const std::string& what, double ts) {
  if (py::isinstance<StateSpace>(x)) return x.cast<StateSpace>();
  if (py::isinstance<TransferFunction>(x)) return StateSpace::from_tf(x.cast<TransferFunction>());
  if (is_number(x)) return StateSpace::gain(b::Matrix::Constant(1, 1, x.cast<double>()), ts);
  throw py::type_error(what + ": expected a StateSpace, a TransferFunction or a number, got " +
                       py::str(py::type::of(x)).cast<std::string>());
}

double sample_time(const py::handle& x) {
  if (py::isinstance<StateSpace>(x)) return x.cast<const StateSpace&>().ts();
  if (py::isinstance<TransferFunction>(x)) return x.cast<const TransferFunction&>().ts();
  return 0.0;
}

namespace {

// tf("expression"): in s, or in z with a sample time (as `dmbd analyze --tf`).
TransferFunction parse_tf(const std::string& text, double ts, const py::object& params) {
  try {
    const b::Expression e = b::Expression::parse(text);
    const bool discrete = e.uses('z');
    if (discrete && e.uses('s')) throw InputError("uses both s and z");
    if (discrete && !(ts > 0.0)) throw InputError("an expression in z needs a sample time ts > 0");
    if (!discrete && ts > 0.0 && e.uses('s'))
      throw InputError("an expression in s is continuous: give ts only with an expression in z (or discretise with c2d)");
    return TransferFunction::parse(text, to_parameters(params), ts);
  } catch (InputError& e) {
    e.prepend("tf '" + text + "': ");
    throw;
  }
}

std::string list_repr(const std::vector<double>& v) { return py::repr(py::cast(v)).cast<std::string>(); }

std::string tf_repr(const TransferFunction& g) {
  std::string s = "TransferFunction(" + list_repr(g.num().descending()) + ", " + list_repr(g.den().descending());
  if (g.is_discrete()) s += ", ts=" + py::repr(py::float_(g.ts())).cast<std::string>();
  return s + ")";
}

std::string ss_repr(const StateSpace& s) {
  std::string r = "StateSpace(" + std::to_string(s.num_states()) + " states, " + std::to_string(s.num_inputs()) +
                  " inputs, " + std::to_string(s.num_outputs()) + " outputs";
  if (s.is_discrete()) r += ", ts=" + py::repr(py::float_(s.ts())).cast<std::string>();
  return r + ")";
}

StateSpace negated(const StateSpace& s) { return StateSpace(s.a(), s.b(), -s.c(), -s.d(), s.ts()); }

StateSpace make_ss(const py::object& a, const py::object& bm, const py::object& c, const py::object& d, double ts) {
  const b::Matrix A = to_matrix(a, "A", Vector1D::Scalar), B = to_matrix(bm, "B", Vector1D::Column),
                  C = to_matrix(c, "C", Vector1D::Row);
  const b::Matrix D = d.is_none() ? b::Matrix::Zero(C.rows(), B.cols()) : to_matrix(d, "D", Vector1D::Row);
  return StateSpace(A, B, C, D, ts);
}

// The interconnection functions on any two systems: transfer functions stay transfer
// functions; anything with a StateSpace is done in state space.
py::object series(const py::object& first, const py::object& second) {
  if (is_tf_like(first) && is_tf_like(second)) {
    const double ts = std::max(sample_time(first), sample_time(second));
    return py::cast(as_tf(second, ts) * as_tf(first, ts));
  }
  const double ts = std::max(sample_time(first), sample_time(second));
  return py::cast(b::series(as_ss(first, "series", ts), as_ss(second, "series", ts)));
}

py::object parallel(const py::object& x, const py::object& y) {
  const double ts = std::max(sample_time(x), sample_time(y));
  if (is_tf_like(x) && is_tf_like(y)) return py::cast(as_tf(x, ts) + as_tf(y, ts));
  return py::cast(b::parallel(as_ss(x, "parallel", ts), as_ss(y, "parallel", ts)));
}

py::object feedback(const py::object& forward, const py::object& back, int sign) {
  if (sign != 1 && sign != -1) throw InputError("feedback: sign must be -1 (negative feedback) or +1");
  const double ts = std::max(sample_time(forward), sample_time(back));
  if (is_tf_like(forward) && is_tf_like(back)) return py::cast(b::feedback(as_tf(forward, ts), as_tf(back, ts), sign));
  const StateSpace f = as_ss(forward, "feedback", ts);
  // A number around a square MIMO model is that gain on every channel (python-control's sys2=1).
  if (is_number(back) && f.num_inputs() == f.num_outputs() && f.num_inputs() > 1)
    return py::cast(b::feedback(f, StateSpace::gain(back.cast<double>() * b::Matrix::Identity(f.num_inputs(), f.num_inputs()), ts), sign));
  return py::cast(b::feedback(f, as_ss(back, "feedback", ts), sign));
}

py::object c2d(const py::object& sys, double ts, const std::string& method, double prewarp) {
  const b::C2dMethod m = b::parse_c2d_method(method);
  if (py::isinstance<StateSpace>(sys)) return py::cast(b::c2d(sys.cast<const StateSpace&>(), ts, m, prewarp));
  if (py::isinstance<TransferFunction>(sys)) return py::cast(b::c2d(sys.cast<const TransferFunction&>(), ts, m, prewarp));
  throw py::type_error("c2d: expected a TransferFunction or a StateSpace");
}

py::object d2c(const py::object& sys, const std::string& method, double prewarp) {
  const b::C2dMethod m = b::parse_c2d_method(method);
  if (py::isinstance<StateSpace>(sys)) return py::cast(b::d2c(sys.cast<const StateSpace&>(), m, prewarp));
  if (py::isinstance<TransferFunction>(sys)) return py::cast(b::d2c(sys.cast<const TransferFunction&>(), m, prewarp));
  throw py::type_error("d2c: expected a TransferFunction or a StateSpace");
}

// A binary operator of a TransferFunction with another one or a number (at its sample
// time); anything else is NotImplemented, so that Python asks the other operand (a
// StateSpace does the interconnection in state space).
template <typename F>
auto tf_operator(F f) {
  return [f](const TransferFunction& g, const py::object& h) -> py::object {
    if (!is_tf_like(h)) return py::reinterpret_borrow<py::object>(Py_NotImplemented);
    return py::cast(f(g, as_tf(h, g.ts())));
  };
}

void bind_transfer_function(py::module_& m) {
  py::class_<TransferFunction> c(m, "TransferFunction", R"doc(
A SISO transfer function num/den: continuous in s (ts == 0) or discrete in z (ts > 0).

TransferFunction(num, den, ts=0.0) takes coefficient lists, highest power first; the
denominator is made monic. dmbd.tf("1/(s+1)") parses an expression. Operators: g * h
(series), g + h, g - h (parallel), g / h, -g, g ** n, also with numbers. Immutable.
)doc");
  c.def(py::init([](const py::object& num, const py::object& den, double ts) {
          return TransferFunction::from_descending(to_vector(num, "num"), to_vector(den, "den"), ts);
        }),
        "num"_a, "den"_a, "ts"_a = 0.0)
      .def_property_readonly("num", [](const TransferFunction& g) { return to_array(g.num().descending()); },
                             "Numerator coefficients, highest power first (NumPy array).")
      .def_property_readonly("den", [](const TransferFunction& g) { return to_array(g.den().descending()); },
                             "Denominator coefficients, highest power first, monic (NumPy array).")
      .def_property_readonly("ts", &TransferFunction::ts, "Sample time in seconds (0: continuous).")
      .def_property_readonly("is_discrete", &TransferFunction::is_discrete)
      .def_property_readonly("order", &TransferFunction::order, "Degree of the denominator.")
      .def_property_readonly("relative_degree", &TransferFunction::relative_degree)
      .def_property_readonly("is_proper", &TransferFunction::is_proper)
      .def_property_readonly("is_strictly_proper", &TransferFunction::is_strictly_proper)
      .def("poles", [](const TransferFunction& g) { return to_array(g.poles()); }, "Roots of the denominator (complex array).")
      .def("zeros", [](const TransferFunction& g) { return to_array(g.zeros()); }, "Roots of the numerator (complex array).")
      .def("dc_gain", [](const TransferFunction& g) { return optional_float(g.dc_gain()); },
           "Value at s = 0 (z = 1); None when infinite.")
      .def("is_stable", &TransferFunction::is_stable, "Every pole with Re s < 0 (|z| < 1).")
      .def("minreal", &TransferFunction::minreal, "tol"_a = 1e-7,
           "Pole/zero pairs closer than tol relative to (1 + |root|) cancelled.")
      .def("__call__", [](const TransferFunction& g, const py::object& x) { return map_complex(x, [&g](b::Complex v) { return g.evaluate(v); }); },
           "x"_a, "The value at a point (or an array of points) of the s- or z-plane.")
      .def("__mul__", tf_operator([](const TransferFunction& g, const TransferFunction& h) { return g * h; }), py::is_operator())
      .def("__rmul__", tf_operator([](const TransferFunction& g, const TransferFunction& h) { return h * g; }), py::is_operator())
      .def("__add__", tf_operator([](const TransferFunction& g, const TransferFunction& h) { return g + h; }), py::is_operator())
      .def("__radd__", tf_operator([](const TransferFunction& g, const TransferFunction& h) { return h + g; }), py::is_operator())
      .def("__sub__", tf_operator([](const TransferFunction& g, const TransferFunction& h) { return g - h; }), py::is_operator())
      .def("__rsub__", tf_operator([](const TransferFunction& g, const TransferFunction& h) { return h - g; }), py::is_operator())
      .def("__truediv__", tf_operator([](const TransferFunction& g, const TransferFunction& h) { return g / h; }), py::is_operator())
      .def("__rtruediv__", tf_operator([](const TransferFunction& g, const TransferFunction& h) { return h / g; }), py::is_operator())
      .def("__neg__", [](const TransferFunction& g) { return -g; })
      .def("__pow__", [](const TransferFunction& g, int n) { return g.pow(n); }, py::is_operator())
      .def("__repr__", &tf_repr);
}

void bind_state_space(py::module_& m) {
  py::class_<StateSpace> c(m, "StateSpace", R"doc(
A state-space model x' = A x + B u, y = C x + D u (continuous, ts == 0) or
x[k+1] = A x[k] + B u[k] (discrete, ts > 0), any number of inputs and outputs.

StateSpace(A, B, C, D=None, ts=0.0): array-likes; a 1-D B is a column, a 1-D C or D a
row, D=None is zero. sys[i, j] is the SISO model from input j to output i. Operators:
a * b (b then a), a + b, a - b (parallel), -a, also with TransferFunctions and numbers.
Immutable.
)doc");
  c.def(py::init(&make_ss), "A"_a, "B"_a, "C"_a, "D"_a = py::none(), "ts"_a = 0.0)
      .def_static("from_tf", &StateSpace::from_tf, "g"_a, "The balanced realisation of a proper TransferFunction.")
      .def_property_readonly("A", [](const StateSpace& s) { return to_array(s.a()); })
      .def_property_readonly("B", [](const StateSpace& s) { return to_array(s.b()); })
      .def_property_readonly("C", [](const StateSpace& s) { return to_array(s.c()); })
      .def_property_readonly("D", [](const StateSpace& s) { return to_array(s.d()); })
      .def_property_readonly("ts", &StateSpace::ts, "Sample time in seconds (0: continuous).")
      .def_property_readonly("is_discrete", &StateSpace::is_discrete)
      .def_property_readonly("num_states", &StateSpace::num_states)
      .def_property_readonly("num_inputs", &StateSpace::num_inputs)
      .def_property_readonly("num_outputs", &StateSpace::num_outputs)
      .def("poles", [](const StateSpace& s) { return to_array(s.poles()); }, "Eigenvalues of A (complex array).")
      .def("is_stable", &StateSpace::is_stable)
      .def("dc_gain", [](const StateSpace& s) { return to_array(s.dc_gain()); },
           "Steady-state gain (outputs x inputs); InputError with a pole at DC.")
      .def("__call__", [](const StateSpace& s, b::Complex x) { return Eigen::MatrixXcd(s.evaluate(x)); }, "x"_a,
           "C (xI - A)^-1 B + D at one point of the s- or z-plane (outputs x inputs).")
      .def("to_tf", [](const StateSpace& s, int output, int input) { return s.to_tf(output, input); }, "output"_a = 0,
           "input"_a = 0, "The transfer function from one input to one output.")
      .def("minimal", &StateSpace::minimal, "tol"_a = 1e-9, "Uncontrollable, then unobservable states removed.")
      .def("balanced", &StateSpace::balanced, "The same system under a diagonal power-of-two similarity.")
      .def("transformed", [](const StateSpace& s, const py::object& t) { return s.transformed(to_matrix(t, "T", Vector1D::Scalar)); },
           "T"_a, "A' = T^-1 A T, B' = T^-1 B, C' = C T.")
      .def("select", &StateSpace::select, "outputs"_a, "inputs"_a, "The sub-system from some inputs to some outputs.")
      .def("__getitem__",
           [](const StateSpace& s, std::pair<int, int> ij) {
             if (ij.first < 0 || ij.first >= s.num_outputs() || ij.second < 0 || ij.second >= s.num_inputs())
               throw py::index_error("StateSpace[" + std::to_string(ij.first) + ", " + std::to_string(ij.second) +
                                     "]: the model has " + std::to_string(s.num_outputs()) + " outputs and " +
                                     std::to_string(s.num_inputs()) + " inputs");
             return s.select({ij.first}, {ij.second});
           })
      .def("__mul__", [](const StateSpace& s, const py::object& o) { return b::series(as_ss(o, "*", s.ts()), s); }, py::is_operator())
      .def("__rmul__", [](const StateSpace& s, const py::object& o) { return b::series(s, as_ss(o, "*", s.ts())); }, py::is_operator())
      .def("__add__", [](const StateSpace& s, const py::object& o) { return b::parallel(s, as_ss(o, "+", s.ts())); }, py::is_operator())
      .def("__radd__", [](const StateSpace& s, const py::object& o) { return b::parallel(as_ss(o, "+", s.ts()), s); }, py::is_operator())
      .def("__sub__", [](const StateSpace& s, const py::object& o) { return b::parallel(s, negated(as_ss(o, "-", s.ts()))); }, py::is_operator())
      .def("__rsub__", [](const StateSpace& s, const py::object& o) { return b::parallel(as_ss(o, "-", s.ts()), negated(s)); }, py::is_operator())
      .def("__neg__", &negated)
      .def("__repr__", &ss_repr);
}

}  // namespace

void bind_lti(py::module_& m) {
  bind_transfer_function(m);
  bind_state_space(m);

  m.def("tf", &parse_tf, "expression"_a, "ts"_a = 0.0, "params"_a = py::none(), R"doc(
A transfer function from a rational expression in s, or in z with ts > 0, e.g.
tf("1/((s/wc)^2 + sqrt(2)*s/wc + 1)", params={"wc": 377.0}) (the grammar of
`dmbd analyze --tf`, docs/analyze.md). ExpressionError (with its column) on a mistake.)doc");
  m.def("tf", [](const StateSpace& sys, int output, int input) { return sys.to_tf(output, input); }, "sys"_a,
        "output"_a = 0, "input"_a = 0, "The transfer function of one channel of a StateSpace.");
  m.def("tf", [](const TransferFunction& g) { return g; }, "g"_a);
  m.def("tf", [](const py::object& num, const py::object& den, double ts) {
          return TransferFunction::from_descending(to_vector(num, "num"), to_vector(den, "den"), ts);
        },
        "num"_a, "den"_a, "ts"_a = 0.0, "A transfer function from coefficient lists, highest power first.");
  m.def("ss", &StateSpace::from_tf, "g"_a, "The realisation of a proper TransferFunction.");
  m.def("ss", [](const StateSpace& s) { return s; }, "sys"_a);
  m.def("ss", &make_ss, "A"_a, "B"_a, "C"_a, "D"_a = py::none(), "ts"_a = 0.0,
        "A StateSpace from matrices (see StateSpace).");

  m.def("series", &series, "first"_a, "second"_a,
        "u -> first -> second -> y. Two transfer functions (or numbers) give a TransferFunction, otherwise a StateSpace.");
  m.def("parallel", &parallel, "a"_a, "b"_a, "y = a(u) + b(u).");
  m.def("feedback", &feedback, "forward"_a, "back"_a = 1.0, "sign"_a = -1,
        "The closed loop u = r + sign * back(y), y = forward(u); sign = -1 is negative feedback.");
  m.def("append", [](const py::object& x, const py::object& y) {
          const double ts = std::max(sample_time(x), sample_time(y));
          return b::append(as_ss(x, "append", ts), as_ss(y, "append", ts));
        },
        "a"_a, "b"_a, "Block-diagonal stacking: inputs and outputs concatenated (a StateSpace).");
  m.def("c2d", &c2d, "sys"_a, "ts"_a, "method"_a = "tustin", "prewarp_rad_s"_a = 0.0, R"doc(
The discrete equivalent at sample time ts, of the same type: method "zoh", "tustin"
(also "bilinear"; pre-warped at prewarp_rad_s > 0) or "backward-euler" ("euler").)doc");
  m.def("d2c", &d2c, "sys"_a, "method"_a = "tustin", "prewarp_rad_s"_a = 0.0,
        "The continuous system whose c2d (tustin or zoh) is sys.");
}

}  // namespace dmbd::python
