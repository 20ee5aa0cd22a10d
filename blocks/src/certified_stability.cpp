// Certified stability verdicts (certified_stability.hpp).
#include "dmbd/blocks/certified_stability.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>

namespace dmbd::blocks {

namespace {

constexpr double kU = std::numeric_limits<double>::epsilon() / 2.0;

// Whether every root of f (no root at the boundary point left) lies exactly on the
// boundary, by the form of its coefficients alone.
bool on_boundary_by_form(const Polynomial& f, bool discrete) {
  if (f.degree() == 1) return discrete && f[0] == f[1];  // z + 1 (times a constant)
  if (f.degree() != 2) return false;
  if (!discrete) return f[1] == 0.0 && f[0] * f[2] > 0.0;  // a s^2 + c: s = +-j sqrt(c/a)
  // a z^2 + b z + a with b^2 < 4 a^2: a conjugate pair whose product is exactly 1.
  return f[0] == f[2] && std::abs(f[1]) < 2.0 * std::abs(f[2]);
}

bool power_of_two(double x) {
  int e = 0;
  return x != 0.0 && std::isfinite(x) && std::abs(std::frexp(x, &e)) == 0.5;
}

double inf_norm(const Eigen::MatrixXd& m) { return m.rows() == 0 ? 0.0 : m.rowwise().sum().maxCoeff(); }

}  // namespace

std::optional<Polynomial> companion_polynomial(const Matrix& a) {
  const Eigen::Index n = a.rows();
  std::vector<Eigen::Index> source(static_cast<size_t>(n), -1);  // row i's one column
  Eigen::Index full = -1;
  for (Eigen::Index i = 0; i < n; ++i) {
    int count = 0;
    for (Eigen::Index j = 0; j < n; ++j)
      if (a(i, j) != 0.0) {
        ++count;
        source[static_cast<size_t>(i)] = j;
      }
    if (count == 1 && source[static_cast<size_t>(i)] != i) continue;
    if (full >= 0) return std::nullopt;
    full = i;
  }
  if (full < 0) return std::nullopt;
  std::vector<double> c(static_cast<size_t>(n) + 1, 0.0);
  c[static_cast<size_t>(n)] = 1.0;
  Eigen::Index prev = full;
  double scale = 1.0;
  std::vector<bool> seen(static_cast<size_t>(n), false);
  for (Eigen::Index k = 0; k < n; ++k) {
    if (seen[static_cast<size_t>(prev)]) return std::nullopt;
    seen[static_cast<size_t>(prev)] = true;
    const double v = -a(full, prev) * scale;  // exact: scale is a power of two
    if (!std::isfinite(v) || (a(full, prev) != 0.0 && v == 0.0)) return std::nullopt;
    c[static_cast<size_t>(n - 1 - k)] = v;
    if (k + 1 == n) break;
    Eigen::Index next = -1;
    for (Eigen::Index i = 0; i < n; ++i)
      if (i != full && source[static_cast<size_t>(i)] == prev) next = i;
    if (next < 0) return std::nullopt;
    scale *= a(next, prev);
    if (!power_of_two(scale)) return std::nullopt;
    prev = next;
  }
  return Polynomial(std::move(c));
}


// D⁻¹ A D with D diagonal, its entries powers of two (so the similarity is exact and
// the eigenvalues are A's to the bit), chosen to make each row's and column's
// off-diagonal sums comparable (Parlett & Reinsch's balancing, as LAPACK's dgebal). A
// realisation's states differ in scale by up to 1e10 (radians against newtons): the
// eigenvectors of the unbalanced matrix are so ill-conditioned that the enclosure below
// widens past the boundary for well-damped poles (the paper's potentiometer loop).
Matrix balanced_exactly(Matrix a) {
  const Eigen::Index n = a.rows();
  for (bool changed = true; changed;) {
    changed = false;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double c = a.col(i).cwiseAbs().sum() - std::abs(a(i, i));
      const double r = a.row(i).cwiseAbs().sum() - std::abs(a(i, i));
      if (!(c > 0.0 && r > 0.0) || !std::isfinite(c) || !std::isfinite(r)) continue;
      double f = 1.0, cc = c, rr = r;
      while (cc < rr / 2.0) cc *= 2.0, rr /= 2.0, f *= 2.0;
      while (cc >= rr * 2.0) cc /= 2.0, rr *= 2.0, f /= 2.0;
      if ((cc + rr) < 0.95 * (c + r)) {
        a.col(i) *= f;
        a.row(i) /= f;
        changed = true;
      }
    }
  }
  return a;
}

std::vector<RootCluster> enclose_eigenvalues(const Matrix& unbalanced) {
  using CMatrix = Eigen::MatrixXcd;
  const Eigen::Index n = unbalanced.rows();
  if (n == 0) return {};
  const Matrix a = balanced_exactly(unbalanced);
  const RootCluster unknown{std::vector<Complex>(static_cast<size_t>(n), Complex(0.0)),
                            std::vector<double>(static_cast<size_t>(n), std::numeric_limits<double>::infinity())};
  Eigen::ComplexEigenSolver<CMatrix> es(a.cast<Complex>());
  if (es.info() != Eigen::Success) return {unknown};
  const CMatrix v = es.eigenvectors();
  const Eigen::PartialPivLU<CMatrix> lu(v);
  const CMatrix x = lu.inverse();
  if (!x.allFinite()) return {unknown};
  const CMatrix av = a.cast<Complex>() * v;
  const CMatrix m = x * av;
  const CMatrix f = x * v;
  const Eigen::MatrixXd ax = x.cwiseAbs(), aa = a.cwiseAbs(), avv = v.cwiseAbs();
  // Rounding of complex dot products of length n: at most (n + 2) sqrt(2) u... taken 4 (n + 2) u
  // (of the absolute products), and 1 % on the bounds themselves.
  const double g = 4.0 * (static_cast<double>(n) + 2.0) * kU * 1.01;
  const double e_m = 2.0 * g * inf_norm(ax * (aa * avv)) * 1.01;
  const double e_f = (inf_norm((CMatrix::Identity(n, n) - f).cwiseAbs()) + g * inf_norm(ax * avv)) * 1.01;
  if (!(e_f < 0.5)) return {unknown};
  const double m_norm = inf_norm(m.cwiseAbs()) * (1.0 + 4.0 * kU * static_cast<double>(n)) + e_m;
  const double delta = (e_m + e_f / (1.0 - e_f) * m_norm) * 1.01;
  std::vector<Complex> c(static_cast<size_t>(n));
  std::vector<double> r(static_cast<size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    double off = 0.0;
    for (Eigen::Index j = 0; j < n; ++j)
      if (j != i) off += std::abs(m(i, j));
    c[static_cast<size_t>(i)] = m(i, i);
    r[static_cast<size_t>(i)] = (off * (1.0 + 4.0 * kU * static_cast<double>(n)) + delta) * (1.0 + 1e-12);
  }
  // Connected components, as enclose_roots.
  std::vector<size_t> parent(static_cast<size_t>(n));
  std::iota(parent.begin(), parent.end(), size_t{0});
  auto find = [&parent](size_t k) {
    while (parent[k] != k) k = parent[k] = parent[parent[k]];
    return k;
  };
  for (size_t i = 0; i < c.size(); ++i)
    for (size_t j = i + 1; j < c.size(); ++j)
      if (std::abs(c[i] - c[j]) * (1.0 - 1e-12) <= r[i] + r[j]) parent[find(i)] = find(j);
  std::vector<int> index(c.size(), -1);
  std::vector<RootCluster> out;
  for (size_t i = 0; i < c.size(); ++i) {
    const size_t root = find(i);
    if (index[root] < 0) {
      index[root] = static_cast<int>(out.size());
      out.push_back({});
    }
    out[static_cast<size_t>(index[root])].centers.push_back(c[i]);
    out[static_cast<size_t>(index[root])].radii.push_back(r[i]);
  }
  return out;
}

void VerdictBuilder::add_clusters(const std::vector<RootCluster>& clusters) {
  for (const RootCluster& c : clusters) {
    const Side side = side_of(c, discrete_);
    outside_ = outside_ || side == Side::Outside;
    straddles_ = straddles_ || side == Side::Straddles;
  }
}

void VerdictBuilder::add_polynomial(const Polynomial& p, int multiplicity) {
  if (p.degree() < 1) return;
  const double x0 = discrete_ ? 1.0 : 0.0;
  const int m = exact_roots_at(p, x0);
  at_x0_ += m * multiplicity;
  const Polynomial rest = deflated(p, x0, m);
  if (rest.degree() < 1) return;
  if (on_boundary_by_form(rest, discrete_)) {
    const Polynomial monic = rest.monic();
    if (multiplicity > 1 || std::find(edge_factors_.begin(), edge_factors_.end(), monic) != edge_factors_.end())
      repeated_edge_ = true;
    edge_factors_.push_back(monic);
    return;
  }
  add_clusters(enclose_roots(rest));
}

void VerdictBuilder::add_matrix(const Matrix& a) {
  if (a.rows() == 0) return;
  if (a.rows() == 1) {
    add_polynomial(Polynomial({-a(0, 0), 1.0}));  // x - a, exact
    return;
  }
  if (const std::optional<Polynomial> p = companion_polynomial(a)) {
    add_polynomial(*p);
    return;
  }
  add_clusters(enclose_eigenvalues(a));
}

Stability VerdictBuilder::verdict(int cancelled) const {
  const int at_x0 = at_x0_ - cancelled;
  if (outside_ || repeated_edge_ || at_x0 >= 2) return Stability::Unstable;
  if (straddles_) return Stability::Undecided;
  return !edge_factors_.empty() || at_x0 == 1 ? Stability::Marginal : Stability::Stable;
}

Stability certified_stability(const FactorList& den, bool discrete, int cancelled) {
  VerdictBuilder v(discrete);
  for (const PolynomialFactor& f : den) v.add_polynomial(f.poly, f.multiplicity);
  return v.verdict(cancelled);
}

Stability certified_stability(const TransferFunction& g) {
  const int zeros_at_x0 = g.num().is_zero() ? 0 : g.split_num().m;
  const int poles_at_x0 = g.split_den().m;
  return certified_stability(g.den_factors(), g.is_discrete(), std::min(zeros_at_x0, poles_at_x0));
}

}  // namespace dmbd::blocks
