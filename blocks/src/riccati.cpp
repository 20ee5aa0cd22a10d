#include "dmbd/blocks/riccati.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <string>

#include "dmbd/base/error.hpp"
#include "ordered_schur.hpp"

namespace dmbd::blocks {

namespace {

std::string size_text(const Matrix& m) { return std::to_string(m.rows()) + " x " + std::to_string(m.cols()); }

void check_size(const Matrix& m, Eigen::Index rows, Eigen::Index cols, const char* name) {
  if (m.rows() != rows || m.cols() != cols)
    throw InputError(std::string(name) + ": expected a " + std::to_string(rows) + " x " + std::to_string(cols) +
                     " matrix, got " + size_text(m));
  if (!m.allFinite()) throw InputError(std::string(name) + ": has entries that are not finite");
}

void check_symmetric(const Matrix& m, const char* name) {
  const double scale = m.cwiseAbs().maxCoeff();
  if ((m - m.transpose()).cwiseAbs().maxCoeff() > 1e-10 * scale)
    throw InputError(std::string(name) + ": expected a symmetric matrix");
}

// The equation's data checked, and the cross term folded in: Ã = A - B R^-1 N',
// G = B R^-1 B', Q̃ = Q - N R^-1 N' (the equation in A, G, Q̃ has the same solution).
struct Reduced {
  Matrix a, g, q;
};

Reduced reduce(const Matrix& a, const Matrix& b, const Matrix& q, const Matrix& r, const Matrix& n_in) {
  if (a.rows() != a.cols()) throw InputError("A: expected a square matrix, got " + size_text(a));
  if (a.rows() == 0) throw InputError("A: the system has no states");
  const Eigen::Index n = a.rows(), m = b.cols();
  check_size(a, n, n, "A");
  check_size(b, n, m, "B");
  if (m == 0) throw InputError("B: the system has no inputs");
  check_size(q, n, n, "Q");
  check_size(r, m, m, "R");
  const Matrix nn = n_in.size() ? n_in : Matrix::Zero(n, m);
  check_size(nn, n, m, "N");
  check_symmetric(q, "Q");
  check_symmetric(r, "R");
  const Matrix rs = 0.5 * (r + r.transpose());
  const Eigen::LLT<Matrix> llt(rs);
  if (llt.info() != Eigen::Success || !(llt.matrixL().toDenseMatrix().diagonal().minCoeff() > 0.0))
    throw InputError("R: expected a positive definite matrix");
  const Matrix rinv_bt = llt.solve(b.transpose()), rinv_nt = llt.solve(nn.transpose());
  Reduced out{a - b * rinv_nt, b * rinv_bt, 0.5 * (q + q.transpose()) - nn * rinv_nt};
  out.g = 0.5 * (out.g + out.g.transpose()).eval();
  out.q = 0.5 * (out.q + out.q.transpose()).eval();
  return out;
}

// X = U21 U11^-1 from the Schur vectors of the n selected eigenvalues; `boundary` names
// the curve the eigenvalues must not lie on.
Matrix stabilising_solution(const ComplexMatrix& m, Eigen::Index n, const char* boundary) {
  const double norm = m.cwiseAbs().colwise().sum().maxCoeff();
  const double on_axis = 1e3 * std::numeric_limits<double>::epsilon() * std::max(norm, 1e-300);
  bool touches = false;
  const OrderedSchur s = ordered_schur(m, [&](Complex x) {
    if (std::abs(x.real()) <= on_axis) touches = true;
    return x.real() < 0.0;
  });
  if (touches || s.selected != n)
    throw InputError(std::string("no stabilising solution: eigenvalues on the ") + boundary +
                     " (the pair (A, B) is not stabilisable, or Q does not see a mode of A on the " + boundary + ")");
  const ComplexMatrix u11 = s.u.topLeftCorner(n, n), u21 = s.u.bottomLeftCorner(n, n);
  const Eigen::PartialPivLU<ComplexMatrix> lu(u11.transpose());
  if (!(lu.rcond() > static_cast<double>(n) * std::numeric_limits<double>::epsilon()))
    throw InputError("no stabilising solution: the stable invariant subspace is not a graph (U11 singular)");
  const Matrix x = lu.solve(u21.transpose()).transpose().real();
  if (!x.allFinite()) throw InputError("no stabilising solution: the solution is not finite");
  return 0.5 * (x + x.transpose());
}

std::vector<Complex> eigenvalues(const Matrix& m) {
  const Eigen::EigenSolver<Matrix> es(m, false);
  std::vector<Complex> e(es.eigenvalues().data(), es.eigenvalues().data() + es.eigenvalues().size());
  sort_roots(e);
  return e;
}

}  // namespace

Matrix solve_care(const Matrix& a, const Matrix& b, const Matrix& q, const Matrix& r, const Matrix& n) {
  const Reduced d = reduce(a, b, q, r, n);
  const Eigen::Index k = a.rows();
  Matrix h(2 * k, 2 * k);
  h << d.a, -d.g, -d.q, -d.a.transpose();
  return stabilising_solution(h.cast<Complex>(), k, "imaginary axis");
}

Matrix solve_dare(const Matrix& a, const Matrix& b, const Matrix& q, const Matrix& r, const Matrix& n) {
  const Reduced d = reduce(a, b, q, r, n);
  const Eigen::Index k = a.rows();
  const Matrix id = Matrix::Identity(k, k), zero = Matrix::Zero(k, k);
  Matrix m(2 * k, 2 * k), l(2 * k, 2 * k);
  m << d.a, zero, -d.q, id;
  l << id, d.g, zero, d.a.transpose();
  const Eigen::PartialPivLU<Matrix> lu(m - l);
  if (!(lu.rcond() > static_cast<double>(k) * std::numeric_limits<double>::epsilon()))
    throw InputError("no stabilising solution: the symplectic pencil has an eigenvalue at z = 1 (on the unit circle)");
  const Matrix cayley = lu.solve(m + l);
  return stabilising_solution(cayley.cast<Complex>(), k, "unit circle");
}

LinearQuadratic lqr(const Matrix& a, const Matrix& b, const Matrix& q, const Matrix& r, const Matrix& n) {
  const Matrix s = solve_care(a, b, q, r, n);
  const Matrix nn = n.size() ? n : Matrix::Zero(b.rows(), b.cols());
  const Matrix k = (0.5 * (r + r.transpose())).llt().solve(b.transpose() * s + nn.transpose());
  return {k, s, eigenvalues(a - b * k)};
}

LinearQuadratic dlqr(const Matrix& a, const Matrix& b, const Matrix& q, const Matrix& r, const Matrix& n) {
  const Matrix s = solve_dare(a, b, q, r, n);
  const Matrix nn = n.size() ? n : Matrix::Zero(b.rows(), b.cols());
  const Matrix w = 0.5 * (r + r.transpose()) + b.transpose() * s * b;
  const Matrix k = w.llt().solve(b.transpose() * s * a + nn.transpose());
  return {k, s, eigenvalues(a - b * k)};
}

double care_residual(const Matrix& a, const Matrix& b, const Matrix& q, const Matrix& r, const Matrix& n,
                     const Matrix& x) {
  const Matrix nn = n.size() ? n : Matrix::Zero(b.rows(), b.cols());
  const Matrix f = x * b + nn;
  const Matrix quad = f * r.llt().solve(f.transpose());
  const Matrix res = a.transpose() * x + x * a - quad + q;
  const Matrix scale = (a.transpose() * x).cwiseAbs() + (x * a).cwiseAbs() + quad.cwiseAbs() + q.cwiseAbs();
  return res.cwiseAbs().maxCoeff() / std::max(scale.maxCoeff(), 1e-300);
}

double dare_residual(const Matrix& a, const Matrix& b, const Matrix& q, const Matrix& r, const Matrix& n,
                     const Matrix& x) {
  const Matrix nn = n.size() ? n : Matrix::Zero(b.rows(), b.cols());
  const Matrix f = a.transpose() * x * b + nn;
  const Matrix quad = f * (r + b.transpose() * x * b).llt().solve(f.transpose());
  const Matrix axa = a.transpose() * x * a;
  const Matrix res = axa - x - quad + q;
  const Matrix scale = axa.cwiseAbs() + x.cwiseAbs() + quad.cwiseAbs() + q.cwiseAbs();
  return res.cwiseAbs().maxCoeff() / std::max(scale.maxCoeff(), 1e-300);
}

}  // namespace dmbd::blocks
