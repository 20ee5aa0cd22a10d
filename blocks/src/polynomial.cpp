#include "dmbd/blocks/polynomial.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/state_space.hpp"

namespace dmbd::blocks {

Polynomial::Polynomial(std::vector<double> ascending) : c_(std::move(ascending)) { strip(); }
Polynomial::Polynomial(std::initializer_list<double> ascending) : c_(ascending) { strip(); }

void Polynomial::strip() {
  while (!c_.empty() && c_.back() == 0.0) c_.pop_back();
}

Polynomial Polynomial::from_descending(const std::vector<double>& descending) {
  return Polynomial(std::vector<double>(descending.rbegin(), descending.rend()));
}

Polynomial Polynomial::constant(double c) { return Polynomial(std::vector<double>{c}); }

Polynomial Polynomial::monomial(int degree, double coefficient) {
  std::vector<double> c(static_cast<size_t>(degree) + 1, 0.0);
  c.back() = coefficient;
  return Polynomial(std::move(c));
}

Polynomial Polynomial::from_roots(const std::vector<Complex>& roots, double leading) {
  // Multiply out in complex arithmetic, then check the imaginary parts vanish.
  std::vector<Complex> c{Complex(1.0)};
  for (const Complex& r : roots) {
    std::vector<Complex> next(c.size() + 1, Complex(0.0));
    for (size_t k = 0; k < c.size(); ++k) {
      next[k + 1] += c[k];
      next[k] -= r * c[k];
    }
    c = std::move(next);
  }
  std::vector<double> re(c.size());
  double scale = 0.0;
  for (const Complex& v : c) scale = std::max(scale, std::abs(v));
  for (size_t k = 0; k < c.size(); ++k) {
    if (std::abs(c[k].imag()) > 1e-8 * std::max(1.0, scale)) {
      throw InputError("roots are not closed under complex conjugation: the polynomial would not be real");
    }
    re[k] = leading * c[k].real();
  }
  return Polynomial(std::move(re));
}

std::vector<double> Polynomial::descending() const { return std::vector<double>(c_.rbegin(), c_.rend()); }

int Polynomial::zero_roots() const {
  int n = 0;
  while (n < static_cast<int>(c_.size()) && c_[n] == 0.0) ++n;
  return n;
}

bool Polynomial::has_root_at(double x0) const {
  double scale = 0.0, xk = 1.0;
  for (double c : c_) {
    scale += std::abs(c) * xk;
    xk *= std::abs(x0);
  }
  return std::abs((*this)(x0)) <= 1e-12 * scale;
}

std::pair<Polynomial, int> Polynomial::without_root(double x0) const {
  Polynomial p = *this;
  int m = 0;
  while (p.degree() >= 1 && p.has_root_at(x0)) {
    p = divide(p, Polynomial({-x0, 1.0})).first;
    ++m;
  }
  return {p, m};
}

Polynomial expand(const FactorList& factors) {
  Polynomial r = Polynomial::constant(1.0);
  for (const PolynomialFactor& f : factors) r = r * f.poly.pow(f.multiplicity);
  return r;
}

double Polynomial::operator()(double x) const {
  double v = 0.0;
  for (auto it = c_.rbegin(); it != c_.rend(); ++it) v = v * x + *it;
  return v;
}

Complex Polynomial::operator()(Complex x) const {
  Complex v(0.0);
  for (auto it = c_.rbegin(); it != c_.rend(); ++it) v = v * x + *it;
  return v;
}

Polynomial Polynomial::derivative() const {
  if (c_.size() <= 1) return Polynomial();
  std::vector<double> d(c_.size() - 1);
  for (size_t k = 1; k < c_.size(); ++k) d[k - 1] = static_cast<double>(k) * c_[k];
  return Polynomial(std::move(d));
}

namespace {

// |p(x)| with a running error bound, used to stop polishing when the residual is
// at rounding level.
Complex newton_step(const Polynomial& p, const Polynomial& dp, Complex x) {
  const Complex d = dp(x);
  if (d == Complex(0.0)) return x;
  return x - p(x) / d;
}

}  // namespace

std::vector<Complex> Polynomial::roots() const {
  std::vector<Complex> out;
  const int nz = zero_roots();
  for (int k = 0; k < nz; ++k) out.emplace_back(0.0, 0.0);
  // Deflated polynomial without the zero roots.
  const std::vector<double> q(c_.begin() + nz, c_.end());
  const int n = static_cast<int>(q.size()) - 1;
  if (n >= 1) {
    // Companion matrix (top row form) of the monic polynomial.
    Matrix comp = Matrix::Zero(n, n);
    for (int j = 0; j < n; ++j) comp(0, j) = -q[n - 1 - j] / q[n];
    for (int i = 1; i < n; ++i) comp(i, i - 1) = 1.0;
    const Vector d = balancing_scales(comp);
    const Matrix bal = d.cwiseInverse().asDiagonal() * comp * d.asDiagonal();
    Eigen::EigenSolver<Matrix> es(bal, false);
    if (es.info() != Eigen::Success) throw InputError("polynomial root finding did not converge");
    const Polynomial p(q);
    const Polynomial dp = p.derivative();
    for (int k = 0; k < n; ++k) {
      Complex r = es.eigenvalues()[k];
      double res = std::abs(p(r));
      for (int it = 0; it < 8 && res > 0.0; ++it) {
        const Complex r2 = newton_step(p, dp, r);
        const double res2 = std::abs(p(r2));
        if (!(res2 < res)) break;
        r = r2;
        res = res2;
      }
      out.push_back(r);
    }
    // Real polynomial: make conjugate pairs exact, and near-real singletons real.
    std::vector<Complex> fixed;
    std::vector<bool> used(out.size(), false);
    for (size_t i = nz; i < out.size(); ++i) {
      if (used[i]) continue;
      used[i] = true;
      const Complex r = out[i];
      const double tol = 1e-10 * std::max(1.0, std::abs(r));
      if (std::abs(r.imag()) <= tol) {
        fixed.emplace_back(r.real(), 0.0);
        continue;
      }
      // Find the partner closest to conj(r).
      size_t best = out.size();
      double best_d = 0.0;
      for (size_t j = nz; j < out.size(); ++j) {
        if (used[j]) continue;
        const double dist = std::abs(out[j] - std::conj(r));
        if (best == out.size() || dist < best_d) best = j, best_d = dist;
      }
      if (best != out.size()) {
        used[best] = true;
        const Complex m(0.5 * (r.real() + out[best].real()), 0.5 * (std::abs(r.imag()) + std::abs(out[best].imag())));
        fixed.push_back(m);
        fixed.push_back(std::conj(m));
      } else {
        fixed.emplace_back(r.real(), 0.0);
      }
    }
    out.resize(nz);
    out.insert(out.end(), fixed.begin(), fixed.end());
  }
  std::sort(out.begin(), out.end(), [](const Complex& a, const Complex& b) {
    if (a.real() != b.real()) return a.real() < b.real();
    return a.imag() < b.imag();
  });
  return out;
}

Polynomial Polynomial::monic() const {
  if (c_.empty()) return *this;
  return (1.0 / c_.back()) * (*this);
}

Polynomial Polynomial::pow(int n) const {
  if (n < 0) throw InputError("negative power of a polynomial");
  Polynomial r = constant(1.0), b = *this;
  while (n > 0) {
    if (n & 1) r = r * b;
    b = b * b;
    n >>= 1;
  }
  return r;
}

Polynomial Polynomial::compose(const Polynomial& inner) const {
  // Horner in polynomial arithmetic.
  Polynomial r;
  for (auto it = c_.rbegin(); it != c_.rend(); ++it) r = r * inner + constant(*it);
  return r;
}

Polynomial Polynomial::negated_argument() const {
  std::vector<double> c = c_;
  for (size_t k = 1; k < c.size(); k += 2) c[k] = -c[k];
  return Polynomial(std::move(c));
}

Polynomial Polynomial::trimmed(double rel_tol) const {
  double m = 0.0;
  for (double v : c_) m = std::max(m, std::abs(v));
  std::vector<double> c = c_;
  while (!c.empty() && std::abs(c.back()) <= rel_tol * m) c.pop_back();
  return Polynomial(std::move(c));
}

Polynomial operator+(const Polynomial& a, const Polynomial& b) {
  std::vector<double> c(std::max(a.c_.size(), b.c_.size()), 0.0);
  for (size_t k = 0; k < a.c_.size(); ++k) c[k] += a.c_[k];
  for (size_t k = 0; k < b.c_.size(); ++k) c[k] += b.c_[k];
  return Polynomial(std::move(c));
}

Polynomial operator-(const Polynomial& a, const Polynomial& b) { return a + (-b); }

Polynomial operator*(const Polynomial& a, const Polynomial& b) {
  if (a.is_zero() || b.is_zero()) return Polynomial();
  std::vector<double> c(a.c_.size() + b.c_.size() - 1, 0.0);
  for (size_t i = 0; i < a.c_.size(); ++i)
    for (size_t j = 0; j < b.c_.size(); ++j) c[i + j] += a.c_[i] * b.c_[j];
  return Polynomial(std::move(c));
}

Polynomial operator*(double k, const Polynomial& a) {
  std::vector<double> c = a.c_;
  for (double& v : c) v *= k;
  return Polynomial(std::move(c));
}

Polynomial Polynomial::operator-() const { return -1.0 * (*this); }

std::pair<Polynomial, Polynomial> Polynomial::divide(const Polynomial& a, const Polynomial& b) {
  if (b.is_zero()) throw InputError("polynomial division by zero");
  std::vector<double> r = a.c_;
  const int nb = b.degree();
  if (a.degree() < nb) return {Polynomial(), a};
  std::vector<double> q(static_cast<size_t>(a.degree() - nb) + 1, 0.0);
  for (int k = a.degree() - nb; k >= 0; --k) {
    const double f = r[static_cast<size_t>(k + nb)] / b.c_.back();
    q[static_cast<size_t>(k)] = f;
    for (int j = 0; j <= nb; ++j) r[static_cast<size_t>(k + j)] -= f * b.c_[static_cast<size_t>(j)];
    r[static_cast<size_t>(k + nb)] = 0.0;
  }
  r.resize(static_cast<size_t>(nb));
  return {Polynomial(std::move(q)), Polynomial(std::move(r))};
}

}  // namespace dmbd::blocks
