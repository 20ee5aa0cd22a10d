#include "phase_model.hpp"

#include "angle_wrap.hpp"
#include "dmbd/base/vector_clones.hpp"

#include <algorithm>
#include <cmath>

namespace dmbd::blocks {

namespace {

// atan2(y, x) within 1e-5 rad (NaN at 0/0): Hastings' degree-11 odd minimax polynomial
// for atan on [0, 1], branch-free so that the loops below vectorise. Written by hand
// because libm's atan2 is exact to the last bit at ten times the cost, while the branch
// choice it serves needs a few tenths of a radian.
inline double atan2_poly(double y, double x) {
  const double ax = std::fabs(x), ay = std::fabs(y);
  const double t = std::min(ax, ay) / std::max(ax, ay);
  const double t2 = t * t;
  double r = t * (0.99997726 + t2 * (-0.33262347 + t2 * (0.19354346 + t2 * (-0.11643287 + t2 * (0.05265332 + t2 * -0.01172120)))));
  r = ay > ax ? M_PI_2 - r : r;
  r = x < 0.0 ? M_PI - r : r;
  return std::copysign(r, y);
}

// p[k] += sign arg(1 - a x[k]^e - j b x[k]) with e = 2 for a conjugate pair, 1 for one
// root. 0.0 - (...) keeps a zero imaginary part +0: a root on the axis gives +pi past
// it, as wrap_pi does.
DMBD_VECTOR_CLONES void add_axis_phases(const double* x, double* p, std::size_t n, double a, double b, double sign,
                                        bool pair) {
  if (pair) {
    for (std::size_t k = 0; k < n; ++k) p[k] += sign * atan2_poly(0.0 - x[k] * b, 1.0 - x[k] * x[k] * a);
  } else {
    for (std::size_t k = 0; k < n; ++k) p[k] += sign * atan2_poly(0.0 - x[k] * b, 1.0 - x[k] * a);
  }
}

}  // namespace

PhaseModel::PhaseModel(const TransferFunction& g) : discrete_(g.is_discrete()), ts_(g.ts()) {
  const double x0 = discrete_ ? 1.0 : 0.0;
  const auto [n, mn] = g.num().without_root(x0);
  const auto [d, md] = g.den().without_root(x0);
  m_ = mn - md;
  zeros_ = n.roots();
  poles_ = d.roots();
  const double k0 = n(x0) / d(x0);
  low_rad_ = m_ * M_PI / 2.0 + (k0 < 0.0 ? -M_PI : 0.0);
  add_roots(zeros_, 1.0);
  add_roots(poles_, -1.0);
}

// Continuous roots in conjugate pairs: each root above the real axis with the
// unmatched root below nearest its conjugate, when within 1e-6 of its modulus (a real
// polynomial's roots, off the exact conjugate by rounding, which moves the pair's phase
// by as little: only the branch is taken from it). The root above stands for both.
// Every other root on its own.
void PhaseModel::add_roots(const std::vector<Complex>& roots, double sign) {
  if (discrete_) {
    for (const Complex& r : roots) z_.push_back({r.real(), r.imag(), std::arg(Complex(1.0, 0.0) - r), sign, std::abs(r) < 1.0});
    return;
  }
  std::vector<bool> paired(roots.size(), false);
  for (std::size_t i = 0; i < roots.size(); ++i) {
    const Complex& r = roots[i];
    if (!(r.imag() > 0.0)) continue;
    std::size_t partner = roots.size();
    double best = 1e-6 * std::abs(r);
    for (std::size_t j = 0; j < roots.size(); ++j) {
      if (paired[j] || !(roots[j].imag() < 0.0)) continue;
      const double d = std::abs(roots[j] - std::conj(r));
      if (d <= best) best = d, partner = j;
    }
    if (partner == roots.size()) continue;
    paired[i] = paired[partner] = true;
    pairs_.push_back({2.0 * r.real() / std::norm(r), 1.0 / std::norm(r), sign});
  }
  for (std::size_t i = 0; i < roots.size(); ++i)
    if (!paired[i]) s_.push_back({roots[i].real() / std::norm(roots[i]), roots[i].imag() / std::norm(roots[i]), sign});
}

// Exact phase change of one root's factor from DC to w.
double PhaseModel::factor(const Complex& r, double w) const {
  if (!discrete_) return wrap_pi(std::arg(Complex(1.0, 0.0) - Complex(0.0, w) / r));
  const double th = w * ts_;
  const double raw = std::arg(std::polar(1.0, th) - r) - std::arg(Complex(1.0, 0.0) - r);
  return std::abs(r) < 1.0 ? wrap_2pi(raw) : wrap_pi(raw);
}

double PhaseModel::phase_rad(double w) const {
  double p = low_rad_ + (discrete_ ? m_ * w * ts_ / 2.0 : 0.0);
  for (const Complex& z : zeros_) p += factor(z, w);
  for (const Complex& q : poles_) p -= factor(q, w);
  return p;
}

void PhaseModel::approx_phase_rad(const std::vector<double>& w, std::vector<double>& out) const {
  const std::size_t n = w.size();
  out.assign(n, low_rad_);
  double* p = out.data();
  const double* x = w.data();
  if (!discrete_) {
    for (const SRoot& r : s_) add_axis_phases(x, p, n, r.im_over_abs2, r.re_over_abs2, r.sign, false);
    for (const SPair& r : pairs_) add_axis_phases(x, p, n, r.inv_abs2, r.two_re_over_abs2, r.sign, true);
    return;
  }
  for (std::size_t k = 0; k < n; ++k) {
    const double th = x[k] * ts_, c = std::cos(th), s = std::sin(th);
    p[k] += m_ * th / 2.0;
    for (const ZRoot& r : z_) {
      // arg((e^{j th} - r) conj(1 - r)): the difference of the two angles in one
      // product, so a small change keeps its sign.
      const double ar = c - r.re, ai = s - r.im, br = 1.0 - r.re, bi = r.im;
      double d = atan2_poly(ai * br + ar * bi, ar * br - ai * bi);
      if (r.inside) d = d < 0.0 ? d + 2.0 * M_PI : d;
      p[k] += r.sign * d;
    }
  }
}

}  // namespace dmbd::blocks
