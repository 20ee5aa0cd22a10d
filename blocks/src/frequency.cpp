#include "dmbd/blocks/frequency.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "angle_wrap.hpp"
#include "dmbd/blocks/error.hpp"
#include "phase_model.hpp"
#include "scaled_response.hpp"

namespace dmbd::blocks {

namespace {

constexpr double kDeg = 180.0 / M_PI;

Complex point(const TransferFunction& g, double w) {
  return g.is_discrete() ? std::polar(1.0, w * g.ts()) : Complex(0.0, w);
}

// p(s) p(-s) style products evaluated on the imaginary axis: for E(s) even, the
// polynomial in x = w^2 with E(jw) = F(w^2).
Polynomial even_part_in_w2(const Polynomial& e) {
  std::vector<double> f;
  for (int k = 0; 2 * k <= e.degree(); ++k) f.push_back((k % 2 ? -1.0 : 1.0) * e[2 * k]);
  return Polynomial(std::move(f));
}

// Im Q(jw) = w * G(w^2) with G built from the odd coefficients of Q.
Polynomial odd_part_in_w2(const Polynomial& q) {
  std::vector<double> g;
  for (int k = 1; k <= q.degree(); k += 2) g.push_back(((k - 1) / 2 % 2 ? -1.0 : 1.0) * q[k]);
  return Polynomial(std::move(g));
}

// Positive real roots x of f, returned as w = sqrt(x), ascending.
std::vector<double> positive_sqrt_roots(const Polynomial& f) {
  std::vector<double> out;
  if (f.degree() < 1) return out;
  for (const Complex& r : f.roots()) {
    if (r.real() > 0.0 && std::abs(r.imag()) <= 1e-7 * std::abs(r)) out.push_back(std::sqrt(r.real()));
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The rational function of a jv-axis variable whose value at jv equals g at w:
// itself for a continuous g (v = w), or g((1+v)/(1-v)) for a discrete one
// (v = tan(w ts / 2)).
struct AxisForm {
  Polynomial num, den;
  bool discrete;
  double ts;
  explicit AxisForm(const TransferFunction& g) : discrete(g.is_discrete()), ts(g.ts()) {
    if (!discrete) {
      num = g.num();
      den = g.den();
      return;
    }
    const int n = std::max(g.num().degree(), g.den().degree());
    const Polynomial f({1.0, 1.0}), h({1.0, -1.0});
    auto sub = [&](const Polynomial& p) {
      Polynomial out;
      for (int k = 0; k <= p.degree(); ++k) out = out + p[k] * (f.pow(k) * h.pow(n - k));
      return out;
    };
    num = sub(g.num());
    den = sub(g.den());
  }
  double to_w(double v) const { return discrete ? 2.0 * std::atan(v) / ts : v; }
  double to_v(double w) const { return discrete ? std::tan(w * ts / 2.0) : w; }
  // d/dv of log L(jv), exact.
  Complex dlog(double v) const {
    const Complex s(0.0, v);
    return Complex(0.0, 1.0) * (num.derivative()(s) / num(s) - den.derivative()(s) / den(s));
  }
  Complex value(double v) const {
    const Complex s(0.0, v);
    return num(s) / den(s);
  }
};

// Newton refinement of a root v of f(v) = Re or Im of log L(jv) - target.
double refine(const AxisForm& af, double v, bool magnitude, double target) {
  for (int it = 0; it < 20; ++it) {
    const Complex l = af.value(v);
    if (l == Complex(0.0) || !std::isfinite(std::abs(l))) break;
    const Complex dl = af.dlog(v);
    const double f = magnitude ? std::log(std::abs(l)) - target : wrap_pi(std::arg(l) - target);
    const double df = magnitude ? dl.real() : dl.imag();
    if (df == 0.0 || !std::isfinite(df)) break;
    double step = f / df;
    if (!std::isfinite(step)) break;
    // Stay near the polynomial root: refinement, not a search.
    step = std::clamp(step, -0.1 * std::abs(v), 0.1 * std::abs(v));
    v -= step;
    if (std::abs(step) <= 1e-15 * std::abs(v)) break;
  }
  return v;
}

}  // namespace

std::vector<double> logspace(double lo, double hi, int n) {
  if (!(lo > 0.0) || !(hi >= lo) || n < 1) throw InputError("logspace needs 0 < lo <= hi and n >= 1");
  if (n == 1) return {lo};
  std::vector<double> w(static_cast<size_t>(n));
  const double a = std::log10(lo), b = std::log10(hi);
  for (int k = 0; k < n; ++k) w[static_cast<size_t>(k)] = std::pow(10.0, a + (b - a) * k / (n - 1));
  w.front() = lo;
  w.back() = hi;
  return w;
}

std::vector<double> frequency_grid_around(const std::vector<Complex>& roots, double ts, int n) {
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  for (const Complex& r : roots) {
    const double mag = ts > 0.0 ? std::abs(std::log(r)) / ts : std::abs(r);
    if (mag > 0.0 && std::isfinite(mag)) lo = std::min(lo, mag), hi = std::max(hi, mag);
  }
  if (!(hi > 0.0)) lo = hi = ts > 0.0 ? 0.1 / ts : 1.0;
  lo /= 100.0;
  hi *= 100.0;
  if (ts > 0.0) {
    hi = M_PI / ts;
    lo = std::min(lo, hi / 1000.0);
  }
  return logspace(lo, hi, n);
}

std::vector<double> default_frequency_grid(const TransferFunction& g, int n) {
  std::vector<Complex> roots = g.poles();
  for (const Complex& z : g.zeros()) roots.push_back(z);
  return frequency_grid_around(roots, g.is_discrete() ? g.ts() : 0.0, n);
}

std::vector<Complex> frequency_response(const TransferFunction& g, const std::vector<double>& w) {
  std::vector<ScaledResponse> r;
  scaled_responses(g, w, r);
  std::vector<Complex> h(w.size());
  for (size_t k = 0; k < w.size(); ++k) h[k] = r[k].value(w[k]);
  return h;
}

std::vector<Eigen::MatrixXcd> frequency_response(const StateSpace& sys, const std::vector<double>& w) {
  const int n = sys.num_states(), m = sys.num_inputs();
  std::vector<Eigen::MatrixXcd> out(w.size());
  if (n == 0) {
    for (auto& r : out) r = sys.d().cast<Complex>();
    return out;
  }
  // A = Q H Q^T with H upper Hessenberg: G(x) = C Q (xI - H)^-1 Q^T B + D.
  Eigen::HessenbergDecomposition<Matrix> hd(sys.a());
  const Matrix h = hd.matrixH();
  const Matrix q = hd.matrixQ();
  const Eigen::MatrixXcd bt = (q.transpose() * sys.b()).cast<Complex>();
  const Eigen::MatrixXcd ct = (sys.c() * q).cast<Complex>();
  const Eigen::MatrixXcd d = sys.d().cast<Complex>();
  // Row-major working copies so that the row operations below run over contiguous
  // memory; plain loops, because Eigen's dynamic-size row expressions cost more than
  // the arithmetic at these sizes.
  const Eigen::Matrix<Complex, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> minus_h = -h.cast<Complex>();
  Eigen::Matrix<Complex, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> work(n, n), x(n, m);
  for (size_t k = 0; k < w.size(); ++k) {
    const Complex s = sys.is_discrete() ? std::polar(1.0, w[k] * sys.ts()) : Complex(0.0, w[k]);
    work = minus_h;
    for (int i = 0; i < n; ++i) work(i, i) += s;
    x = bt;
    Complex* a = work.data();
    Complex* xb = x.data();
    // Gaussian elimination with partial pivoting on a Hessenberg matrix: only the
    // sub-diagonal entry is below each pivot, so it costs O(n^2) instead of O(n^3).
    for (int c = 0; c < n - 1; ++c) {
      Complex* rc = a + c * n;
      Complex* rn = rc + n;
      if (std::norm(rn[c]) > std::norm(rc[c])) {
        for (int j = c; j < n; ++j) std::swap(rc[j], rn[j]);
        for (int j = 0; j < m; ++j) std::swap(xb[c * m + j], xb[(c + 1) * m + j]);
      }
      if (rc[c] == Complex(0.0)) continue;
      const Complex f = rn[c] / rc[c];
      for (int j = c + 1; j < n; ++j) rn[j] -= f * rc[j];
      rn[c] = 0.0;
      for (int j = 0; j < m; ++j) xb[(c + 1) * m + j] -= f * xb[c * m + j];
    }
    for (int r = n - 1; r >= 0; --r) {
      const Complex* rr = a + r * n;
      for (int j = 0; j < m; ++j) {
        Complex acc = xb[r * m + j];
        for (int q = r + 1; q < n; ++q) acc -= rr[q] * xb[q * m + j];
        xb[r * m + j] = acc / rr[r];
      }
    }
    out[k] = ct * x + d;
  }
  return out;
}

// The response from the coefficients (scaled_response), the phase as the branch of
// arg G nearest the factor-wise model: the model is only needed to within pi, so
// its approximate form serves; the exact one only where G is 0 or infinite.
Bode bode(const TransferFunction& g, const std::vector<double>& w) {
  Bode b;
  b.w_rad_s = w;
  const PhaseModel model(g);
  std::vector<double> model_rad;
  model.approx_phase_rad(w, model_rad);
  std::vector<ScaledResponse> responses;
  scaled_responses(g, w, responses);
  const size_t n = w.size();
  b.response.resize(n);
  b.mag_db.resize(n);
  b.phase_deg.resize(n);
  for (size_t k = 0; k < n; ++k) {
    const ScaledResponse& r = responses[k];
    b.response[k] = r.value(w[k]);
    const bool regular = std::isfinite(r.h.real()) && std::isfinite(r.h.imag()) && r.h != Complex(0.0);
    if (!regular || std::isnan(model_rad[k])) {
      b.mag_db[k] = 20.0 * std::log10(std::abs(r.h));
      b.phase_deg[k] = model.phase_rad(w[k]) * kDeg;
      continue;
    }
    b.mag_db[k] = r.mag_db(w[k]);
    const double a = r.arg_rad(w[k]);
    b.phase_deg[k] = (a + 2.0 * M_PI * std::round((model_rad[k] - a) / (2.0 * M_PI))) * kDeg;
  }
  return b;
}

Margins margins(const TransferFunction& loop) {
  Margins out;
  if (loop.num().is_zero()) return out;
  const AxisForm af(loop);
  const Polynomial& n = af.num;
  const Polynomial& d = af.den;

  // Gain crossovers: |N(jv)|^2 = |D(jv)|^2.
  const Polynomial e = n * n.negated_argument() - d * d.negated_argument();
  std::vector<double> gc = positive_sqrt_roots(even_part_in_w2(e));
  // Phase crossovers: Im N(jv) D(-jv) = 0 with the real part negative.
  const Polynomial q = n * d.negated_argument();
  std::vector<double> pc = positive_sqrt_roots(odd_part_in_w2(q));

  for (double v : gc) {
    v = refine(af, v, true, 0.0);
    const double w = af.to_w(v);
    const double ph = bode(loop, {w}).phase_deg[0];
    double pm = std::remainder(180.0 + ph, 360.0);
    if (pm <= -180.0) pm += 360.0;
    out.gain_crossovers.push_back({w, pm});
  }
  auto add_phase_crossover = [&](double w, Complex l) {
    if (!(l.real() < 0.0) || !std::isfinite(std::abs(l))) return;
    if (std::abs(l.imag()) > 1e-6 * std::abs(l)) return;
    out.phase_crossovers.push_back({w, -20.0 * std::log10(std::abs(l))});
  };
  for (double v : pc) {
    v = refine(af, v, false, M_PI);
    const double w = af.to_w(v);
    add_phase_crossover(w, loop.evaluate(point(loop, w)));
  }
  // DC is a phase crossover when L(0) is finite (no pole at s = 0, z = 1, as dc_gain()
  // decides it) and negative: evaluating num/den there would turn a pole at z = 1 into
  // a huge finite value (issue 13: -279 dB at 0 Hz).
  if (const auto dc = loop.dc_gain(); dc && *dc < 0.0)
    out.phase_crossovers.push_back({0.0, -20.0 * std::log10(-*dc)});
  if (loop.is_discrete()) add_phase_crossover(M_PI / loop.ts(), loop.evaluate(Complex(-1.0, 0.0)));

  settle_margins(out);
  return out;
}

namespace {

void dedupe(std::vector<Crossing>& cs) {
  std::sort(cs.begin(), cs.end(), [](const Crossing& a, const Crossing& b) { return a.w_rad_s < b.w_rad_s; });
  cs.erase(std::unique(cs.begin(), cs.end(),
                       [](const Crossing& a, const Crossing& b) {
                         return std::abs(a.w_rad_s - b.w_rad_s) <= 1e-8 * std::max(1e-300, std::abs(b.w_rad_s));
                       }),
           cs.end());
}

const Crossing* smallest(const std::vector<Crossing>& cs) {
  const Crossing* best = nullptr;
  for (const Crossing& c : cs)
    if (!best || std::abs(c.margin) < std::abs(best->margin)) best = &c;
  return best;
}

}  // namespace

void settle_margins(Margins& out) {
  dedupe(out.gain_crossovers);
  dedupe(out.phase_crossovers);
  if (const Crossing* c = smallest(out.gain_crossovers)) {
    out.phase_margin_deg = c->margin;
    out.gain_crossover_rad_s = c->w_rad_s;
  }
  if (const Crossing* c = smallest(out.phase_crossovers)) {
    out.gain_margin_db = c->margin;
    out.phase_crossover_rad_s = c->w_rad_s;
  }
}

std::optional<double> bandwidth(const TransferFunction& g, double drop_db) {
  const std::optional<double> dc = g.dc_gain();
  if (!dc || *dc == 0.0) return std::nullopt;
  const double level = std::abs(*dc) * std::pow(10.0, drop_db / 20.0);
  const AxisForm af(g);
  const Polynomial e = af.num * af.num.negated_argument() - (level * level) * (af.den * af.den.negated_argument());
  for (double v : positive_sqrt_roots(even_part_in_w2(e))) {
    v = refine(af, v, true, std::log(level));
    const double w = af.to_w(v);
    if (g.is_discrete() && !(w < M_PI / g.ts())) continue;
    // A downward crossing: just above it the gain is below the level.
    if (std::abs(g.evaluate(point(g, w * (1.0 + 1e-6)))) < level) return w;
  }
  return std::nullopt;
}

}  // namespace dmbd::blocks
