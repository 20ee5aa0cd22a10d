#include "dmbd/blocks/transfer_function.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/certified_stability.hpp"
#include "dmbd/blocks/root_enclosure.hpp"
#include "tolerance.hpp"

namespace dmbd::blocks {

void require_same_ts(double a, double b, const char* what) {
  if (a != b)
    throw InputError(std::string(what) + ": cannot combine systems with different sample times (" +
                     std::to_string(a) + " s and " + std::to_string(b) + " s)");
}

void require_tolerance(double tol, const char* what) {
  if (tol >= 0.0 && std::isfinite(tol)) return;
  char value[32];
  std::snprintf(value, sizeof value, "%g", tol);
  throw InputError(std::string(what) + ": the tolerance 'tol' must be a finite number >= 0, got " + value);
}

TransferFunction::TransferFunction(Polynomial num, Polynomial den, double ts) : ts_(ts) {
  if (!(ts >= 0.0) || !std::isfinite(ts)) throw InputError("sample time must be a finite number >= 0");
  if (den.is_zero()) throw InputError("transfer function with a zero denominator");
  for (double c : num.coeffs())
    if (!std::isfinite(c)) throw InputError("transfer function numerator has a non-finite coefficient");
  for (double c : den.coeffs())
    if (!std::isfinite(c)) throw InputError("transfer function denominator has a non-finite coefficient");
  const double lead = den.leading();
  num_ = (1.0 / lead) * num;
  den_ = (1.0 / lead) * den;
  // Make the leading coefficient exactly 1 (1/lead*lead may round).
  std::vector<double> d = den_.coeffs();
  d.back() = 1.0;
  den_ = Polynomial(std::move(d));
}

TransferFunction::TransferFunction(double gain, double ts)
    : TransferFunction(Polynomial::constant(gain), Polynomial::constant(1.0), ts) {}

TransferFunction TransferFunction::from_descending(const std::vector<double>& num, const std::vector<double>& den,
                                                   double ts) {
  return TransferFunction(Polynomial::from_descending(num), Polynomial::from_descending(den), ts);
}

TransferFunction TransferFunction::parse(std::string_view expression, const ParameterMap& params, double ts) {
  const Expression e = Expression::parse(expression);
  if (!(ts >= 0.0) || !std::isfinite(ts)) throw InputError("sample time must be a finite number >= 0");
  const Rational r = e.evaluate_rational(params, ts > 0.0 ? 'z' : 's');
  return TransferFunction(r.num, r.den, ts).with_factors(r.num_factors, r.den_factors);
}

TransferFunction TransferFunction::with_factors(FactorList num, FactorList den) const {
  TransferFunction g = *this;
  g.has_factors_ = true;
  g.num_f_ = std::move(num);
  g.den_f_ = std::move(den);
  return g;
}

// Each factor without its exact roots at x0; the value of the rest at x0 as the product
// of the factors' values (long double: a chain of factors neither overflows nor cancels),
// scaled to full's leading coefficient.
TransferFunction::Split TransferFunction::split(const Polynomial& full, const FactorList& factors) const {
  const double x0 = is_discrete() ? 1.0 : 0.0;
  Split out;
  if (full.is_zero()) return out;
  long double value = full.leading();
  for (const PolynomialFactor& f : factors) {
    if (f.poly.is_zero()) continue;
    const int m = exact_roots_at(f.poly, x0);
    const Polynomial rest = deflated(f.poly, x0, m);
    out.m += m * f.multiplicity;
    for (int k = 0; k < f.multiplicity; ++k) value *= static_cast<long double>(rest(x0)) / rest.leading();
    out.factors.push_back({rest, f.multiplicity});
  }
  const Polynomial r = expand(out.factors);
  out.rest = (full.leading() / r.leading()) * r;
  out.rest_at_x0 = static_cast<double>(value);
  return out;
}

TransferFunction::Split TransferFunction::split_num() const { return split(num_, num_factors()); }
TransferFunction::Split TransferFunction::split_den() const { return split(den_, den_factors()); }

std::optional<double> TransferFunction::dc_gain() const {
  if (num_.is_zero()) return 0.0;
  const Split n = split_num(), d = split_den();
  if (d.m > n.m) return std::nullopt;
  if (n.m > d.m) return 0.0;
  return n.rest_at_x0 / d.rest_at_x0;
}

std::vector<Complex> TransferFunction::roots_of(const Split& s) const {
  const double x0 = is_discrete() ? 1.0 : 0.0;
  std::vector<Complex> r;
  for (const PolynomialFactor& f : s.factors) {
    const std::vector<Complex> fr = f.poly.roots();
    for (int k = 0; k < f.multiplicity; ++k) r.insert(r.end(), fr.begin(), fr.end());
  }
  r.insert(r.end(), static_cast<size_t>(s.m), Complex(x0, 0.0));
  std::sort(r.begin(), r.end(), [](const Complex& a, const Complex& b) {
    return a.real() != b.real() ? a.real() < b.real() : a.imag() < b.imag();
  });
  return r;
}

bool TransferFunction::is_stable() const { return certified_stability(*this) == Stability::Stable; }

TransferFunction TransferFunction::minreal(double tol) const {
  require_tolerance(tol, "minreal");
  std::vector<Complex> z = zeros(), p = poles();
  std::vector<bool> pz(z.size(), false), pp(p.size(), false);
  bool any = false;
  for (size_t i = 0; i < z.size(); ++i) {
    size_t best = p.size();
    double best_d = 0.0;
    for (size_t j = 0; j < p.size(); ++j) {
      if (pp[j]) continue;
      const double dist = std::abs(z[i] - p[j]);
      if (dist <= tol * (1.0 + std::abs(p[j])) && (best == p.size() || dist < best_d)) best = j, best_d = dist;
    }
    if (best != p.size()) {
      pz[i] = pp[best] = true;
      any = true;
    }
  }
  if (!any) return *this;
  std::vector<Complex> zr, pr;
  for (size_t i = 0; i < z.size(); ++i)
    if (!pz[i]) zr.push_back(z[i]);
  for (size_t j = 0; j < p.size(); ++j)
    if (!pp[j]) pr.push_back(p[j]);
  // Cancelled pairs were matched one to one; conjugates of a cancelled complex pair
  // are cancelled together since roots() makes them exact conjugates.
  return TransferFunction(Polynomial::from_roots(zr, num_.leading()), Polynomial::from_roots(pr, 1.0), ts_);
}

TransferFunction operator*(const TransferFunction& a, const TransferFunction& b) {
  require_same_ts(a.ts_, b.ts_, "series connection");
  const TransferFunction g(a.num_ * b.num_, a.den_ * b.den_, a.ts_);
  if (!a.has_factors_ && !b.has_factors_) return g;
  FactorList num = a.num_factors(), den = a.den_factors();
  for (const PolynomialFactor& f : b.num_factors()) num.push_back(f);
  for (const PolynomialFactor& f : b.den_factors()) den.push_back(f);
  return g.with_factors(std::move(num), std::move(den));
}

TransferFunction operator+(const TransferFunction& a, const TransferFunction& b) {
  require_same_ts(a.ts_, b.ts_, "parallel connection");
  if (a.den_ == b.den_) return TransferFunction(a.num_ + b.num_, a.den_, a.ts_);
  return TransferFunction(a.num_ * b.den_ + b.num_ * a.den_, a.den_ * b.den_, a.ts_);
}

TransferFunction operator-(const TransferFunction& a, const TransferFunction& b) { return a + (-b); }

TransferFunction operator/(const TransferFunction& a, const TransferFunction& b) {
  require_same_ts(a.ts_, b.ts_, "division");
  if (b.num_.is_zero()) throw InputError("division by a zero transfer function");
  return TransferFunction(a.num_ * b.den_, a.den_ * b.num_, a.ts_);
}

TransferFunction TransferFunction::operator-() const { return TransferFunction(-num_, den_, ts_); }

TransferFunction TransferFunction::pow(int n) const {
  if (n >= 0) return TransferFunction(num_.pow(n), den_.pow(n), ts_);
  if (num_.is_zero()) throw InputError("negative power of a zero transfer function");
  return TransferFunction(den_.pow(-n), num_.pow(-n), ts_);
}

TransferFunction feedback(const TransferFunction& g, const TransferFunction& h, int sign) {
  require_same_ts(g.ts(), h.ts(), "feedback connection");
  const Polynomial den = g.den() * h.den() - static_cast<double>(sign) * (g.num() * h.num());
  if (den.trimmed(1e-14).is_zero())
    throw InputError("algebraic loop: 1 - sign*G*H is identically zero, the feedback connection is ill-posed");
  return TransferFunction(g.num() * h.den(), den, g.ts());
}

}  // namespace dmbd::blocks
