// python-control 0.10's verbs under their names and return conventions (docs/python.md,
// "python-control's verbs"), computed by the project's own algorithms in blocks/:
// margins (margin, stability_margins), time responses with inputs linear between samples
// (forced_response, step_response, impulse_response, initial_response), Nyquist and root
// locus data, poles and zeros, damping, DC gain, LQR (lqr, dlqr), pole placement (place),
// and python-control's calling conventions of series, parallel and feedback.
#include "bindings.hpp"
#include "control_results.hpp"
#include "convert.hpp"
#include "systems.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

#include "dmbd/base/error.hpp"
#include "dmbd/blocks/exact_frequency.hpp"
#include "dmbd/blocks/forced_response.hpp"
#include "dmbd/blocks/nyquist.hpp"
#include "dmbd/blocks/pole_placement.hpp"
#include "dmbd/blocks/riccati.hpp"
#include "dmbd/blocks/root_locus.hpp"
#include "dmbd/blocks/siso.hpp"
#include "dmbd/blocks/stability_margin.hpp"

namespace dmbd::python {

namespace b = dmbd::blocks;
using b::Complex;
using b::Matrix;
using b::StateSpace;
using b::TransferFunction;
using namespace pybind11::literals;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

// Runs f; an InputError gets the verb's name in front.
template <typename F>
auto named(const char* verb, F f) {
  try {
    return f();
  } catch (InputError& e) {
    e.prepend(std::string(verb) + ": ");
    throw;
  }
}

void warn(const std::string& text) {
  if (PyErr_WarnEx(PyExc_UserWarning, text.c_str(), 2) != 0) throw py::error_already_set();
}

// ---- A SISO loop: its transfer, its poles and those of its closed loop ----

bool is_ss(const py::object& sys) { return py::isinstance<StateSpace>(sys); }

const StateSpace& ss_of(const py::object& sys) { return sys.cast<const StateSpace&>(); }

void require_siso(const py::object& sys) {
  if (is_ss(sys) && (ss_of(sys).num_inputs() != 1 || ss_of(sys).num_outputs() != 1))
    throw InputError("needs one input and one output, the model has " + std::to_string(ss_of(sys).num_inputs()) +
                     " inputs and " + std::to_string(ss_of(sys).num_outputs()) + " outputs (take one channel: sys[i, j])");
  if (!is_ss(sys) && !is_tf_like(sys))
    throw py::type_error("expected a TransferFunction or a StateSpace, got " + py::str(py::type::of(sys)).cast<std::string>());
}

b::Siso siso(const py::object& sys) {
  require_siso(sys);
  return is_ss(sys) ? b::Siso::from_state_space(b::SparseStateSpace(ss_of(sys))) : b::Siso::from_tf(as_tf(sys));
}

// The transfer at w rad/s: from the data (Siso::response), else from the zeros and poles.
Complex loop_at(const b::Siso& g, double w) {
  if (const auto r = g.response(w)) return *r;
  return std::exp(g.zpk().log_response(w));
}

// L at a point of the s- (z-) plane.
Complex loop_at_point(const py::object& sys, Complex x) {
  return is_ss(sys) ? ss_of(sys).evaluate(x)(0, 0) : as_tf(sys).evaluate(x);
}

std::vector<Complex> open_loop_poles(const py::object& sys) { return is_ss(sys) ? ss_of(sys).poles() : as_tf(sys).poles(); }

std::vector<Complex> closed_loop_poles(const py::object& sys) {
  const double ts = sample_time(sys);
  if (is_ss(sys)) return b::feedback(ss_of(sys), StateSpace::gain(Matrix::Ones(1, 1), ts)).poles();
  return b::feedback(as_tf(sys), TransferFunction(1.0, ts)).poles();
}

// L as w -> infinity (continuous): D of a realisation, lead num / lead den of a proper TF.
Complex loop_at_infinity(const py::object& sys) {
  if (is_ss(sys)) return ss_of(sys).d()(0, 0);
  const TransferFunction g = as_tf(sys);
  if (!g.is_proper()) return kInf;
  return g.relative_degree() == 0 ? g.num().leading() / g.den().leading() : 0.0;
}

// ---- margins ----

double ratio_of_db(const std::optional<double>& db) { return db ? std::pow(10.0, *db / 20.0) : kInf; }
double or_nan(const std::optional<double>& v) { return v ? *v : kNan; }
double or_inf(const std::optional<double>& v) { return v ? *v : kInf; }

b::StabilityMargin sensitivity(const py::object& sys, const b::Siso& g) {
  std::vector<Complex> features = open_loop_poles(sys);
  for (const Complex& z : g.zpk().all_zeros()) features.push_back(z);
  for (const Complex& p : closed_loop_poles(sys)) features.push_back(p);
  return b::stability_margin([&g](double w) { return loop_at(g, w); }, features, g.ts(), loop_at_infinity(sys));
}

py::tuple stability_margins(const py::object& sys, bool returnall) {
  return named("stability_margins", [&] {
    const b::Siso g = siso(sys);
    const b::Margins m = b::margins(g.zpk(), [&g](double w) { return g.response(w); });
    const b::StabilityMargin s = sensitivity(sys, g);
    if (!returnall)
      return py::make_tuple(ratio_of_db(m.gain_margin_db), or_inf(m.phase_margin_deg), s.margin,
                            or_nan(m.phase_crossover_rad_s), or_nan(m.gain_crossover_rad_s), s.w_rad_s);
    std::vector<double> gm, wpc, pm, wgc, sm, wms;
    for (const b::Crossing& c : m.phase_crossovers) gm.push_back(std::pow(10.0, c.margin / 20.0)), wpc.push_back(c.w_rad_s);
    for (const b::Crossing& c : m.gain_crossovers) pm.push_back(c.margin), wgc.push_back(c.w_rad_s);
    for (const b::Crossing& c : s.minima) sm.push_back(c.margin), wms.push_back(c.w_rad_s);
    return py::make_tuple(to_array(gm), to_array(pm), to_array(sm), to_array(wpc), to_array(wgc), to_array(wms));
  });
}

py::tuple margin(const py::object& sys) {
  return named("margin", [&] {
    const b::Siso g = siso(sys);
    const b::Margins m = b::margins(g.zpk(), [&g](double w) { return g.response(w); });
    return py::make_tuple(ratio_of_db(m.gain_margin_db), or_inf(m.phase_margin_deg), or_nan(m.phase_crossover_rad_s),
                          or_nan(m.gain_crossover_rad_s));
  });
}

// ---- poles, zeros, damping, DC gain ----

py::object zeros_of(const py::object& sys) {
  if (!is_ss(sys)) return to_array(as_tf(sys).zeros());
  const b::Zpk z = siso(sys).zpk();
  return to_array(z.is_zero() ? std::vector<Complex>{} : z.all_zeros());
}

PoleZeroData pole_zero_map(const py::object& sys) {
  return named("pole_zero_map", [&] {
    require_siso(sys);
    return PoleZeroData{to_array(open_loop_poles(sys)), zeros_of(sys), py::none(), py::none(), sample_time(sys)};
  });
}

py::array_t<Complex> complex_array(const b::ComplexMatrix& m) {
  py::array_t<Complex> a({static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
  auto w = a.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) w(i, j) = m(i, j);
  return a;
}

PoleZeroData root_locus_map(const py::object& sys, const py::object& gains_obj) {
  return named("root_locus_map", [&] {
    PoleZeroData d = pole_zero_map(sys);
    const std::vector<double> gains = gains_obj.is_none()
                                          ? b::default_root_locus_gains(is_ss(sys) ? ss_of(sys).to_tf() : as_tf(sys))
                                          : to_vector(gains_obj, "gains");
    d.gains = to_array(gains);
    d.loci = complex_array(is_ss(sys) ? b::root_locus(ss_of(sys), gains) : b::root_locus(as_tf(sys), gains));
    return d;
  });
}

py::tuple damp(const py::object& sys, bool doprint) {
  const std::vector<Complex> p = open_loop_poles(sys);
  const double ts = sample_time(sys);
  std::vector<double> wn, zeta;
  for (const Complex& z : p) {
    const Complex s = ts > 0.0 ? std::log(z) / ts : z;  // python-control: s = log(z)/dt
    wn.push_back(std::abs(s));
    zeta.push_back(-s.real() / std::abs(s));
  }
  if (doprint) {
    py::print("    Eigenvalue (pole)       Damping     Frequency");
    char line[96];
    for (size_t k = 0; k < p.size(); ++k) {
      if (std::abs(p[k].imag()) < 1e-12)
        std::snprintf(line, sizeof line, "           %10.4g    %10.4g    %10.4g", p[k].real(), zeta[k], wn[k]);
      else
        std::snprintf(line, sizeof line, "%10.4g%+10.4gj    %10.4g    %10.4g", p[k].real(), p[k].imag(), zeta[k], wn[k]);
      py::print(line);
    }
  }
  return py::make_tuple(to_array(wn), to_array(zeta), to_array(p));
}

double siso_dcgain(const b::Siso& g) {
  const b::Zpk& z = g.zpk();
  if (z.is_zero() || z.m() > 0) return 0.0;
  return z.m() < 0 ? std::copysign(kInf, z.k()) : z.k();
}

py::object dcgain(const py::object& sys) {
  return named("dcgain", [&]() -> py::object {
    if (!is_ss(sys) || (ss_of(sys).num_inputs() == 1 && ss_of(sys).num_outputs() == 1))
      return py::float_(siso_dcgain(siso(sys)));
    const StateSpace& s = ss_of(sys);
    Matrix g(s.num_outputs(), s.num_inputs());
    for (int i = 0; i < s.num_outputs(); ++i)
      for (int j = 0; j < s.num_inputs(); ++j)
        g(i, j) = siso_dcgain(b::Siso::from_state_space(b::SparseStateSpace(s.select({i}, {j}))));
    return to_array(g);
  });
}

// ---- Nyquist ----

NyquistResponseData nyquist_response(const py::object& sys, const py::object& omega, bool return_contour,
                                     double indent_radius, const std::string& indent_direction, const py::object& omega_num,
                                     bool warn_encirclements) {
  return named("nyquist_response", [&] {
    const b::Siso g = siso(sys);
    const double ts = g.ts();
    std::vector<double> w;
    if (omega.is_none()) {
      const int n = omega_num.is_none() ? 1000 : omega_num.cast<int>();
      w = b::nyquist_frequencies(b::default_frequency_grid(g.zpk(), n), ts);
    } else {
      w = to_vector(omega, "omega");
    }
    const b::Nyquist n = b::nyquist([&sys](Complex x) { return loop_at_point(sys, x); }, open_loop_poles(sys),
                                    closed_loop_poles(sys), w, ts, indent_radius, b::parse_indent(indent_direction),
                                    omega.is_none());
    if (warn_encirclements && std::abs(n.curve_encirclements - n.count) > 0.05)
      warn("nyquist_response: the sampled curve encircles -1 " + std::to_string(n.curve_encirclements) +
           " times, the Nyquist criterion " + std::to_string(n.count) +
           " (count is the criterion's; the frequencies may not start at 0 or reach far enough)");
    return NyquistResponseData{n.count, to_array(n.contour), to_array(n.response), ts, return_contour};
  });
}

// ---- time responses ----

// A number in any form NumPy takes as one (Python or NumPy scalars, 0-d arrays).
bool is_scalar(const py::object& x) {
  return !x.is_none() && !py::isinstance<py::str>(x) && py::module_::import("numpy").attr("ndim")(x).cast<int>() == 0;
}

struct Times {
  std::vector<double> t;
  double dt = 0.0;
};

// python-control's checks of an evenly spaced time vector (np.allclose of the steps).
Times checked_times(std::vector<double> t) {
  if (t.size() < 2) throw InputError("T: expected at least 2 times");
  const double dt = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  for (size_t k = 1; k < t.size(); ++k)
    if (!(std::abs(t[k] - t[k - 1] - dt) <= 1e-8 + 1e-5 * std::abs(dt)))
      throw InputError("T: time values must be equally spaced");
  return {std::move(t), dt};
}

// T as given, or (None, or a final time) a grid to that time: T_num points (default
// 1000) when continuous, every sample when discrete; the final time defaults to
// step_horizon's (docs/python.md).
Times time_grid(const StateSpace& s, const py::object& t_obj, const py::object& t_num) {
  const bool given_array = !t_obj.is_none() && !is_scalar(t_obj);
  if (given_array) return checked_times(to_vector(t_obj, "T"));
  const double t_end = t_obj.is_none() ? b::default_step_horizon(s) : py::float_(t_obj).cast<double>();
  if (!(t_end > 0.0) || !std::isfinite(t_end)) throw InputError("T: expected a positive final time");
  std::vector<double> t;
  if (s.is_discrete()) {
    const int n = static_cast<int>(std::floor(t_end / s.ts() + 1e-9)) + 1;
    for (int k = 0; k < std::max(n, 2); ++k) t.push_back(k * s.ts());
  } else {
    const int n = t_num.is_none() ? 1000 : t_num.cast<int>();
    if (n < 2) throw InputError("T_num: expected at least 2 points");
    for (int k = 0; k < n; ++k) t.push_back(t_end * k / (n - 1));
  }
  return checked_times(t);
}

// X0: a number for every state, or one value per state.
b::Vector initial_state(const py::object& x0, int n) {
  if (is_scalar(x0)) return b::Vector::Constant(n, py::float_(x0).cast<double>());
  const Matrix m = to_matrix(x0, "X0", Vector1D::Column);
  if (m.size() != n || (m.cols() != 1 && m.rows() != 1))
    throw InputError("X0: expected " + std::to_string(n) + " initial states, got an array of shape " +
                     std::to_string(m.rows()) + " x " + std::to_string(m.cols()));
  return Eigen::Map<const b::Vector>(m.data(), n);
}

// U: a number for every input and sample, (samples,) or (1, samples) for one input,
// (inputs, samples) otherwise. Returned samples x inputs.
Matrix input_samples(const py::object& u, int inputs, size_t samples) {
  const Eigen::Index n = static_cast<Eigen::Index>(samples);
  if (is_scalar(u)) return Matrix::Constant(n, inputs, py::float_(u).cast<double>());
  const Matrix m = to_matrix(u, "U", Vector1D::Row);
  if (m.rows() != inputs || m.cols() != n)
    throw InputError("U: expected shape (" + std::to_string(inputs) + ", " + std::to_string(samples) + ")" +
                     (inputs == 1 ? " or (" + std::to_string(samples) + ",)" : "") + ", got (" +
                     std::to_string(m.rows()) + ", " + std::to_string(m.cols()) + ")");
  return m.transpose();
}

py::array_t<double> stacked(const std::vector<Matrix>& traces) {  // traces[k]: rows x samples
  const Eigen::Index r = traces.empty() ? 0 : traces[0].rows(), c = traces.empty() ? 0 : traces[0].cols();
  py::array_t<double> a({static_cast<py::ssize_t>(r), static_cast<py::ssize_t>(traces.size()), static_cast<py::ssize_t>(c)});
  auto w = a.mutable_unchecked<3>();
  for (size_t k = 0; k < traces.size(); ++k)
    for (Eigen::Index i = 0; i < r; ++i)
      for (Eigen::Index j = 0; j < c; ++j) w(i, static_cast<py::ssize_t>(k), j) = traces[k](i, j);
  return a;
}

b::StateTrajectory simulate(const StateSpace& s, const Matrix& u, const Times& t, const b::Vector& x0) {
  return b::forced_response(s, u, t.dt, x0);
}

bool siso_system(const StateSpace& s) { return s.num_inputs() == 1 && s.num_outputs() == 1; }

TimeResponseData forced_response(const py::object& sys, const py::object& t_obj, const py::object& u_obj,
                                 const py::object& x0, const py::object& return_x, const py::object& squeeze) {
  return named("forced_response", [&] {
    const StateSpace s = as_ss(sys, "forced_response");
    Times t;
    if (t_obj.is_none()) {
      if (!s.is_discrete()) throw InputError("T: needed for a continuous system");
      if (is_scalar(u_obj)) throw InputError("T and U: give T, or U as an array");
      const Matrix u = to_matrix(u_obj, "U", Vector1D::Row);
      std::vector<double> tv;
      for (Eigen::Index k = 0; k < u.cols(); ++k) tv.push_back(static_cast<double>(k) * s.ts());
      t = checked_times(tv);
    } else {
      t = checked_times(to_vector(t_obj, "T"));
    }
    const Matrix u = input_samples(u_obj, s.num_inputs(), t.t.size());
    const b::StateTrajectory r = simulate(s, u, t, initial_state(x0, s.num_states()));
    return TimeResponseData{to_array(t.t), to_array(Matrix(r.y.transpose())), to_array(Matrix(r.x.transpose())),
                            to_array(Matrix(u.transpose())), siso_system(s), 0, squeeze,
                            !return_x.is_none() && return_x.cast<bool>(), "Forced response"};
  });
}

// The response to one input at a time (step, impulse): traces of every input, or of one.
TimeResponseData per_input(const StateSpace& s, const Times& t, const py::object& input, const py::object& output,
                           const std::function<std::pair<Matrix, b::Vector>(int)>& drive, bool return_x,
                           const py::object& squeeze, const std::string& title) {
  const int in = input.is_none() ? -1 : input.cast<int>(), out = output.is_none() ? -1 : output.cast<int>();
  if (in >= s.num_inputs() || (!input.is_none() && in < 0))
    throw InputError("input " + std::to_string(in) + " does not exist (the system has " + std::to_string(s.num_inputs()) + ")");
  if (out >= s.num_outputs() || (!output.is_none() && out < 0))
    throw InputError("output " + std::to_string(out) + " does not exist (the system has " + std::to_string(s.num_outputs()) + ")");
  std::vector<Matrix> ys, xs, us;
  for (int i = 0; i < s.num_inputs(); ++i) {
    if (in >= 0 && i != in) continue;
    const auto [u, x0] = drive(i);
    const b::StateTrajectory r = simulate(s, u, t, x0);
    ys.push_back(out >= 0 ? Matrix(r.y.col(out).transpose()) : Matrix(r.y.transpose()));
    xs.push_back(r.x.transpose());
    us.push_back(in >= 0 ? Matrix(u.col(in).transpose()) : Matrix(u.transpose()));
  }
  const bool issiso = siso_system(s) || (in >= 0 && out >= 0);
  return TimeResponseData{to_array(t.t), stacked(ys), stacked(xs), stacked(us), issiso, static_cast<int>(ys.size()),
                          squeeze, return_x, title};
}

TimeResponseData step_response(const py::object& sys, const py::object& t_obj, const py::object& x0, const py::object& input,
                               const py::object& output, const py::object& t_num, bool return_x, const py::object& squeeze) {
  return named("step_response", [&] {
    const StateSpace s = as_ss(sys, "step_response");
    const Times t = time_grid(s, t_obj, t_num);
    const b::Vector x = initial_state(x0, s.num_states());
    return per_input(s, t, input, output, [&](int i) {
      Matrix u = Matrix::Zero(static_cast<Eigen::Index>(t.t.size()), s.num_inputs());
      u.col(i).setOnes();
      return std::make_pair(u, x);
    }, return_x, squeeze, "Step response");
  });
}

TimeResponseData impulse_response(const py::object& sys, const py::object& t_obj, const py::object& input,
                                  const py::object& output, const py::object& t_num, bool return_x, const py::object& squeeze) {
  return named("impulse_response", [&] {
    const StateSpace s = as_ss(sys, "impulse_response");
    const Times t = time_grid(s, t_obj, t_num);
    if (!s.is_discrete() && s.d().cwiseAbs().maxCoeff() > 0.0)
      warn("impulse_response: the system has direct feedthrough (D != 0): the impulse D delta(t) is left out of the output");
    return per_input(s, t, input, output, [&](int i) {
      Matrix u = Matrix::Zero(static_cast<Eigen::Index>(t.t.size()), s.num_inputs());
      if (s.is_discrete()) {
        u(0, i) = 1.0 / s.ts();  // unit area, as python-control
        return std::make_pair(u, b::Vector(b::Vector::Zero(s.num_states())));
      }
      return std::make_pair(u, b::Vector(s.b().col(i)));  // x(0+) = B e_i
    }, return_x, squeeze, "Impulse response");
  });
}

TimeResponseData initial_response(const py::object& sys, const py::object& t_obj, const py::object& x0,
                                  const py::object& output, const py::object& t_num, bool return_x, const py::object& squeeze) {
  return named("initial_response", [&] {
    const StateSpace s = as_ss(sys, "initial_response");
    const Times t = time_grid(s, t_obj, t_num);
    const int out = output.is_none() ? -1 : output.cast<int>();
    if (out >= s.num_outputs() || (!output.is_none() && out < 0))
      throw InputError("output " + std::to_string(out) + " does not exist (the system has " + std::to_string(s.num_outputs()) + ")");
    const b::StateTrajectory r =
        simulate(s, Matrix::Zero(static_cast<Eigen::Index>(t.t.size()), s.num_inputs()), t, initial_state(x0, s.num_states()));
    const Matrix y = out >= 0 ? Matrix(r.y.col(out).transpose()) : Matrix(r.y.transpose());
    return TimeResponseData{to_array(t.t), to_array(y), to_array(Matrix(r.x.transpose())), py::none(),
                            s.num_outputs() == 1 || out >= 0, 0, squeeze, return_x, "Initial response"};
  });
}

// ---- state feedback ----

py::tuple feedback_gains(const b::LinearQuadratic& l) { return py::make_tuple(to_array(l.k), to_array(l.s), to_array(l.poles)); }

Matrix cross(const py::object& n) { return n.is_none() ? Matrix() : to_matrix(n, "N", Vector1D::Column); }
Matrix square(const py::object& x, const char* what) { return to_matrix(x, what, Vector1D::Scalar); }

py::tuple lqr_matrices(const py::object& a, const py::object& bm, const py::object& q, const py::object& r, const py::object& n,
                       bool discrete) {
  return named(discrete ? "dlqr" : "lqr", [&] {
    const Matrix A = square(a, "A"), B = to_matrix(bm, "B", Vector1D::Column);
    return feedback_gains(discrete ? b::dlqr(A, B, square(q, "Q"), square(r, "R"), cross(n))
                                   : b::lqr(A, B, square(q, "Q"), square(r, "R"), cross(n)));
  });
}

py::tuple lqr_system(const StateSpace& s, const py::object& q, const py::object& r, const py::object& n, bool discrete_verb) {
  if (discrete_verb && !s.is_discrete())
    throw InputError("dlqr: the system is continuous (ts = 0): expected a discrete one (or lqr)");
  // lqr of a discrete system is dlqr (python-control).
  return lqr_matrices(py::cast(s.a()), py::cast(s.b()), q, r, n, s.is_discrete());
}

py::array_t<double> place(const py::object& a, const py::object& bm, const py::object& p) {
  return named("place", [&] {
    auto poles = py::array_t<Complex, py::array::c_style | py::array::forcecast>::ensure(
        py::module_::import("numpy").attr("ravel")(p));
    if (!poles) throw py::type_error("place: p: expected an array of poles");
    const std::vector<Complex> pv(poles.data(), poles.data() + poles.size());
    return to_array(b::place(square(a, "A"), to_matrix(bm, "B", Vector1D::Column), pv).k);
  });
}

// ---- interconnection with python-control's argument conventions ----

py::object fold(const char* verb, const py::args& systems) {
  if (systems.empty()) throw py::type_error(std::string(verb) + ": expected at least one system");
  const py::object pairwise = py::module_::import("dmbd._dmbd").attr(verb);
  py::object acc = systems[0];
  for (size_t k = 1; k < systems.size(); ++k) acc = pairwise(acc, systems[k]);
  return acc;
}

void bind_time_responses(py::module_& m) {
  m.def("forced_response", &forced_response, "sys"_a, "T"_a = py::none(), "U"_a = 0.0, "X0"_a = 0.0,
        "return_x"_a = py::none(), "squeeze"_a = py::none(), R"doc(
The response to the inputs U at the times T (python-control's forced_response): U linear
between samples (as scipy.signal.lsim), the step over each interval exact (matrix
exponential); a discrete system needs T spaced by its sample time (T may be None: len(U)
samples). U: a number, (len(T),) or (1, len(T)) for one input, (inputs, len(T)); X0: a
number or one value per state. A TimeResponseData; t, y = forced_response(...).)doc");
  m.def("step_response", &step_response, "sys"_a, "T"_a = py::none(), "X0"_a = 0.0, "input"_a = py::none(),
        "output"_a = py::none(), "T_num"_a = py::none(), "return_x"_a = false, "squeeze"_a = py::none(), R"doc(
Unit-step responses from each input (or `input`) to every output (or `output`) as a
TimeResponseData (outputs x inputs x samples, 1-D for SISO). T: times, a final time, or
None (step_horizon; T_num points, default 1000, when continuous).)doc");
  m.def("impulse_response", &impulse_response, "sys"_a, "T"_a = py::none(), "input"_a = py::none(), "output"_a = py::none(),
        "T_num"_a = py::none(), "return_x"_a = false, "squeeze"_a = py::none(), R"doc(
Unit-impulse responses as step_response: continuous, C e^{At} B (the D delta left out,
with a warning); discrete, the response to a pulse of area 1 (1/dt at k = 0), as
python-control.)doc");
  m.def("initial_response", &initial_response, "sys"_a, "T"_a = py::none(), "X0"_a = 0.0, "output"_a = py::none(),
        "T_num"_a = py::none(), "return_x"_a = false, "squeeze"_a = py::none(),
        "The free response from the initial state X0 as a TimeResponseData (inputs None).");
}

void bind_loop_verbs(py::module_& m) {
  m.def("margin", &margin, "sys"_a, R"doc(
(gm, pm, wcg, wcp) of a SISO loop transfer in negative feedback, as python-control's
margin: gain margin as a ratio (inf when the phase never crosses -180 deg), phase
margin in degrees (inf when |L| never crosses 1), the phase- and gain-crossover
frequencies in rad/s (nan where there is none). The margins of smallest magnitude.)doc");
  m.def("stability_margins", &stability_margins, "sys"_a, "returnall"_a = false, R"doc(
(gm, pm, sm, wpc, wgc, wms) as python-control's stability_margins: margin's four and the
stability margin sm = min |1 + L(jw)| (1 / peak sensitivity) at wms rad/s (inf when the
infimum is approached as w -> inf). returnall=True: arrays of every crossing and every
local minimum.)doc");
  m.def("dcgain", &dcgain, "sys"_a,
        "The DC gain as python-control's dcgain: a float (+-inf with a pole at DC), a matrix for several channels.");
  m.def("damp", &damp, "sys"_a, "doprint"_a = true, R"doc(
(wn, zeta, poles) as python-control's damp: natural frequencies (rad/s), damping ratios
and poles (a discrete pole z through s = log(z)/dt); doprint prints python-control's table.)doc");
  m.def("pole_zero_map", &pole_zero_map, "sys"_a, "A PoleZeroData of the poles and zeros (poles, zeros = pole_zero_map(sys)).");
  m.def("root_locus_map", &root_locus_map, "sys"_a, "gains"_a = py::none(), R"doc(
A PoleZeroData whose loci[i, j] is branch j of the closed-loop poles of gains[i] * sys in
negative feedback (the roots of den + k num; eigenvalues of A - kB(1 + kD)^-1 C for a
StateSpace), branches matched from gain to gain. gains default: 0 and 200 log-spaced.)doc");
  m.def("nyquist_response", &nyquist_response, "sys"_a, "omega"_a = py::none(), "return_contour"_a = false,
        "indent_radius"_a = 1e-4, "indent_direction"_a = "right", "omega_num"_a = py::none(), "warn_encirclements"_a = true,
        R"doc(
A NyquistResponseData: the loop along the Nyquist contour at omega (rad/s; default: 0 up
to two decades beyond the poles and zeros, and points around poles on the axis) indented
around poles on or near the axis, and count, the clockwise encirclements of -1 from the
Nyquist criterion (closed-loop minus open-loop unstable poles; a UserWarning when the
sampled curve's winding disagrees).)doc");
}

void bind_state_feedback(py::module_& m) {
  m.def("lqr", [](const StateSpace& s, const py::object& q, const py::object& r, const py::object& n) {
    return lqr_system(s, q, r, n, false);
  }, "sys"_a, "Q"_a, "R"_a, "N"_a = py::none());
  m.def("lqr", [](const py::object& a, const py::object& bm, const py::object& q, const py::object& r, const py::object& n) {
    return lqr_matrices(a, bm, q, r, n, false);
  }, "A"_a, "B"_a, "Q"_a, "R"_a, "N"_a = py::none(), R"doc(
(K, S, E) = lqr(A, B, Q, R[, N]) or lqr(sys, Q, R[, N]) as python-control: u = -K x
minimising the integral of x'Qx + u'Ru + 2x'Nu; S the stabilising solution of the
continuous Riccati equation (Hamiltonian Schur method), E the eigenvalues of A - BK. A
discrete sys is solved by dlqr.)doc");
  m.def("dlqr", [](const StateSpace& s, const py::object& q, const py::object& r, const py::object& n) {
    return lqr_system(s, q, r, n, true);
  }, "sys"_a, "Q"_a, "R"_a, "N"_a = py::none());
  m.def("dlqr", [](const py::object& a, const py::object& bm, const py::object& q, const py::object& r, const py::object& n) {
    return lqr_matrices(a, bm, q, r, n, true);
  }, "A"_a, "B"_a, "Q"_a, "R"_a, "N"_a = py::none(), R"doc(
(K, S, E) = dlqr(A, B, Q, R[, N]) or dlqr(sys, Q, R[, N]) as python-control: the discrete
regulator minimising the sum of x'Qx + u'Ru + 2x'Nu, S from the discrete Riccati
equation, E the eigenvalues of A - BK.)doc");
  m.def("place", &place, "A"_a, "B"_a, "p"_a, R"doc(
K such that A - BK has the eigenvalues p (python-control's place). One input: the unique
gain by orthogonal deflation (repeated poles allowed); several inputs: Kautsky-Nichols-
Van Dooren's robust eigenvector method (a pole at most rank B times).)doc");
}

}  // namespace

void bind_control_verbs(py::module_& m) {
  bind_control_results(m);
  bind_loop_verbs(m);
  bind_time_responses(m);
  bind_state_feedback(m);
  // python-control's conventions beside the existing ones (lti.cpp): any number of systems,
  // and feedback's keywords sys1, sys2.
  m.def("series", [](const py::args& s) { return fold("series", s); },
        "series(sys1, sys2, ..., sysn): u -> sys1 -> sys2 -> ... -> sysn -> y (python-control).");
  m.def("parallel", [](const py::args& s) { return fold("parallel", s); },
        "parallel(sys1, sys2, ..., sysn): the sum of their outputs (python-control).");
  m.def("feedback", [](const py::object& sys1, const py::object& sys2, int sign) {
    return py::module_::import("dmbd._dmbd").attr("feedback")(sys1, sys2, sign);
  }, "sys1"_a, "sys2"_a = 1.0, "sign"_a = -1, "feedback(sys1, sys2=1, sign=-1): python-control's keywords.");
}

}  // namespace dmbd::python
