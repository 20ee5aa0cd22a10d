#include "dmbd/blocks/schur_exponential.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <unsupported/Eigen/MatrixFunctions>

#include "dmbd/blocks/error.hpp"

namespace dmbd::blocks {

namespace {

// sinh(z)/z, to rounding also near 0 (series: the next term z^6/5040 < 2e-16 there).
Complex sinch(Complex z) {
  if (std::abs(z) < 1e-2) {
    const Complex z2 = z * z;
    return 1.0 + z2 / 6.0 * (1.0 + z2 / 20.0);
  }
  return std::sinh(z) / z;
}

// The divided difference (e^b - e^a)/(b - a) (e^a when a == b): Higham, Functions of
// Matrices (2008), eq. 10.42, e^{(a+b)/2} sinch((b-a)/2), free of the cancellation of
// the plain quotient. When the two decay rates are far apart (|Re(b - a)| > 600) sinh
// would overflow while e^{(a+b)/2} underflows; the plain quotient has no cancellation there.
Complex exp_divided_difference(Complex a, Complex b) {
  const Complex half = 0.5 * (b - a);
  if (std::abs(half.real()) < 300.0) return std::exp(0.5 * (a + b)) * sinch(half);
  return (std::exp(b) - std::exp(a)) / (b - a);
}

// The exact diagonal and first superdiagonal of e^{Th} for upper triangular T.
void exact_band(ComplexMatrix& f, const ComplexMatrix& t, double h) {
  const Eigen::Index n = t.rows();
  for (Eigen::Index i = 0; i < n; ++i) f(i, i) = std::exp(t(i, i) * h);
  for (Eigen::Index i = 0; i + 1 < n; ++i)
    f(i, i + 1) = t(i, i + 1) * h * exp_divided_difference(t(i, i) * h, t(i + 1, i + 1) * h);
}

}  // namespace

SchurExponential::SchurExponential(const Matrix& m) : m_(m) {
  if (m.rows() != m.cols()) throw InputError("matrix exponential: the matrix is not square");
  if (!m.allFinite()) throw InputError("matrix exponential: the matrix has a non-finite entry");
  if (m.rows() == 0) return;
  norm1_ = m.cwiseAbs().colwise().sum().maxCoeff();
  const Eigen::ComplexSchur<ComplexMatrix> schur(m.cast<Complex>());
  if (schur.info() != Eigen::Success) throw InputError("matrix exponential: the Schur form did not converge");
  u_ = schur.matrixU();
  t_ = schur.matrixT().triangularView<Eigen::Upper>();
}

ComplexMatrix SchurExponential::triangular_exp(double t) const {
  const Eigen::Index n = t_.rows();
  if (!(t >= 0.0) || !std::isfinite(t)) throw InputError("matrix exponential: the time must be finite and >= 0");
  if (t == 0.0) return ComplexMatrix::Identity(n, n);
  // s squarings bring ||T h||_1 to at most 5, where Eigen's Pade approximant of degree
  // 13 is accurate to rounding without squarings of its own (its threshold is 5.37).
  const double norm = t_.cwiseAbs().colwise().sum().maxCoeff();
  int s = 0;
  if (norm > 0.0) s = std::max(0, static_cast<int>(std::ceil(std::log2(norm) + std::log2(t) - std::log2(5.0))));
  const double h = std::ldexp(t, -s);
  ComplexMatrix f = (t_ * h).exp();
  f.triangularView<Eigen::StrictlyLower>().setZero();
  exact_band(f, t_, h);
  ComplexMatrix sq(n, n);
  for (int j = s - 1; j >= 0; --j) {
    sq.noalias() = f.triangularView<Eigen::Upper>() * f;
    f = sq.triangularView<Eigen::Upper>();
    exact_band(f, t_, std::ldexp(t, -j));
  }
  return f;
}

bool SchurExponential::short_time(double t) const { return t * norm1_ <= 0.5; }

// e^{Mt} v = sum (Mt)^k v / k! in M's own coordinates, for ||M t||_1 <= 1/2: the terms
// shrink at least twofold each, and entry by entry the sum is accurate relative to
// itself wherever its terms do not cancel. The Schur basis would mix the entries and
// leave each only accurate to rounding of the largest: for a chain of n lags y(t) ~
// t^n/n! shortly after the step, which would drown in the rounding of x_1 ~ t.
// Summed until, past n terms (when every entry M can reach has had its first), each
// entry of the term is below rounding of that entry of the sum.
Matrix SchurExponential::taylor(const Matrix& v, double t) const {
  Matrix sum = v, term = v, next(v.rows(), v.cols());
  const double eps = std::numeric_limits<double>::epsilon();
  for (int k = 1; k <= size() + 60; ++k) {
    next.noalias() = m_ * term;
    term = next * (t / k);
    sum += term;
    if (k >= size() && (term.array().abs() <= eps * sum.array().abs()).all()) break;
  }
  return sum;
}

Matrix SchurExponential::exp(double t) const {
  if (size() == 0) return Matrix();
  if (short_time(t)) return taylor(Matrix::Identity(size(), size()), t);
  return (u_ * triangular_exp(t) * u_.adjoint()).real();
}

Vector SchurExponential::apply(const Vector& v, double t) const {
  if (size() == 0) return v;
  if (short_time(t)) return taylor(v, t);
  const Eigen::VectorXcd w = u_.adjoint() * v.cast<Complex>();
  return (u_ * (triangular_exp(t).triangularView<Eigen::Upper>() * w)).real();
}

Matrix SchurExponential::samples(const Vector& v, double dt, int n) const {
  Matrix out(v.size(), n);
  if (n <= 0) return out;
  const Matrix step = n > 1 ? exp(dt) : Matrix();
  for (int k = 0; k < n; ++k) {
    if (k % kRestart == 0 || short_time(static_cast<double>(k) * dt)) {
      out.col(k) = apply(v, static_cast<double>(k) * dt);
    } else {
      out.col(k).noalias() = step * out.col(k - 1);
    }
  }
  return out;
}

}  // namespace dmbd::blocks
