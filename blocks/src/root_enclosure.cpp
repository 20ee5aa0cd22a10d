// Certified root enclosures (root_enclosure.hpp). Double-double arithmetic is written
// out here (Dekker's and Knuth's error-free transformations) rather than taken from a
// library: the project has no multiprecision dependency, and the error bound below needs
// to know exactly which operations are done.
#include "dmbd/blocks/root_enclosure.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/state_space.hpp"

namespace dmbd::blocks {

namespace {

constexpr double kU = std::numeric_limits<double>::epsilon() / 2.0;  // unit roundoff 2^-53

struct DD {
  double hi, lo;
};

DD two_sum(double a, double b) {
  const double s = a + b, bb = s - a;
  return {s, (a - (s - bb)) + (b - bb)};
}
DD quick_two_sum(double a, double b) {
  const double s = a + b;
  return {s, b - (s - a)};
}
DD two_prod(double a, double b) {
  const double p = a * b;
  return {p, std::fma(a, b, -p)};
}
// The accurate double-double sum: error <= 3 u^2 (|a| + |b|).
DD add(DD a, DD b) {
  DD s = two_sum(a.hi, b.hi);
  const DD t = two_sum(a.lo, b.lo);
  s.lo += t.hi;
  s = quick_two_sum(s.hi, s.lo);
  s.lo += t.lo;
  return quick_two_sum(s.hi, s.lo);
}
// error <= 4 u^2 |a b|.
DD mul(DD a, double b) {
  DD p = two_prod(a.hi, b);
  p.lo += a.lo * b;
  return quick_two_sum(p.hi, p.lo);
}
DD neg(DD a) { return {-a.hi, -a.lo}; }

// p(z) in double-double, and a proven bound on the error of the result: each Horner step
// v <- v z + a does two products and two sums per component, each with an error below
// 4 u^2 times the magnitudes involved, which are bounded by S = sum |a_k| |z|_1^k
// (|z|_1 = |Re z| + |Im z| >= the factor |z| picks up in a complex product).
struct Value {
  Complex v;     // the double-double value rounded to double
  double error;  // |v - p(z)| <= error
};

Value eval_certified(const std::vector<double>& c, Complex z) {
  const double zr = z.real(), zi = z.imag(), z1 = std::abs(zr) + std::abs(zi);
  DD vr{0.0, 0.0}, vi{0.0, 0.0};
  double s = 0.0;
  for (auto it = c.rbegin(); it != c.rend(); ++it) {
    const DD nr = add(add(mul(vr, zr), neg(mul(vi, zi))), DD{*it, 0.0});
    const DD ni = add(mul(vr, zi), mul(vi, zr));
    vr = nr;
    vi = ni;
    s = s * z1 + std::abs(*it);
  }
  const Complex v(vr.hi + vr.lo, vi.hi + vi.lo);
  const double n = static_cast<double>(c.size());
  // 16 (n + 1) u^2 S for the double-double steps (generous: 14 u^2 per step suffices),
  // the final rounding to double (u |v| per component), S itself rounded up by 1.01.
  const double err = 16.0 * (n + 1.0) * kU * kU * s * 1.01 + 2.0 * kU * (std::abs(v.real()) + std::abs(v.imag()));
  return {v, err};
}

Complex eval_derivative(const std::vector<double>& c, Complex z) {
  Complex v(0.0), d(0.0);
  for (auto it = c.rbegin(); it != c.rend(); ++it) {
    d = d * z + v;
    v = v * z + *it;
  }
  return d;
}

// Starting values: the eigenvalues of the balanced companion matrix.
std::vector<Complex> companion_roots(const std::vector<double>& q) {
  const int n = static_cast<int>(q.size()) - 1;
  Matrix comp = Matrix::Zero(n, n);
  for (int j = 0; j < n; ++j) comp(0, j) = -q[static_cast<size_t>(n - 1 - j)] / q[static_cast<size_t>(n)];
  for (int i = 1; i < n; ++i) comp(i, i - 1) = 1.0;
  const Vector d = balancing_scales(comp);
  const Matrix bal = d.cwiseInverse().asDiagonal() * comp * d.asDiagonal();
  Eigen::EigenSolver<Matrix> es(bal, false);
  if (es.info() != Eigen::Success) throw InputError("polynomial root finding did not converge");
  std::vector<Complex> z(es.eigenvalues().data(), es.eigenvalues().data() + n);
  // Aberth's iteration needs distinct starting values.
  for (size_t i = 0; i < z.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (z[i] == z[j]) z[i] += std::polar(1e-8 * std::max(std::abs(z[i]), 1e-300), 2.0 * static_cast<double>(i));
  return z;
}

// Aberth-Ehrlich: all roots refined together (clusters included), the residual in
// double-double so that the approximations converge to the doubles nearest the roots.
void aberth(const std::vector<double>& q, std::vector<Complex>& z) {
  const size_t n = z.size();
  for (int it = 0; it < 60; ++it) {
    double worst = 0.0;
    for (size_t i = 0; i < n; ++i) {
      const Complex pv = eval_certified(q, z[i]).v;
      if (pv == Complex(0.0)) continue;
      const Complex dp = eval_derivative(q, z[i]);
      Complex s(0.0);
      for (size_t j = 0; j < n; ++j)
        if (j != i) s += 1.0 / (z[i] - z[j]);
      const Complex ratio = pv / dp;
      const Complex w = ratio / (1.0 - ratio * s);
      if (!std::isfinite(w.real()) || !std::isfinite(w.imag())) continue;
      z[i] -= w;
      worst = std::max(worst, std::abs(w) / std::max(std::abs(z[i]), std::numeric_limits<double>::min()));
    }
    if (worst <= 4.0 * kU) break;
  }
}

// |prod_{j != i} (z_i - z_j)| * |a_n| bounded below, in logarithms (no overflow), each
// |z_i - z_j| rounded at most 3 u (subtraction, hypot), the logs and sum at most 2 u
// each relative: taken 8 u (n + 2) smaller.
double log_denominator_lower(const std::vector<Complex>& z, size_t i, double lead) {
  double lg = std::log(std::abs(lead));
  for (size_t j = 0; j < z.size(); ++j) {
    if (j == i) continue;
    const double d = std::abs(z[i] - z[j]);
    if (d == 0.0) return -std::numeric_limits<double>::infinity();
    lg += std::log(d);
  }
  return lg - 8.0 * kU * (static_cast<double>(z.size()) + 2.0) * (1.0 + std::abs(lg));
}

}  // namespace

std::vector<RootCluster> enclose_roots(const Polynomial& p) {
  if (p.degree() < 1) return {};
  std::vector<RootCluster> out;
  const int nz = p.zero_roots();
  if (nz > 0) out.push_back({std::vector<Complex>(static_cast<size_t>(nz), Complex(0.0)), std::vector<double>(static_cast<size_t>(nz), 0.0)});
  const std::vector<double> q(p.coeffs().begin() + nz, p.coeffs().end());
  const size_t n = q.size() - 1;
  if (n == 0) return out;
  std::vector<Complex> z = companion_roots(q);
  aberth(q, z);
  // The discs need distinct centres: Aberth's iteration lands several approximations of
  // a root that is exactly a double on it. Any distinct points give valid discs.
  for (size_t i = 0; i < z.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (z[i] == z[j]) z[i] += std::polar(1e-10 * std::max(std::abs(z[i]), 1e-300), 2.0 * static_cast<double>(i));
  std::vector<double> r(n);
  const double nd = static_cast<double>(n);
  for (size_t i = 0; i < n; ++i) {
    const Value v = eval_certified(q, z[i]);
    const double num = (std::abs(v.v) * (1.0 + 4.0 * kU) + v.error) * (1.0 + 4.0 * kU);
    const double lden = log_denominator_lower(z, i, q.back());
    // n |W_i|, rounded up (exp and the product: a relative 1e-12 is far above their error).
    r[i] = num == 0.0 ? 0.0 : nd * std::exp(std::log(num) - lden) * (1.0 + 1e-12);
    if (!std::isfinite(r[i])) r[i] = std::numeric_limits<double>::infinity();
  }
  // Connected components of the discs (union-find); touching counts as connected, and
  // the distance is taken 1e-12 shorter, so rounding can only merge, never split.
  std::vector<size_t> parent(n);
  std::iota(parent.begin(), parent.end(), size_t{0});
  auto find = [&parent](size_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j)
      if (std::abs(z[i] - z[j]) * (1.0 - 1e-12) <= r[i] + r[j]) parent[find(i)] = find(j);
  std::vector<int> index(n, -1);
  for (size_t i = 0; i < n; ++i) {
    const size_t root = find(i);
    if (index[root] < 0) {
      index[root] = static_cast<int>(out.size());
      out.push_back({});
    }
    RootCluster& c = out[static_cast<size_t>(index[root])];
    c.centers.push_back(z[i]);
    c.radii.push_back(r[i]);
  }
  return out;
}

Side side_of(const RootCluster& c, bool discrete) {
  bool inside = true, outside = true;
  for (int k = 0; k < c.size(); ++k) {
    const Complex z = c.centers[static_cast<size_t>(k)];
    const double r = c.radii[static_cast<size_t>(k)];
    if (!std::isfinite(r)) return Side::Straddles;
    if (discrete) {
      // x = |z| - 1 and a bound R on |x - (|z| - 1)| + r: then the sign of x -+ R, which
      // a rounded sum keeps, decides. |z| is exact for a real z, from hypot within 1 ulp;
      // |z| - 1 is exact for |z| in [1/2, 2] (Sterbenz) and within u |x| otherwise.
      const bool real = z.imag() == 0.0;
      const double m = real ? std::abs(z.real()) : std::abs(z);
      const double x = m - 1.0;
      const double bound = (r + (real ? 0.0 : 2.0 * kU * m) + kU * std::abs(x)) * (1.0 + 4.0 * kU);
      inside = inside && x + bound < 0.0;
      outside = outside && x - bound > 0.0;
    } else {
      // z.real() is exact; r an upper bound; the sign of a rounded sum is the exact one's.
      inside = inside && z.real() + r < 0.0;
      outside = outside && z.real() - r > 0.0;
    }
  }
  return inside ? Side::Inside : outside ? Side::Outside : Side::Straddles;
}

namespace {

// Whether the sum of the values is exactly zero: Shewchuk's error-free expansion.
bool sums_to_zero(const std::vector<double>& values) {
  std::vector<double> parts;
  for (double x : values) {
    size_t k = 0;
    for (double y : parts) {
      const DD s = two_sum(x, y);
      if (s.lo != 0.0) parts[k++] = s.lo;
      x = s.hi;
    }
    parts.resize(k);
    parts.push_back(x);
  }
  for (double v : parts)
    if (v != 0.0) return false;
  return true;
}

}  // namespace

int exact_roots_at(const Polynomial& p, double x0) {
  if (p.is_zero()) return 0;
  if (x0 == 0.0) return p.zero_roots();
  if (x0 != 1.0) throw InputError("exact_roots_at: the boundary point is 0 or 1");
  Polynomial q = p;
  int m = 0;
  while (q.degree() >= 1 && sums_to_zero(q.coeffs())) {
    q = deflated(q, 1.0, 1);
    ++m;
  }
  return m;
}

Polynomial deflated(const Polynomial& p, double x0, int m) {
  Polynomial q = p;
  for (int k = 0; k < m && q.degree() >= 1; ++k) {
    const std::vector<double>& c = q.coeffs();
    const int n = q.degree();
    std::vector<double> d(static_cast<size_t>(n));
    double carry = 0.0;
    for (int j = n; j >= 1; --j) {
      carry = c[static_cast<size_t>(j)] + x0 * carry;
      d[static_cast<size_t>(j - 1)] = carry;
    }
    q = Polynomial(std::move(d));
  }
  return q;
}

}  // namespace dmbd::blocks
