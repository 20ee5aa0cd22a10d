#include "dmbd/blocks/time_response.hpp"

#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/schur_exponential.hpp"
#include "golden_section.hpp"

namespace dmbd::blocks {

namespace {

struct Zoh {
  Matrix phi, gamma;
};

// [A B; 0 0]: the state [x; u] of a system whose input is held constant (Van Loan).
Matrix augmented(const StateSpace& sys) {
  const int n = sys.num_states(), m = sys.num_inputs();
  Matrix big = Matrix::Zero(n + m, n + m);
  big.topLeftCorner(n, n) = sys.a();
  big.topRightCorner(n, m) = sys.b();
  return big;
}

// ZOH over dt (SchurExponential: to rounding for any dt and stiffness).
Zoh zoh(const StateSpace& sys, double dt) {
  const int n = sys.num_states(), m = sys.num_inputs();
  const Matrix e = SchurExponential(augmented(sys)).exp(dt);
  return {e.topLeftCorner(n, n), e.topRightCorner(n, m)};
}

// The response C x + D u at k dt from the states x (the first rows of the columns of z)
// and the constant input u.
TimeResponse outputs(const StateSpace& sys, const Matrix& z, double dt, const Vector& u) {
  TimeResponse r;
  const int n = sys.num_states();
  r.t.resize(static_cast<size_t>(z.cols()));
  for (Eigen::Index k = 0; k < z.cols(); ++k) r.t[static_cast<size_t>(k)] = static_cast<double>(k) * dt;
  r.y = (sys.c() * z.topRows(n)).transpose();
  r.y.rowwise() += (sys.d() * u).transpose();
  return r;
}

void check_channel(const StateSpace& sys, int in) {
  if (in < 0 || in >= sys.num_inputs())
    throw InputError("input " + std::to_string(in) + " does not exist (the system has " +
                     std::to_string(sys.num_inputs()) + ")");
}

void check_horizon(double t_end, int n) {
  if (!(t_end > 0.0) || !std::isfinite(t_end)) throw InputError("the final time must be a positive number of seconds");
  if (n < 2) throw InputError("a time response needs at least 2 samples");
}

// Simulate x[k+1] = phi x[k] + gamma u[k], y[k] = C x[k] + D u[k].
TimeResponse run(const StateSpace& sys, const Matrix& phi, const Matrix& gamma, const Matrix& u, double dt,
                 const Vector& x0) {
  const Eigen::Index samples = u.rows();
  TimeResponse r;
  r.t.resize(static_cast<size_t>(samples));
  r.y.resize(samples, sys.num_outputs());
  Vector x = x0.size() ? x0 : Vector::Zero(sys.num_states());
  // Preallocated work vectors: no heap allocation inside the loop.
  Vector xn(x.size()), uk(u.cols()), yk(sys.num_outputs());
  for (Eigen::Index k = 0; k < samples; ++k) {
    r.t[static_cast<size_t>(k)] = static_cast<double>(k) * dt;
    uk = u.row(k).transpose();
    yk.noalias() = sys.c() * x;
    yk.noalias() += sys.d() * uk;
    r.y.row(k) = yk.transpose();
    xn.noalias() = phi * x;
    xn.noalias() += gamma * uk;
    x.swap(xn);
  }
  return r;
}

// Root of f in [a, b] where f(a) and f(b) differ in sign, by bisection to rounding level.
double bisect(const std::function<double(double)>& f, double a, double b) {
  double fa = f(a);
  for (int it = 0; it < 200 && b - a > 4.0 * std::numeric_limits<double>::epsilon() * std::abs(b); ++it) {
    const double m = 0.5 * (a + b);
    const double fm = f(m);
    if ((fm > 0.0) == (fa > 0.0)) {
      a = m;
      fa = fm;
    } else {
      b = m;
    }
  }
  return 0.5 * (a + b);
}

// Maximum of a locally unimodal f on [a, b] (golden section), the final bracket's middle.
double golden_max(const std::function<double(double)>& f, double a, double b) {
  const GoldenBracket g = golden_section([&](double x) { return -f(x); }, a, b, 1e-15, 200);
  return 0.5 * (g.a + g.b);
}

}  // namespace

TimeResponse step(const StateSpace& sys, double t_end, int n, int in) {
  check_channel(sys, in);
  if (sys.is_discrete()) {
    if (!(t_end > 0.0)) throw InputError("the final time must be a positive number of seconds");
    n = static_cast<int>(std::floor(t_end / sys.ts() + 1e-9)) + 1;
    if (n > 50'000'000) throw InputError("step: too many samples for this sample time and final time");
  }
  check_horizon(t_end, std::max(n, 2));
  const double dt = sys.is_discrete() ? sys.ts() : t_end / (n - 1);
  if (sys.is_discrete()) {
    Matrix u = Matrix::Zero(n, sys.num_inputs());
    u.col(in).setOnes();
    return lsim(sys, u, dt);
  }
  // Each sample from e^{M t_k} of the augmented M (no accumulation over the horizon);
  // balanced first (exact power-of-two similarity: smaller ||M||, fewer squarings).
  const StateSpace bal = sys.balanced();
  Vector z0 = Vector::Zero(bal.num_states() + bal.num_inputs());
  z0(bal.num_states() + in) = 1.0;
  return outputs(bal, SchurExponential(augmented(bal)).samples(z0, dt, n), dt,
                 z0.tail(bal.num_inputs()));
}

TimeResponse impulse(const StateSpace& sys, double t_end, int n, int in) {
  check_channel(sys, in);
  if (sys.is_discrete()) {
    if (!(t_end > 0.0)) throw InputError("the final time must be a positive number of seconds");
    n = static_cast<int>(std::floor(t_end / sys.ts() + 1e-9)) + 1;
    Matrix u = Matrix::Zero(n, sys.num_inputs());
    u(0, in) = 1.0;
    return lsim(sys, u, sys.ts());
  }
  check_horizon(t_end, n);
  const double dt = t_end / (n - 1);
  // y(t_k) = C e^{A t_k} B, each sample from its own exponential (SchurExponential).
  const StateSpace bal = sys.balanced();
  const Matrix x = SchurExponential(bal.a()).samples(bal.b().col(in), dt, n);
  return outputs(bal, x, dt, Vector::Zero(bal.num_inputs()));
}

TimeResponse lsim(const StateSpace& sys, const Matrix& u, double dt, const Vector& x0) {
  if (u.cols() != sys.num_inputs())
    throw InputError("lsim: the input has " + std::to_string(u.cols()) + " columns, the system " +
                     std::to_string(sys.num_inputs()) + " inputs");
  if (x0.size() != 0 && x0.size() != sys.num_states())
    throw InputError("lsim: the initial state has " + std::to_string(x0.size()) + " entries, the system " +
                     std::to_string(sys.num_states()) + " states");
  if (!(dt > 0.0) || !std::isfinite(dt)) throw InputError("lsim: the time step must be positive");
  if (sys.is_discrete()) {
    if (std::abs(dt - sys.ts()) > 1e-12 * sys.ts())
      throw InputError("lsim: a discrete system runs at its own sample time " + std::to_string(sys.ts()) + " s");
    return run(sys, sys.a(), sys.b(), u, sys.ts(), x0);
  }
  const Zoh z = zoh(sys, dt);
  return run(sys, z.phi, z.gamma, u, dt, x0);
}

StepInfo step_info(const StateSpace& sys, const TimeResponse& resp, int out, int in, double settling_fraction,
                   double rise_low, double rise_high) {
  check_channel(sys, in);
  if (out < 0 || out >= sys.num_outputs() || resp.y.cols() != sys.num_outputs())
    throw InputError("step_info: output index out of range");
  if (resp.t.size() < 2 || !sys.is_stable()) return {};
  const StateSpace ch = sys.select({out}, {in});
  // Exact response between samples (continuous): y(t) = C Gamma(t) + D for a unit step
  // from rest; on samples of a discrete system only.
  std::function<double(double)> y_at;
  std::optional<SchurExponential> e;
  if (!sys.is_discrete()) {
    e.emplace(augmented(ch));
    y_at = [&](double t) {
      if (t <= 0.0) return ch.d()(0, 0);
      Vector z0 = Vector::Zero(e->size());
      z0(e->size() - 1) = 1.0;
      return (ch.c() * e->apply(z0, t).head(ch.num_states()))(0, 0) + ch.d()(0, 0);
    };
  }
  std::vector<double> y(resp.t.size());
  for (size_t k = 0; k < y.size(); ++k) y[k] = resp.y(static_cast<Eigen::Index>(k), out);
  return step_figures(resp.t, y, ch.dc_gain()(0, 0), y_at, settling_fraction, rise_low, rise_high);
}

StepInfo step_figures(const std::vector<double>& t, const std::vector<double>& y, double final,
                      const std::function<double(double)>& y_at, double settling_fraction, double rise_low,
                      double rise_high) {
  StepInfo info;
  const size_t n = t.size();
  if (n < 2 || y.size() != n) return info;
  info.final_value = final;
  const bool exact = static_cast<bool>(y_at);

  // Peak.
  size_t kp = 0;
  for (size_t k = 1; k < n; ++k)
    if ((final >= 0 ? y[k] > y[kp] : y[k] < y[kp])) kp = k;
  double tp = t[kp], yp = y[kp];
  if (exact && kp > 0 && kp + 1 < n) {
    const double sgn = final >= 0 ? 1.0 : -1.0;
    tp = golden_max([&](double x) { return sgn * y_at(x); }, t[kp - 1], t[kp + 1]);
    yp = y_at(tp);
    if (sgn * yp < sgn * y[kp]) tp = t[kp], yp = y[kp];
  }
  info.peak = yp;
  info.peak_time_s = tp;
  if (final == 0.0) return info;
  info.overshoot_pct = std::max(0.0, (yp - final) / final * 100.0);

  // Crossing time of the normalised response through `level`, between samples.
  auto crossing = [&](size_t k, double level) {  // y[k-1] below level, y[k] at or above (normalised)
    if (!exact) return t[k];
    return bisect([&](double x) { return y_at(x) / final - level; }, t[k - 1], t[k]);
  };
  auto first_at_or_above = [&](double level) -> std::optional<double> {
    for (size_t k = 0; k < n; ++k)
      if (y[k] / final >= level) return k == 0 ? t[0] : crossing(k, level);
    return std::nullopt;
  };
  const auto t_lo = first_at_or_above(rise_low), t_hi = first_at_or_above(rise_high);
  if (t_lo && t_hi) info.rise_time_s = *t_hi - *t_lo;

  // Settling: after the last sample outside the band.
  size_t last_out = n;
  for (size_t k = n; k-- > 0;)
    if (std::abs(y[k] / final - 1.0) > settling_fraction) {
      last_out = k;
      break;
    }
  if (last_out == n) {
    info.settling_time_s = t[0];
  } else if (last_out + 1 < n) {
    if (!exact) {
      info.settling_time_s = t[last_out + 1];
    } else {
      const double side = y[last_out] / final - 1.0 > 0.0 ? settling_fraction : -settling_fraction;
      info.settling_time_s =
          bisect([&](double x) { return y_at(x) / final - 1.0 - side; }, t[last_out], t[last_out + 1]);
    }
  }
  return info;
}

double default_step_horizon(const StateSpace& sys) { return step_horizon(sys.poles(), sys.ts()); }

double step_horizon(const std::vector<Complex>& roots, double ts) {
  double slowest = std::numeric_limits<double>::infinity(), fastest = 0.0, delay = 0.0, spread = 0.0;
  std::vector<Complex> poles;
  for (const Complex& p : roots) poles.push_back(ts > 0.0 ? std::log(p) / ts : p);
  for (const Complex& s : poles)
    if (std::isfinite(std::abs(s))) fastest = std::max(fastest, std::abs(s));
  // A pole whose decay rate is at rounding level against the fastest one is an
  // integrator (it comes out as -1e-17 rather than 0 from the eigenvalues).
  bool stable = true;
  for (const Complex& s : poles) {
    if (!(s.real() < -1e-9 * fastest)) {
      stable = false;
    } else {
      slowest = std::min(slowest, -s.real());
      delay += (-1.0 / s).real();  // mean and variance of the impulse response of 1/(1 - s/p)
      spread += std::max(0.0, (1.0 / (s * s)).real());
    }
  }
  if (!stable) {
    // Horizon set by the slowest non-zero dynamics.
    double slow_mag = std::numeric_limits<double>::infinity();
    for (const Complex& s : poles)
      if (std::abs(s) > 1e-9 * fastest) slow_mag = std::min(slow_mag, std::abs(s));
    if (std::isfinite(slow_mag)) fastest = slow_mag;
  }
  double t = 1.0;
  if (stable && std::isfinite(slowest)) {
    t = std::max(7.0 / slowest, delay + 6.0 * std::sqrt(spread));
  } else if (fastest > 0.0) {
    t = 10.0 / fastest;
  }
  if (ts > 0.0) t = std::max(t, 20.0 * ts);
  return std::clamp(t, 1e-6, 1e6);
}

}  // namespace dmbd::blocks
