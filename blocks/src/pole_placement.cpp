#include "dmbd/blocks/pole_placement.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <string>

#include "dmbd/base/error.hpp"
#include "dmbd/blocks/schur_exponential.hpp"

namespace dmbd::blocks {

namespace {

using ComplexVector = Eigen::VectorXcd;

// A requested pole; the second of a complex pair takes the conjugate of its partner's
// eigenvector.
struct Slot {
  Complex p;
  Eigen::Index partner = -1;  // the other of a complex pair
  bool second = false;        // this slot's vector is conj(partner's)
};

std::vector<Slot> paired(const std::vector<Complex>& poles) {
  std::vector<Slot> s(poles.size());
  for (size_t j = 0; j < poles.size(); ++j) {
    if (!std::isfinite(poles[j].real()) || !std::isfinite(poles[j].imag()))
      throw InputError("poles: pole " + std::to_string(j) + " is not finite");
    s[j].p = poles[j];
  }
  for (size_t j = 0; j < s.size(); ++j) {
    if (s[j].p.imag() == 0.0 || s[j].partner >= 0) continue;
    for (size_t k = j + 1; k < s.size() && s[j].partner < 0; ++k)
      if (s[k].partner < 0 && std::abs(s[k].p - std::conj(s[j].p)) <= 1e-10 * std::abs(s[j].p)) {
        s[j].partner = static_cast<Eigen::Index>(k);
        s[k] = {std::conj(s[j].p), static_cast<Eigen::Index>(j), true};
      }
    if (s[j].partner < 0)
      throw InputError("poles: the complex pole " + std::to_string(s[j].p.real()) + (s[j].p.imag() < 0 ? "" : "+") +
                       std::to_string(s[j].p.imag()) + "j has no conjugate (the gain would not be real)");
  }
  return s;
}

// An orthonormal basis (n x m) of the eigenvectors x that A - BK can have for the pole p:
// U1'(A - pI) x = 0.
ComplexMatrix admissible(const Matrix& a, const Matrix& u1, Complex p, Eigen::Index m) {
  const Eigen::Index n = a.rows();
  if (u1.cols() == 0) return ComplexMatrix::Identity(n, n);
  if (p.imag() == 0.0) {
    const Matrix mj = u1.transpose() * (a - p.real() * Matrix::Identity(n, n));
    const Eigen::JacobiSVD<Matrix> svd(mj, Eigen::ComputeFullV);
    return svd.matrixV().rightCols(m).cast<Complex>();
  }
  const ComplexMatrix mj = u1.transpose().cast<Complex>() * (a.cast<Complex>() - p * ComplexMatrix::Identity(n, n));
  const Eigen::JacobiSVD<ComplexMatrix> svd(mj, Eigen::ComputeFullV);
  return svd.matrixV().rightCols(m);
}

// The unit vector of span(S) nearest the direction y: for a real pole the best real
// one (maximising |y* x| over real x), for a complex one the projection of y.
ComplexVector nearest(const ComplexMatrix& s, const ComplexVector& y, bool real) {
  if (real) {
    const Matrix sr = s.real();
    Matrix py(sr.cols(), 2);
    py << sr.transpose() * y.real(), sr.transpose() * y.imag();
    const Eigen::JacobiSVD<Matrix> svd(py, Eigen::ComputeThinU);
    return (sr * svd.matrixU().col(0)).cast<Complex>();
  }
  ComplexVector x = s * (s.adjoint() * y);
  const double norm = x.norm();
  return norm > 1e-12 ? ComplexVector(x / norm) : ComplexVector(s.col(0));
}

// A unit vector orthogonal to every column of X but column j.
ComplexVector orthogonal_to_others(const ComplexMatrix& x, Eigen::Index j) {
  const Eigen::Index n = x.rows();
  ComplexMatrix others(n, n - 1);
  others << x.leftCols(j), x.rightCols(n - 1 - j);
  const Eigen::HouseholderQR<ComplexMatrix> qr(others);
  return qr.householderQ() * ComplexVector::Unit(n, n - 1);
}

// |det X| of X with unit columns: 1 for orthogonal columns, 0 for dependent ones.
double volume(const ComplexMatrix& x) {
  const Eigen::HouseholderQR<ComplexMatrix> qr(x);
  double v = 1.0;
  for (Eigen::Index k = 0; k < x.cols(); ++k) v *= std::abs(qr.matrixQR()(k, k));
  return v;
}

void set_column(ComplexMatrix& x, const std::vector<Slot>& slots, Eigen::Index j, const ComplexVector& v) {
  x.col(j) = v;
  if (slots[static_cast<size_t>(j)].partner >= 0) x.col(slots[static_cast<size_t>(j)].partner) = v.conjugate();
}


// One input: poles deflated one at a time. For the pair (A, b) of order k and the pole p,
// the closed loop's eigenvector x spans the null space of U1*(A - pI) (U1 the complement
// of b; found by SVD, unique when controllable), and f x = u0*(A - pI) x / |b| (u0 = b/|b|)
// follows from (A - b f) x = p x. A unitary Q with Q e1 = x puts p in the corner of
// Q*(A - b f)Q, whose trailing block is the pair (Q*AQ)_22, (Q*b)_2.. under the gain
// (fQ)_2..: the same problem one order smaller. f = [f x, f_rest] Q*. Only unitary
// transformations and one division by |b| per pole: no controllability matrix, and a
// pole may repeat (its eigenvector is found anew in each deflated problem). In complex
// arithmetic; the gain is unique, so for a conjugate-closed set of poles it is real to
// rounding and its real part is taken.
Matrix deflated_single_input(const Matrix& a_in, const Matrix& b_in, const std::vector<Complex>& poles) {
  ComplexMatrix a = a_in.cast<Complex>();
  ComplexVector b = b_in.col(0).cast<Complex>();
  const double scale = a_in.cwiseAbs().maxCoeff() + b_in.cwiseAbs().maxCoeff();
  std::vector<ComplexMatrix> qs;
  std::vector<Complex> c;
  for (const Complex& p : poles) {
    const Eigen::Index k = a.rows();
    const double beta = b.norm();
    if (!(beta > 1e3 * std::numeric_limits<double>::epsilon() * scale))
      throw InputError("cannot place these poles: (A, B) is not controllable");
    if (k == 1) {
      c.push_back((a(0, 0) - p) / b(0));
      break;
    }
    const ComplexMatrix shifted = a - p * ComplexMatrix::Identity(k, k);
    const ComplexMatrix qb = Eigen::HouseholderQR<ComplexMatrix>(b).householderQ() * ComplexMatrix::Identity(k, k);
    const Eigen::JacobiSVD<ComplexMatrix> svd(qb.rightCols(k - 1).adjoint() * shifted, Eigen::ComputeFullV);
    const ComplexVector x = svd.matrixV().col(k - 1);
    c.push_back((b.adjoint() * shifted * x)(0) / (beta * beta));
    const Eigen::HouseholderQR<ComplexMatrix> qrx(x);
    ComplexMatrix q = qrx.householderQ() * ComplexMatrix::Identity(k, k);
    q.col(0) *= qrx.matrixQR()(0, 0);  // now Q e1 = x exactly (|R00| = |x| = 1)
    const ComplexMatrix qaq = q.adjoint() * a * q;
    a = qaq.bottomRightCorner(k - 1, k - 1);
    b = (q.adjoint() * b).tail(k - 1);
    qs.push_back(q);
  }
  ComplexVector f = ComplexVector::Constant(1, c.back());
  for (size_t i = qs.size(); i-- > 0;) {
    ComplexVector g(f.size() + 1);
    g << c[i], f;
    f = qs[i].conjugate() * g;  // the row [c_i, f] Q* as a column: conj(Q) g
  }
  return f.real().transpose();
}


// Several inputs: Kautsky–Nichols–Van Dooren's method 0 (header).
Matrix robust_multi_input(const Matrix& a, const Matrix& b, const std::vector<Slot>& slots, int& sweeps) {
  const Eigen::Index n = a.rows(), m = b.cols();
  const Eigen::HouseholderQR<Matrix> qr(b);
  const Matrix q = qr.householderQ() * Matrix::Identity(n, n);
  const Matrix z = qr.matrixQR().topRows(std::min(n, m)).triangularView<Eigen::Upper>();
  const double zmax = z.diagonal().cwiseAbs().maxCoeff();
  if (m > n || !(z.diagonal().cwiseAbs().minCoeff() > static_cast<double>(n) * std::numeric_limits<double>::epsilon() * zmax))
    throw InputError("B: expected full column rank (independent inputs)");
  const Matrix u0 = q.leftCols(m), u1 = q.rightCols(n - m);

  std::vector<ComplexMatrix> s(static_cast<size_t>(n));
  ComplexMatrix x(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const Slot& sl = slots[static_cast<size_t>(j)];
    if (sl.second) continue;
    s[static_cast<size_t>(j)] = admissible(a, u1, sl.p, m);
    ComplexVector start(n);  // a fixed generic direction
    for (Eigen::Index k = 0; k < n; ++k)
      start(k) = std::polar(1.0, 0.37 * static_cast<double>(k + 1) + 1.3 * static_cast<double>(j + 1)) + 0.5;
    set_column(x, slots, j, nearest(s[static_cast<size_t>(j)], start, sl.p.imag() == 0.0));
  }
  double v = volume(x);
  for (int sweep = 1; sweep <= 100; ++sweep) {
    for (Eigen::Index j = 0; j < n; ++j) {
      const Slot& sl = slots[static_cast<size_t>(j)];
      if (sl.second) continue;
      set_column(x, slots, j, nearest(s[static_cast<size_t>(j)], orthogonal_to_others(x, j), sl.p.imag() == 0.0));
    }
    sweeps = sweep;
    const double vn = volume(x);
    const bool settled = std::abs(vn - v) <= 1e-10 * vn;
    v = vn;
    if (settled) break;
  }
  const Eigen::JacobiSVD<ComplexMatrix> sv(x);
  const double smax = sv.singularValues()(0), smin = sv.singularValues()(n - 1);
  if (!(smin > 10.0 * static_cast<double>(n) * std::numeric_limits<double>::epsilon() * smax))
    throw InputError("cannot place these poles: the eigenvectors are dependent ((A, B) not controllable, or a pole "
                     "repeated more often than the " + std::to_string(m) + " independent inputs allow)");
  ComplexMatrix xl = x;
  for (Eigen::Index j = 0; j < n; ++j) xl.col(j) *= slots[static_cast<size_t>(j)].p;
  const Matrix closed = Eigen::PartialPivLU<ComplexMatrix>(x.transpose()).solve(xl.transpose()).transpose().real();
  return z.triangularView<Eigen::Upper>().solve(u0.transpose() * (a - closed));
}

}  // namespace

PolePlacement place(const Matrix& a, const Matrix& b, const std::vector<Complex>& poles) {
  const Eigen::Index n = a.rows(), m = b.cols();
  if (a.cols() != n || n == 0) throw InputError("A: expected a square matrix with at least one state");
  if (b.rows() != n || m == 0)
    throw InputError("B: expected " + std::to_string(n) + " rows and at least one column, got " +
                     std::to_string(b.rows()) + " x " + std::to_string(m));
  if (!a.allFinite() || !b.allFinite()) throw InputError("A, B: have entries that are not finite");
  if (static_cast<Eigen::Index>(poles.size()) != n)
    throw InputError("poles: expected " + std::to_string(n) + " poles (one per state), got " + std::to_string(poles.size()));
  const std::vector<Slot> slots = paired(poles);
  PolePlacement out;
  out.sweeps = 0;
  if (m == 1) {
    std::vector<Complex> p;
    for (const Slot& sl : slots) p.push_back(sl.p);
    out.k = deflated_single_input(a, b, p);
  } else {
    out.k = robust_multi_input(a, b, slots, out.sweeps);
  }
  const Matrix closed = a - b * out.k;
  const Eigen::EigenSolver<Matrix> es(closed);  // real: conjugate pairs exact
  out.achieved.assign(es.eigenvalues().data(), es.eigenvalues().data() + n);
  sort_roots(out.achieved);
  const Eigen::JacobiSVD<ComplexMatrix> sv(es.eigenvectors());
  out.eigenvector_condition = sv.singularValues()(0) / sv.singularValues()(n - 1);
  return out;
}

}  // namespace dmbd::blocks
