#include "dmbd/blocks/zpk.hpp"

#include "dmbd/blocks/frequency.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/state_space.hpp"
#include "angle_wrap.hpp"

namespace dmbd::blocks {

namespace {

constexpr double kDeg = 180.0 / M_PI;
constexpr double kDbPerNeper = 20.0 / M_LN10;

// Phase change of the factor (z - r)/(1 - r) from z = 1 to e^{j th}: it winds once
// around a root inside the circle (monotone, in [0, 2 pi)) and not around one outside.
double discrete_factor_phase(const Complex& r, double th) {
  const double raw = std::arg(std::polar(1.0, th) - r) - std::arg(Complex(1.0, 0.0) - r);
  return std::abs(r) < 1.0 ? wrap_2pi(raw) : std::remainder(raw, 2.0 * M_PI);
}

// log of one root's factor at w: continuous 1 - jw/r, discrete (e^{jwT} - r)/(1 - r).
Complex log_factor(const Complex& r, double w, double ts) {
  if (ts == 0.0) {
    const Complex f = 1.0 - Complex(0.0, w) / r;
    return {std::log(std::abs(f)), std::arg(f)};
  }
  const double th = w * ts;
  return {std::log(std::abs(std::polar(1.0, th) - r)) - std::log(std::abs(1.0 - r)), discrete_factor_phase(r, th)};
}

// d/dw of log_factor.
Complex factor_slope(const Complex& r, double w, double ts) {
  if (ts == 0.0) return Complex(0.0, 1.0) / (Complex(0.0, w) - r);
  const Complex e = std::polar(1.0, w * ts);
  return Complex(0.0, ts) * e / (e - r);
}

std::vector<Complex> sorted(std::vector<Complex> v) {
  sort_roots(v);
  return v;
}

// Runs of equal roots in a sorted list.
std::vector<Zpk::Root> runs(const std::vector<Complex>& sorted_roots) {
  std::vector<Zpk::Root> out;
  for (const Complex& r : sorted_roots) {
    if (!out.empty() && out.back().value == r) {
      ++out.back().count;
    } else {
      out.push_back({r, 1});
    }
  }
  return out;
}

}  // namespace

Zpk::Zpk(double k, int m, std::vector<Complex> zeros, std::vector<Complex> poles, double ts)
    : k_(k),
      m_(m),
      zeros_(sorted(std::move(zeros))),
      poles_(sorted(std::move(poles))),
      ts_(ts),
      distinct_zeros_(runs(zeros_)),
      distinct_poles_(runs(poles_)) {
  if (!(ts >= 0.0) || !std::isfinite(ts)) throw InputError("sample time must be a finite number >= 0");
  if (!std::isfinite(k)) throw InputError("zero-pole-gain form: the gain must be finite");
  const Complex x0(is_discrete() ? 1.0 : 0.0, 0.0);
  for (const auto* list : {&zeros_, &poles_})
    for (const Complex& r : *list) {
      if (!std::isfinite(r.real()) || !std::isfinite(r.imag())) throw InputError("zero-pole-gain form: a root is not finite");
      if (r == x0) throw InputError("zero-pole-gain form: roots at the boundary point belong in m");
    }
}

namespace {

// The roots of the factors (each repeated by its multiplicity). A root that rounds to
// exactly the boundary point although the coefficients have none there (they were
// removed exactly) is the nearest double beside it: Zpk keeps boundary roots in m only.
std::vector<Complex> factor_roots(const FactorList& factors, double x0) {
  std::vector<Complex> out;
  for (const PolynomialFactor& f : factors) {
    std::vector<Complex> r = f.poly.roots();
    for (Complex& z : r)
      if (z == Complex(x0, 0.0)) z = Complex(std::nextafter(x0, -1.0), 0.0);
    for (int k = 0; k < f.multiplicity; ++k) out.insert(out.end(), r.begin(), r.end());
  }
  return out;
}

}  // namespace

Zpk Zpk::from_tf(const TransferFunction& g) {
  if (g.num().is_zero()) return Zpk(0.0, 0, {}, {}, g.ts());
  const double x0 = g.is_discrete() ? 1.0 : 0.0;
  const TransferFunction::Split n = g.split_num(), d = g.split_den();
  return Zpk(n.rest_at_x0 / d.rest_at_x0, n.m - d.m, factor_roots(n.factors, x0), factor_roots(d.factors, x0), g.ts());
}

std::vector<Complex> Zpk::all_poles() const {
  std::vector<Complex> p = poles_;
  p.insert(p.end(), static_cast<size_t>(std::max(0, -m_)), Complex(is_discrete() ? 1.0 : 0.0, 0.0));
  return sorted(std::move(p));
}

std::vector<Complex> Zpk::all_zeros() const {
  std::vector<Complex> z = zeros_;
  z.insert(z.end(), static_cast<size_t>(std::max(0, m_)), Complex(is_discrete() ? 1.0 : 0.0, 0.0));
  return sorted(std::move(z));
}

std::optional<double> Zpk::dc_gain() const {
  if (k_ == 0.0 || m_ > 0) return 0.0;
  if (m_ < 0) return std::nullopt;
  return k_;
}

Complex Zpk::log_response(double w) const {
  if (k_ == 0.0) return Complex(-std::numeric_limits<double>::infinity(), 0.0);
  Complex v(std::log(std::abs(k_)), k_ < 0.0 ? -M_PI : 0.0);
  if (m_ != 0) {
    const double th = w * ts_;
    v += static_cast<double>(m_) * (is_discrete() ? Complex(std::log(2.0 * std::sin(th / 2.0)), (M_PI + th) / 2.0)
                                                  : Complex(std::log(w), M_PI / 2.0));
  }
  for (const Root& z : distinct_zeros_) v += static_cast<double>(z.count) * log_factor(z.value, w, ts_);
  for (const Root& p : distinct_poles_) v -= static_cast<double>(p.count) * log_factor(p.value, w, ts_);
  return v;
}

Complex Zpk::log_slope(double w) const {
  Complex s(0.0);
  if (m_ != 0) s += static_cast<double>(m_) * (is_discrete() ? factor_slope(Complex(1.0, 0.0), w, ts_) : Complex(1.0 / w, 0.0));
  for (const Root& z : distinct_zeros_) s += static_cast<double>(z.count) * factor_slope(z.value, w, ts_);
  for (const Root& p : distinct_poles_) s -= static_cast<double>(p.count) * factor_slope(p.value, w, ts_);
  return s;
}

Zpk operator*(const Zpk& a, const Zpk& b) {
  require_same_ts(a.ts_, b.ts_, "series connection");
  std::vector<Complex> z = a.zeros_, p = a.poles_;
  z.insert(z.end(), b.zeros_.begin(), b.zeros_.end());
  p.insert(p.end(), b.poles_.begin(), b.poles_.end());
  return Zpk(a.k_ * b.k_, a.m_ + b.m_, std::move(z), std::move(p), a.ts_);
}

Zpk Zpk::cancelled(double rel_tol, std::vector<Complex>* removed) const {
  std::vector<bool> zu(zeros_.size(), false), pu(poles_.size(), false);
  for (size_t i = 0; i < zeros_.size(); ++i) {
    size_t best = poles_.size();
    for (size_t j = 0; j < poles_.size(); ++j)
      if (!pu[j] && (best == poles_.size() || std::abs(zeros_[i] - poles_[j]) < std::abs(zeros_[i] - poles_[best])))
        best = j;
    if (best < poles_.size() && std::abs(zeros_[i] - poles_[best]) <= rel_tol * std::abs(poles_[best]))
      zu[i] = pu[best] = true;
  }
  std::vector<Complex> z, p;
  for (size_t i = 0; i < zeros_.size(); ++i)
    if (!zu[i]) z.push_back(zeros_[i]);
  for (size_t j = 0; j < poles_.size(); ++j) {
    if (!pu[j]) {
      p.push_back(poles_[j]);
    } else if (removed) {
      removed->push_back(poles_[j]);
    }
  }
  return Zpk(k_, m_, std::move(z), std::move(p), ts_);
}

std::optional<TransferFunction> Zpk::to_tf() const {
  if (k_ == 0.0) return TransferFunction(0.0, ts_);
  // The gain of the monic form: k prod(-p)/prod(-z), or k prod(1 - p)/prod(1 - z).
  const double x0 = is_discrete() ? 1.0 : 0.0;
  double log_gain = std::log(std::abs(k_)), sign = k_ < 0.0 ? -1.0 : 1.0;
  auto factor = [&](const Complex& r, double power) {
    log_gain += power * std::log(std::abs(x0 - r));
    if (r.imag() == 0.0 && x0 - r.real() < 0.0) sign = -sign;
  };
  for (const Complex& p : poles_) factor(p, 1.0);
  for (const Complex& z : zeros_) factor(z, -1.0);
  if (!(log_gain < 700.0)) return std::nullopt;
  const Polynomial num = Polynomial::from_roots(all_zeros(), sign * std::exp(log_gain));
  const Polynomial den = Polynomial::from_roots(all_poles(), 1.0);
  for (const auto* p : {&num, &den})
    for (double c : p->coeffs())
      if (!std::isfinite(c)) return std::nullopt;
  return TransferFunction(num, den, ts_);
}

std::vector<double> default_frequency_grid(const Zpk& g, int n) {
  std::vector<Complex> roots = g.zeros();
  roots.insert(roots.end(), g.poles().begin(), g.poles().end());
  return frequency_grid_around(roots, g.is_discrete() ? g.ts() : 0.0, n);
}

Bode bode(const Zpk& g, const std::vector<double>& w) {
  Bode b;
  b.w_rad_s = w;
  for (double wk : w) {
    const Complex l = g.log_response(wk);
    b.response.push_back(std::exp(l));
    b.mag_db.push_back(l.real() * kDbPerNeper);
    b.phase_deg.push_back(l.imag() * kDeg);
  }
  return b;
}

bool on_boundary(const Complex& p, bool discrete) {
  if (discrete) return p == Complex(1.0, 0.0) || std::abs(std::abs(p) - 1.0) <= 1e-9;
  return p == Complex(0.0, 0.0) || std::abs(p.real()) <= 1e-9 * std::abs(p);
}

Stability stability(const std::vector<Complex>& poles, bool discrete) {
  std::vector<Complex> edge;
  for (const Complex& p : poles) {
    if (on_boundary(p, discrete)) {
      edge.push_back(p);
    } else if (discrete ? !(std::abs(p) < 1.0) : !(p.real() < 0.0)) {
      return Stability::Unstable;
    }
  }
  for (size_t i = 0; i < edge.size(); ++i)
    for (size_t j = i + 1; j < edge.size(); ++j)
      if (std::abs(edge[i] - edge[j]) <= 1e-6 * std::abs(edge[i])) return Stability::Unstable;
  return edge.empty() ? Stability::Stable : Stability::Marginal;
}

const char* to_string(Stability s) {
  switch (s) {
    case Stability::Stable: return "stable";
    case Stability::Marginal: return "marginal";
    case Stability::Unstable: return "unstable";
    case Stability::Undecided: return "undecided";
  }
  return "?";
}

}  // namespace dmbd::blocks
