#include "dmbd/blocks/state_space.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <string>

#include "dmbd/blocks/certified_stability.hpp"
#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/root_enclosure.hpp"
#include "tolerance.hpp"

namespace dmbd::blocks {

namespace {

std::string dims(const Matrix& m) { return std::to_string(m.rows()) + "x" + std::to_string(m.cols()); }

Matrix blkdiag(const Matrix& a, const Matrix& b) {
  Matrix m = Matrix::Zero(a.rows() + b.rows(), a.cols() + b.cols());
  m.topLeftCorner(a.rows(), a.cols()) = a;
  m.bottomRightCorner(b.rows(), b.cols()) = b;
  return m;
}

// Orthonormal basis of the Krylov space span[B, AB, A^2 B, ...].
Matrix krylov_basis(const Matrix& a, const Matrix& b, double tol) {
  const int n = static_cast<int>(a.rows());
  Matrix q(n, 0);
  Matrix r = b;
  const double scale = std::max({a.norm(), b.norm(), 1e-300});
  for (int k = 0; k < n && q.cols() < n && r.cols() > 0; ++k) {
    for (int pass = 0; pass < 2; ++pass) r -= q * (q.transpose() * r);
    Eigen::JacobiSVD<Matrix> svd(r, Eigen::ComputeThinU);
    const auto& sv = svd.singularValues();
    int keep = 0;
    while (keep < sv.size() && sv(keep) > tol * scale && q.cols() + keep < n) ++keep;
    if (keep == 0) break;
    Matrix next(n, q.cols() + keep);
    next << q, svd.matrixU().leftCols(keep);
    q = next;
    r = a * svd.matrixU().leftCols(keep);
  }
  return q;
}

}  // namespace

StateSpace::StateSpace(Matrix a, Matrix b, Matrix c, Matrix d, double ts)
    : a_(std::move(a)), b_(std::move(b)), c_(std::move(c)), d_(std::move(d)), ts_(ts) {
  if (!(ts >= 0.0) || !std::isfinite(ts)) throw InputError("sample time must be a finite number >= 0");
  const auto n = a_.rows();
  if (a_.cols() != n) throw InputError("state-space A must be square, got " + dims(a_));
  if (b_.rows() != n) throw InputError("state-space B must have " + std::to_string(n) + " rows (A is " + dims(a_) +
                                       "), got " + dims(b_));
  if (c_.cols() != n) throw InputError("state-space C must have " + std::to_string(n) + " columns (A is " +
                                       dims(a_) + "), got " + dims(c_));
  if (d_.rows() != c_.rows() || d_.cols() != b_.cols())
    throw InputError("state-space D must be " + std::to_string(c_.rows()) + "x" + std::to_string(b_.cols()) +
                     " (outputs x inputs), got " + dims(d_));
  if (!a_.allFinite() || !b_.allFinite() || !c_.allFinite() || !d_.allFinite())
    throw InputError("state-space matrices must be finite");
}

StateSpace StateSpace::gain(const Matrix& d, double ts) {
  return StateSpace(Matrix(0, 0), Matrix(0, d.cols()), Matrix(d.rows(), 0), d, ts);
}

StateSpace StateSpace::from_tf(const TransferFunction& tf) {
  if (!tf.is_proper())
    throw InputError("an improper transfer function (numerator degree " + std::to_string(tf.num().degree()) +
                     " > denominator degree " + std::to_string(tf.den().degree()) + ") has no state-space realisation");
  // den = (x - x0)^k q: q(x) eta = u in controllable canonical form (states eta^(r-1) ..
  // eta), then zeta_j = eta / (x - x0)^j through k states with A(j, j) = x0 exactly.
  const double x0 = tf.is_discrete() ? 1.0 : 0.0;
  const TransferFunction::Split split = tf.split_den();  // exact roots at x0, factor by factor
  const Polynomial& q = split.rest;                       // monic, as den
  const int k = split.m;
  const int r = q.degree(), n = r + k;
  // num = (x - x0)^k beta + sum_j alpha_j (x - x0)^j (Taylor coefficients at x0), so
  // y = num xi = beta(x) eta + sum_j alpha_j zeta_(k-j), xi = zeta_k.
  Polynomial beta = tf.num();
  std::vector<double> alpha(static_cast<size_t>(k));
  for (int j = 0; j < k; ++j) {
    const auto [quot, rem] = Polynomial::divide(beta, Polynomial({-x0, 1.0}));
    alpha[static_cast<size_t>(j)] = rem[0];
    beta = quot;
  }
  const double d = beta[r];  // eta^(r) = u - sum q_i eta^(i)
  Matrix a = Matrix::Zero(n, n), b = Matrix::Zero(n, 1), c = Matrix::Zero(1, n), dm(1, 1);
  for (int i = 0; i < r; ++i) {
    a(0, i) = -q[r - 1 - i];
    c(0, i) = beta[r - 1 - i] - d * q[r - 1 - i];
    if (i > 0) a(i, i - 1) = 1.0;
  }
  for (int j = 1; j <= k; ++j) {
    const int s = r + j - 1;
    a(s, s) = x0;
    if (s > 0) a(s, s - 1) = 1.0;
    c(0, s) = alpha[static_cast<size_t>(k - j)];
  }
  if (n > 0) b(0, 0) = 1.0;  // e_0' = u, or zeta_1' = x0 zeta_1 + u when r = 0
  dm(0, 0) = d;
  return StateSpace(a, b, c, dm, tf.ts()).balanced();
}

TransferFunction StateSpace::to_tf(int out, int in) const {
  if (out < 0 || out >= num_outputs() || in < 0 || in >= num_inputs())
    throw InputError("no channel from input " + std::to_string(in) + " to output " + std::to_string(out));
  if (num_states() == 0) return TransferFunction(d_(out, in), ts_);
  const std::vector<Complex> ev = poles();
  return TransferFunction(numerator(ev, out, in), Polynomial::from_roots(ev, 1.0), ts_);
}

Polynomial StateSpace::numerator(const std::vector<Complex>& ev, int out, int in) const {
  if (out < 0 || out >= num_outputs() || in < 0 || in >= num_inputs())
    throw InputError("no channel from input " + std::to_string(in) + " to output " + std::to_string(out));
  const int n = num_states();
  if (static_cast<int>(ev.size()) != n)
    throw InputError("numerator: " + std::to_string(ev.size()) + " poles given for " + std::to_string(n) + " states");
  const double d = d_(out, in);
  if (n == 0) return Polynomial::constant(d);
  // Numerator by interpolation: num(x_k) = G(x_k) * prod(x_k - lambda_i) at n+1 points
  // on a circle, then an inverse DFT. Every value is computed to full relative
  // precision (G by a linear solve, the determinant in product form), so the
  // coefficients are accurate relative to the numerator's own size; the formula
  // det(sI-A+BC) - det(sI-A) loses everything when the numerator is small against
  // the denominator (e.g. ZOH of a slow high-order system).
  // Radius: the geometric mean of the pole magnitudes, leaving out poles at the origin
  // (integrators come out of the eigenvalue solver as +-1e-16 or, for a double
  // integrator, +-1e-8: they must not shrink the circle).
  // "At the origin" is judged against the size of A itself, so that a system whose
  // only poles are integrators (1/s^2 recovered from a matrix logarithm) is not
  // interpolated on a circle of radius 1e-8.
  double r = 1.0;
  if (!is_discrete()) {
    double scale = balanced().a().norm();
    for (const Complex& p : ev) scale = std::max(scale, std::abs(p));
    double logsum = 0.0;
    int count = 0;
    for (const Complex& p : ev)
      if (std::abs(p) > 1e-6 * scale) logsum += std::log(std::abs(p)), ++count;
    if (count > 0) {
      r = std::exp(logsum / count);
    } else if (scale > 0.0) {
      r = scale;
    }
  }
  const int np = n + 1;
  const double offset = 0.318309886;  // fraction of a step: keeps the points off real poles and z = 1
  const Matrix bi = b_.col(in);
  const Matrix co = c_.row(out);
  std::vector<Complex> values(static_cast<size_t>(np));
  double biggest = 0.0;
  for (int k = 0; k < np; ++k) {
    const Complex x = std::polar(r, 2.0 * M_PI * (k + offset) / np);
    Eigen::MatrixXcd m = x * Eigen::MatrixXcd::Identity(n, n) - a_.cast<Complex>();
    const Complex g = (co.cast<Complex>() * Eigen::PartialPivLU<Eigen::MatrixXcd>(m).solve(bi.cast<Complex>()))(0, 0) + d;
    Complex det(1.0);
    for (const Complex& l : ev) det *= x - l;
    values[static_cast<size_t>(k)] = g * det;
    biggest = std::max(biggest, std::abs(values[static_cast<size_t>(k)]));
  }
  std::vector<double> c(static_cast<size_t>(np));
  for (int j = 0; j < np; ++j) {
    Complex acc(0.0);
    for (int k = 0; k < np; ++k) acc += values[static_cast<size_t>(k)] * std::polar(1.0, -2.0 * M_PI * j * (k + offset) / np);
    c[static_cast<size_t>(j)] = acc.real() / np / std::pow(r, j);
  }
  // Coefficients at rounding level relative to the numerator's size on the circle are
  // zeros (CB = 0 for a relative degree of 2, a zero at the origin): make them exact.
  for (int j = 0; j < np; ++j)
    if (std::abs(c[static_cast<size_t>(j)]) * std::pow(r, j) <= 1e-12 * biggest) c[static_cast<size_t>(j)] = 0.0;
  return Polynomial(std::move(c));
}

std::vector<Complex> StateSpace::poles() const {
  std::vector<Complex> ev;
  for (const std::vector<int>& g : state_groups(a_)) {
    Matrix block(g.size(), g.size());
    for (size_t i = 0; i < g.size(); ++i)
      for (size_t j = 0; j < g.size(); ++j) block(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = a_(g[i], g[j]);
    const std::vector<Complex> part = group_eigenvalues(block, is_discrete());
    ev.insert(ev.end(), part.begin(), part.end());
  }
  sort_roots(ev);
  return ev;
}

bool StateSpace::is_stable() const {
  for (const Complex& p : poles())
    if (is_discrete() ? !(std::abs(p) < 1.0) : !(p.real() < 0.0)) return false;
  return true;
}

Matrix StateSpace::dc_gain() const {
  if (num_states() == 0) return d_;
  // A pole at DC is decided on the eigenvalues (relative to the size of A), not on LU
  // pivots, which a badly scaled but regular A can make tiny.
  const StateSpace bal = balanced();
  double scale = 1.0;
  const std::vector<Complex> ev = poles();
  for (const Complex& p : ev) scale = std::max(scale, std::abs(p));
  for (const Complex& p : ev)
    if (std::abs(is_discrete() ? p - 1.0 : p) <= 1e-12 * scale)
      throw InputError("the system has a pole at DC: its steady-state gain is infinite");
  const int n = num_states();
  const Matrix m = is_discrete() ? Matrix(Matrix::Identity(n, n) - bal.a_) : Matrix(-bal.a_);
  return d_ + bal.c_ * Eigen::PartialPivLU<Matrix>(m).solve(bal.b_);
}

Eigen::MatrixXcd StateSpace::evaluate(Complex x) const {
  const int n = num_states();
  if (n == 0) return d_.cast<Complex>();
  Eigen::MatrixXcd m = x * Eigen::MatrixXcd::Identity(n, n) - a_.cast<Complex>();
  return c_.cast<Complex>() * Eigen::PartialPivLU<Eigen::MatrixXcd>(m).solve(b_.cast<Complex>()) +
         d_.cast<Complex>();
}

StateSpace StateSpace::minimal(double tol) const {
  require_tolerance(tol, "minimal");
  if (num_states() == 0) return *this;
  const StateSpace bal = balanced();
  const Matrix qc = krylov_basis(bal.a_, bal.b_, tol);
  const Matrix ac = qc.transpose() * bal.a_ * qc, bc = qc.transpose() * bal.b_, cc = bal.c_ * qc;
  const Matrix qo = krylov_basis(ac.transpose(), cc.transpose(), tol);
  return StateSpace(qo.transpose() * ac * qo, qo.transpose() * bc, cc * qo, d_, ts_);
}

StateSpace StateSpace::transformed(const Matrix& t) const {
  if (t.rows() != num_states() || t.cols() != num_states())
    throw InputError("similarity transform must be " + std::to_string(num_states()) + "x" +
                     std::to_string(num_states()));
  Eigen::FullPivLU<Matrix> lu(t);
  if (!lu.isInvertible()) throw InputError("similarity transform is singular");
  return StateSpace(lu.solve(a_ * t), lu.solve(b_), c_ * t, d_, ts_);
}

StateSpace StateSpace::balanced() const {
  if (num_states() == 0) return *this;
  const Vector d = balancing_scales(a_);
  return StateSpace(d.cwiseInverse().asDiagonal() * a_ * d.asDiagonal(), d.cwiseInverse().asDiagonal() * b_,
                    c_ * d.asDiagonal(), d_, ts_);
}

StateSpace StateSpace::select(const std::vector<int>& outputs, const std::vector<int>& inputs) const {
  Matrix b(num_states(), static_cast<Eigen::Index>(inputs.size())), c(static_cast<Eigen::Index>(outputs.size()), num_states()),
      d(static_cast<Eigen::Index>(outputs.size()), static_cast<Eigen::Index>(inputs.size()));
  for (size_t j = 0; j < inputs.size(); ++j) {
    if (inputs[j] < 0 || inputs[j] >= num_inputs()) throw InputError("input index out of range");
    b.col(static_cast<Eigen::Index>(j)) = b_.col(inputs[j]);
  }
  for (size_t i = 0; i < outputs.size(); ++i) {
    if (outputs[i] < 0 || outputs[i] >= num_outputs()) throw InputError("output index out of range");
    c.row(static_cast<Eigen::Index>(i)) = c_.row(outputs[i]);
    for (size_t j = 0; j < inputs.size(); ++j)
      d(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = d_(outputs[i], inputs[j]);
  }
  return StateSpace(a_, b, c, d, ts_);
}

StateSpace series(const StateSpace& first, const StateSpace& second) {
  require_same_ts(first.ts(), second.ts(), "series connection");
  if (second.num_inputs() != first.num_outputs())
    throw InputError("series connection: " + std::to_string(first.num_outputs()) + " outputs feed " +
                     std::to_string(second.num_inputs()) + " inputs");
  const int n1 = first.num_states(), n2 = second.num_states();
  Matrix a = Matrix::Zero(n1 + n2, n1 + n2);
  a.topLeftCorner(n1, n1) = first.a();
  a.bottomLeftCorner(n2, n1) = second.b() * first.c();
  a.bottomRightCorner(n2, n2) = second.a();
  Matrix b(n1 + n2, first.num_inputs());
  b << first.b(), second.b() * first.d();
  Matrix c(second.num_outputs(), n1 + n2);
  c << second.d() * first.c(), second.c();
  return StateSpace(a, b, c, second.d() * first.d(), first.ts());
}

StateSpace parallel(const StateSpace& x, const StateSpace& y) {
  require_same_ts(x.ts(), y.ts(), "parallel connection");
  if (x.num_inputs() != y.num_inputs() || x.num_outputs() != y.num_outputs())
    throw InputError("parallel connection: systems have different numbers of inputs or outputs");
  Matrix b(x.num_states() + y.num_states(), x.num_inputs());
  b << x.b(), y.b();
  Matrix c(x.num_outputs(), x.num_states() + y.num_states());
  c << x.c(), y.c();
  return StateSpace(blkdiag(x.a(), y.a()), b, c, x.d() + y.d(), x.ts());
}

StateSpace append(const StateSpace& x, const StateSpace& y) {
  require_same_ts(x.ts(), y.ts(), "append");
  return StateSpace(blkdiag(x.a(), y.a()), blkdiag(x.b(), y.b()), blkdiag(x.c(), y.c()), blkdiag(x.d(), y.d()),
                    x.ts());
}

StateSpace feedback(const StateSpace& f, const StateSpace& h, int sign) {
  require_same_ts(f.ts(), h.ts(), "feedback connection");
  if (h.num_inputs() != f.num_outputs() || h.num_outputs() != f.num_inputs())
    throw InputError("feedback connection: the feedback path must map the " + std::to_string(f.num_outputs()) +
                     " outputs back to the " + std::to_string(f.num_inputs()) + " inputs");
  const double s = static_cast<double>(sign);
  const int ny = f.num_outputs(), nu = f.num_inputs(), nf = f.num_states(), nh = h.num_states();
  const Matrix m = Matrix::Identity(ny, ny) - s * f.d() * h.d();
  Eigen::FullPivLU<Matrix> lu(m);
  lu.setThreshold(1e-12);
  if (!lu.isInvertible())
    throw InputError("algebraic loop: I - sign*D_forward*D_feedback is singular, the feedback connection is ill-posed");
  Matrix cx(ny, nf + nh);
  cx << f.c(), s * f.d() * h.c();
  // Eigen's triangular solve binds a reference to the first coefficient even of an
  // empty right-hand side (a null pointer: undefined behaviour, found by UBSan when
  // neither system has states): solve only what is there.
  auto solve = [&lu](const Matrix& rhs) { return rhs.size() == 0 ? Matrix(lu.rows(), rhs.cols()) : Matrix(lu.solve(rhs)); };
  const Matrix cy = solve(cx);  // y = Cy x + Dy r
  const Matrix dy = solve(f.d());
  Matrix cu0 = Matrix::Zero(nu, nf + nh);
  cu0.rightCols(nh) = s * h.c();
  const Matrix cu = cu0 + s * h.d() * cy;  // u = Cu x + Du r
  const Matrix du = Matrix::Identity(nu, nu) + s * h.d() * dy;
  Matrix a = blkdiag(f.a(), h.a());
  a.topRows(nf) += f.b() * cu;
  a.bottomRows(nh) += h.b() * cy;
  Matrix b(nf + nh, nu);
  b << f.b() * du, h.b() * dy;
  return StateSpace(a, b, cy, dy, f.ts());
}

// Tarjan's algorithm without recursion (a chain of 10^5 blocks would overflow the
// stack): `call` holds the depth-first path with each node's next edge. Nodes, edges and
// components are visited in the same order as the recursive formulation.
std::vector<std::vector<int>> strongly_connected_components(const std::vector<std::vector<int>>& dep) {
  const size_t n = dep.size();
  std::vector<int> index(n, -1), low(n, 0), stack;
  std::vector<bool> on(n, false);
  std::vector<std::vector<int>> comps;  // in the order Tarjan closes them: dependencies first
  std::vector<std::pair<size_t, size_t>> call;
  int counter = 0;
  auto open = [&](size_t v) {
    index[v] = low[v] = counter++;
    stack.push_back(static_cast<int>(v));
    on[v] = true;
    call.emplace_back(v, 0);
  };
  for (size_t root = 0; root < n; ++root) {
    if (index[root] >= 0) continue;
    open(root);
    while (!call.empty()) {
      const size_t v = call.back().first;
      if (call.back().second < dep[v].size()) {
        const auto w = static_cast<size_t>(dep[v][call.back().second++]);
        if (index[w] < 0) {
          open(w);
        } else if (on[w]) {
          low[v] = std::min(low[v], index[w]);
        }
        continue;
      }
      call.pop_back();
      if (!call.empty()) low[call.back().first] = std::min(low[call.back().first], low[v]);
      if (low[v] != index[v]) continue;
      std::vector<int> comp;
      int w;
      do {
        w = stack.back();
        stack.pop_back();
        on[static_cast<size_t>(w)] = false;
        comp.push_back(w);
      } while (w != static_cast<int>(v));
      comps.push_back(std::move(comp));
    }
  }
  return comps;
}

Matrix solve_in_dependency_order(const Matrix& g, const Matrix& r) {
  const int n = static_cast<int>(g.rows());
  std::vector<std::vector<int>> dep(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (g(i, j) != 0.0) dep[static_cast<size_t>(i)].push_back(j);
  const std::vector<std::vector<int>> comps = strongly_connected_components(dep);
  Matrix u = Matrix::Zero(n, r.cols());
  std::vector<bool> done(static_cast<size_t>(n), false);
  for (const auto& comp : comps) {
    const int k = static_cast<int>(comp.size());
    // Right-hand side with the already solved entries substituted.
    Matrix rhs(k, r.cols());
    Matrix block = Matrix::Identity(k, k);
    for (int a = 0; a < k; ++a) {
      const int i = comp[static_cast<size_t>(a)];
      rhs.row(a) = r.row(i);
      for (int j : dep[static_cast<size_t>(i)]) {
        if (done[static_cast<size_t>(j)]) {
          rhs.row(a) += g(i, j) * u.row(j);
        } else {
          const auto it = std::find(comp.begin(), comp.end(), j);
          block(a, static_cast<int>(it - comp.begin())) -= g(i, j);
        }
      }
    }
    Matrix x;
    if (k == 1) {
      if (!(std::abs(block(0, 0)) > 1e-12))
        throw InputError("algebraic loop: a direct-feedthrough path around a loop has gain 1");
      x = rhs / block(0, 0);
    } else {
      Eigen::FullPivLU<Matrix> lu(block);
      if (!(std::abs(lu.determinant()) > 1e-12))
        throw InputError("algebraic loop: the direct-feedthrough path around a loop has gain 1 (I - M D is singular)");
      x = lu.solve(rhs);
    }
    for (int a = 0; a < k; ++a) {
      u.row(comp[static_cast<size_t>(a)]) = x.row(a);
      done[static_cast<size_t>(comp[static_cast<size_t>(a)])] = true;
    }
  }
  return u;
}

Vector balancing_scales(const Matrix& m) {
  const int n = static_cast<int>(m.rows());
  Matrix a = m;
  Vector scale = Vector::Ones(n);
  constexpr double radix = 2.0, sqrdx = radix * radix;
  bool done = false;
  for (int sweep = 0; !done && sweep < 100; ++sweep) {
    done = true;
    for (int i = 0; i < n; ++i) {
      double r = 0.0, c = 0.0;
      for (int j = 0; j < n; ++j)
        if (j != i) {
          c += std::abs(a(j, i));
          r += std::abs(a(i, j));
        }
      if (c == 0.0 || r == 0.0) continue;
      double g = r / radix, f = 1.0;
      const double s = c + r;
      while (c < g) f *= radix, c *= sqrdx;
      g = r * radix;
      while (c > g) f /= radix, c /= sqrdx;
      if ((c + r) / f < 0.95 * s) {
        done = false;
        scale(i) *= f;
        a.row(i) /= f;
        a.col(i) *= f;
      }
    }
  }
  return scale;
}

std::vector<std::vector<int>> state_groups(const Matrix& a) {
  const auto n = a.rows();
  std::vector<std::vector<int>> dep(static_cast<size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j)
      if (i != j && a(i, j) != 0.0) dep[static_cast<size_t>(i)].push_back(static_cast<int>(j));
  return strongly_connected_components(dep);
}

std::vector<Complex> group_eigenvalues(const Matrix& block, bool discrete) {
  const auto n = block.rows();
  if (n == 0) return {};
  if (n == 1) return {Complex(block(0, 0), 0.0)};
  if (const std::optional<Polynomial> p = companion_polynomial(block)) {
    // A transfer function's realisation: the roots of its exact characteristic
    // polynomial, those at the boundary point only when exactly there (no tolerance).
    const double x0 = discrete ? 1.0 : 0.0;
    const int m = exact_roots_at(*p, x0);
    std::vector<Complex> ev = deflated(*p, x0, m).roots();
    for (Complex& z : ev)
      if (z == Complex(x0, 0.0)) z = Complex(std::nextafter(x0, -1.0), 0.0);  // rounded onto it: not exactly there
    ev.insert(ev.end(), static_cast<size_t>(m), Complex(x0, 0.0));
    return ev;
  }
  const Vector d = balancing_scales(block);
  const Matrix bal = d.cwiseInverse().asDiagonal() * block * d.asDiagonal();
  Eigen::EigenSolver<Matrix> es(bal, false);
  if (es.info() != Eigen::Success) throw InputError("eigenvalue computation did not converge");
  std::vector<Complex> ev(es.eigenvalues().data(), es.eigenvalues().data() + n);
  // Rounding leaves an integrator inside a group at about 1e-16 times the group's norm:
  // snap what lies within 1e-10 of it (see StateSpace::poles()).
  const double x0 = discrete ? 1.0 : 0.0;
  const double tol = 1e-10 * std::max(bal.norm(), discrete ? 1.0 : 0.0);
  for (Complex& p : ev)
    if (std::abs(p - x0) <= tol) p = Complex(x0, 0.0);
  return ev;
}

void sort_roots(std::vector<Complex>& roots) {
  std::sort(roots.begin(), roots.end(), [](const Complex& x, const Complex& y) {
    return x.real() != y.real() ? x.real() < y.real() : x.imag() < y.imag();
  });
}

}  // namespace dmbd::blocks
