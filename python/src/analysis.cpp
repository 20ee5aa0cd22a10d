// Analysis of a system (docs/python.md, "Analysis"): poles, zeros, frequency and step
// responses, margins. A SISO transfer is analysed as `dmbd analyze` does (blocks::Siso:
// zeros, poles and gain; the phase unwrapped from DC; margins; the step response exact at
// the samples), except that a transfer function's frequency response is evaluated from
// its coefficients (siso_bode below).
#include "bindings.hpp"
#include "convert.hpp"
#include "systems.hpp"

#include <cmath>

#include "dmbd/base/error.hpp"
#include "dmbd/blocks/exact_frequency.hpp"
#include "dmbd/blocks/certified_stability.hpp"
#include "dmbd/blocks/frequency.hpp"
#include "dmbd/blocks/siso.hpp"
#include "dmbd/blocks/zpk.hpp"

namespace dmbd::python {

namespace b = dmbd::blocks;
using b::StateSpace;
using b::TransferFunction;
using namespace pybind11::literals;

namespace {

// The SISO transfer of a system argument; InputError for a StateSpace with more than
// one input or output.
b::Siso siso_of(const py::object& sys, const std::string& what) {
  if (py::isinstance<StateSpace>(sys)) {
    const StateSpace& s = sys.cast<const StateSpace&>();
    if (s.num_inputs() != 1 || s.num_outputs() != 1)
      throw InputError(what + ": needs one input and one output, the model has " + std::to_string(s.num_inputs()) +
                       " inputs and " + std::to_string(s.num_outputs()) + " outputs (take one channel: sys[i, j])");
    return b::Siso::from_state_space(b::SparseStateSpace(s));
  }
  if (is_tf_like(sys)) return b::Siso::from_tf(as_tf(sys));
  throw py::type_error(what + ": expected a TransferFunction or a StateSpace, got " + py::str(py::type::of(sys)).cast<std::string>());
}

bool is_mimo(const py::object& sys) {
  if (!py::isinstance<StateSpace>(sys)) return false;
  const StateSpace& s = sys.cast<const StateSpace&>();
  return s.num_inputs() != 1 || s.num_outputs() != 1;
}

std::vector<b::Complex> poles(const py::object& sys) {
  if (py::isinstance<StateSpace>(sys)) return sys.cast<const StateSpace&>().poles();
  return as_tf(sys).poles();
}

bool discrete(const py::object& sys) { return sample_time(sys) > 0.0; }

std::string stability(const py::object& sys) {
  if (is_tf_like(sys)) return b::to_string(b::certified_stability(as_tf(sys)));
  return b::to_string(b::stability(poles(sys), discrete(sys)));
}

py::object zeros(const py::object& sys) {
  if (is_tf_like(sys)) return to_array(as_tf(sys).zeros());
  const b::Siso g = siso_of(sys, "zeros");
  const b::Zpk& z = g.zpk();
  return to_array(z.is_zero() ? std::vector<b::Complex>{} : z.all_zeros());
}

// The Bode data of a SISO system: a transfer function from its coefficients (direct
// evaluation: exact to rounding, where the roots of a polynomial with a repeated root,
// such as the double zero at z = -1 of a Tustin discretisation, are not), a state-space
// model from the zeros, poles and gain of its transfer. Both phases are unwrapped from DC
// factor by factor (frequency.hpp).
b::Bode siso_bode(const py::object& sys, const std::vector<double>& w, const std::string& what) {
  if (is_tf_like(sys)) return b::bode(as_tf(sys), w);
  return b::bode(siso_of(sys, what).zpk(), w);
}

py::object freqresp(const py::object& sys, const py::object& w_obj) {
  const std::vector<double> w = to_vector(w_obj, "w");
  if (!is_mimo(sys)) return to_array(siso_bode(sys, w, "freqresp").response);
  const StateSpace& s = sys.cast<const StateSpace&>();
  const std::vector<Eigen::MatrixXcd> r = b::frequency_response(s, w);
  py::array_t<std::complex<double>> out(
      {static_cast<py::ssize_t>(w.size()), static_cast<py::ssize_t>(s.num_outputs()), static_cast<py::ssize_t>(s.num_inputs())});
  auto o = out.mutable_unchecked<3>();
  for (size_t k = 0; k < w.size(); ++k)
    for (int i = 0; i < s.num_outputs(); ++i)
      for (int j = 0; j < s.num_inputs(); ++j) o(static_cast<py::ssize_t>(k), i, j) = r[k](i, j);
  return std::move(out);
}

py::tuple bode(const py::object& sys, const py::object& w_obj) {
  const b::Bode bd = siso_bode(sys, to_vector(w_obj, "w"), "bode");
  return py::make_tuple(to_array(bd.mag_db), to_array(bd.phase_deg));
}

// The samples `t` as Siso::step takes them (t_end, n): equally spaced from 0, at the
// sample time of a discrete system.
std::pair<double, int> step_grid(const std::vector<double>& t, double ts) {
  const char* expected = ts > 0.0 ? "the multiples k ts of the sample time from 0 (numpy.arange(n) * ts)"
                                  : "equally spaced from 0 (numpy.linspace(0, t_end, n))";
  if (t.size() < 2) throw InputError(std::string("step: t needs at least 2 samples, ") + expected);
  const double t_end = t.back();
  if (!(t_end > 0.0) || !std::isfinite(t_end)) throw InputError("step: t must end at a positive time");
  const double dt = ts > 0.0 ? ts : t_end / static_cast<double>(t.size() - 1);
  for (size_t k = 0; k < t.size(); ++k)
    if (!(std::abs(t[k] - static_cast<double>(k) * dt) <= 1e-9 * t_end))
      throw InputError("step: t[" + std::to_string(k) + "] = " + std::to_string(t[k]) + ": expected t " + expected);
  return {t_end, static_cast<int>(t.size())};
}

py::array_t<double> step(const py::object& sys, const py::object& t_obj) {
  const b::Siso g = siso_of(sys, "step");
  const auto [t_end, n] = step_grid(to_vector(t_obj, "t"), g.ts());
  const b::Siso::Step st = g.step(t_end, n);
  std::vector<double> y(static_cast<size_t>(st.response.y.rows()));
  for (size_t k = 0; k < y.size(); ++k) y[k] = st.response.y(static_cast<Eigen::Index>(k), 0);
  return to_array(y);
}

py::dict step_info(const py::object& sys, const py::object& t_end_obj, int n) {
  const b::Siso g = siso_of(sys, "step_info");
  const double t_end = t_end_obj.is_none() ? g.default_step_horizon() : t_end_obj.cast<double>();
  const b::StepInfo i = g.step(t_end, n).info;
  return py::dict("rise_time_s"_a = optional_float(i.rise_time_s), "settling_time_s"_a = optional_float(i.settling_time_s),
                  "overshoot_pct"_a = optional_float(i.overshoot_pct), "final_value"_a = optional_float(i.final_value),
                  "peak"_a = optional_float(i.peak), "peak_time_s"_a = optional_float(i.peak_time_s));
}

py::dict margins(const py::object& sys) {
  // Found on the zeros and poles, refined on the transfer's own response (a repeated
  // pole's roots are scattered by rounding; exact_frequency.hpp).
  const b::Siso g = siso_of(sys, "margins");
  const b::Margins m = b::margins(g.zpk(), [&g](double w) { return g.response(w); });
  py::list gc, pc;
  for (const b::Crossing& c : m.gain_crossovers) gc.append(py::dict("w_rad_s"_a = c.w_rad_s, "phase_margin_deg"_a = c.margin));
  for (const b::Crossing& c : m.phase_crossovers) pc.append(py::dict("w_rad_s"_a = c.w_rad_s, "gain_margin_db"_a = c.margin));
  return py::dict("gain_margin_db"_a = optional_float(m.gain_margin_db),
                  "phase_crossover_rad_s"_a = optional_float(m.phase_crossover_rad_s),
                  "phase_margin_deg"_a = optional_float(m.phase_margin_deg),
                  "gain_crossover_rad_s"_a = optional_float(m.gain_crossover_rad_s), "gain_crossovers"_a = gc,
                  "phase_crossovers"_a = pc);
}

py::object dc_gain(const py::object& sys) {
  if (is_mimo(sys)) return to_array(sys.cast<const StateSpace&>().dc_gain());
  return optional_float(siso_of(sys, "dc_gain").zpk().dc_gain());
}

}  // namespace

void bind_analysis(py::module_& m) {
  m.def("poles", [](const py::object& sys) { return to_array(poles(sys)); }, "sys"_a, R"doc(
Every pole (complex array, sorted by real then imaginary part): the roots of a
TransferFunction's denominator, the eigenvalues of a StateSpace's A.)doc");
  m.def("zeros", &zeros, "sys"_a, R"doc(
The zeros (complex array): the roots of a TransferFunction's numerator; of a SISO
StateSpace, the zeros of its transfer as `dmbd analyze` finds them (modes it does not
see left out).)doc");
  m.def("stability", &stability, "sys"_a, R"doc(
"stable" (every pole with Re s < 0, |z| < 1), "marginal" (none outside, those on the
boundary simple) or "unstable", over every pole (as poles()). For a TransferFunction the
verdict is certified on its coefficients (and factors) exactly as given: "undecided"
when a pole's proven enclosure straddles the boundary (docs/analyze.md).)doc");
  m.def("freqresp", &freqresp, "sys"_a, "w"_a, R"doc(
The frequency response at w (rad/s): a complex array; for a StateSpace with several
inputs or outputs, an array of shape (len(w), outputs, inputs).)doc");
  m.def("bode", &bode, "sys"_a, "w"_a, R"doc(
(mag_db, phase_deg) of a SISO system at w (rad/s), NumPy arrays. The phase is unwrapped
from DC factor by factor (docs/analyze.md), not from the first frequency.)doc");
  m.def("frequency_grid", [](const py::object& sys, int n) { return to_array(b::default_frequency_grid(siso_of(sys, "frequency_grid").zpk(), n)); },
        "sys"_a, "n"_a = 400, "n log-spaced frequencies (rad/s) two decades beyond the poles and zeros (to Nyquist when discrete).");
  m.def("step", &step, "sys"_a, "t"_a, R"doc(
The unit-step response y (NumPy array) of a SISO system from rest at the times t, which
must be equally spaced from 0 (numpy.linspace(0, t_end, n)); for a discrete system the
multiples k ts of its sample time. Exact at the samples (matrix exponential).)doc");
  m.def("step_info", &step_info, "sys"_a, "t_end"_a = py::none(), "n"_a = 1000, R"doc(
The step figures of a stable SISO system as a dict: rise_time_s (10-90 %),
settling_time_s (2 %), overshoot_pct, final_value, peak, peak_time_s (None when
unstable), refined between samples. t_end defaults to step_horizon(sys).)doc");
  m.def("step_horizon", [](const py::object& sys) { return siso_of(sys, "step_horizon").default_step_horizon(); }, "sys"_a,
        "A reasonable final time (s) for a step response, from the poles.");
  m.def("margins", &margins, "sys"_a, R"doc(
Gain and phase margins of a loop transfer (negative feedback), as a dict:
gain_margin_db, phase_crossover_rad_s, phase_margin_deg, gain_crossover_rad_s (None
where there is no crossover; the margin of smallest magnitude, as MATLAB's margin),
and every crossing: gain_crossovers [{w_rad_s, phase_margin_deg}], phase_crossovers
[{w_rad_s, gain_margin_db}].)doc");
  m.def("bandwidth", [](const py::object& sys, double drop_db) {
          const b::Siso g = siso_of(sys, "bandwidth");
          return optional_float(b::bandwidth(g.zpk(), [&g](double w) { return g.response(w); }, drop_db));
        },
        "sys"_a, "drop_db"_a = -3.0, "First frequency (rad/s) where |G| falls drop_db below |G(0)|; None if never.");
  m.def("dc_gain", &dc_gain, "sys"_a,
        "The steady-state gain: a float (None when infinite) for a SISO system, a matrix for a StateSpace with several channels.");
}

}  // namespace dmbd::python
