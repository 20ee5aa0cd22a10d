// The zeros of a SISO state-space system without its numerator polynomial (siso.hpp,
// zpk_by_deflation), for factors of any size.
//
// With d = 0, an orthogonal H with H b = beta e1 (beta != 0) splits the states into x1
// (driven by u) and x2, and u is then free to make x1 anything: the zeros of
// (A, b, c, 0) are those of the smaller system (A22, a21, c2, c1) whose input is x1.
// Repeat until the feedthrough is not zero; then the zeros are the eigenvalues of
// A - b c / d. Every step is orthogonal, so nothing is amplified.
#include <Eigen/Householder>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "dmbd/blocks/siso.hpp"

namespace dmbd::blocks {

namespace {

// A feedthrough below this fraction of |b| |c| / |A| makes zeros beyond 1e12 |A|: at
// infinity, as far as double precision can tell.
constexpr double kZeroFeedthrough = 1e-12;

struct Reduced {
  Matrix a;
  Vector b;
  Eigen::RowVectorXd c;
  double d;
};

// One deflation step (d taken as 0): the system seen from x1.
Reduced deflate(Reduced s) {
  Vector essential;
  double tau = 0.0, beta = 0.0;
  s.b.makeHouseholder(essential, tau, beta);
  Vector work(s.a.rows());
  s.a.applyHouseholderOnTheLeft(essential, tau, work.data());
  s.a.applyHouseholderOnTheRight(essential, tau, work.data());
  s.c.applyHouseholderOnTheRight(essential, tau, work.data());
  const auto m = s.a.rows() - 1;
  return {s.a.bottomRightCorner(m, m), s.a.bottomLeftCorner(m, 1), s.c.tail(m), s.c(0)};
}

// d against the size of the response c (sI − A)⁻¹ b, |b| |c| / |A|, with |A| the larger of
// the reduced and the original system's: once deflation has left a reduced A of zero
// (integrators only), its own |A| would make every d look negligible and lose the zero
// −b c / d (ss of (s + 4)/(s² + 2s + 10) came out without its zero). A system of
// integrators only: d counts as zero only when it is.
bool feedthrough_is_zero(const Reduced& s, double original_a_norm) {
  const double ref = std::max(s.a.norm(), original_a_norm);
  if (ref == 0.0) return s.d == 0.0;
  const double scale = s.b.norm() * s.c.norm() / ref;
  return std::abs(s.d) <= kZeroFeedthrough * scale;
}

// The point where the gain is read: on the imaginary axis (unit circle) at the
// geometric mean of the roots' frequencies, moved off any root.
double reading_frequency(const std::vector<Complex>& zeros, const std::vector<Complex>& poles, double ts) {
  double logsum = 0.0;
  int count = 0;
  for (const auto* list : {&zeros, &poles})
    for (const Complex& r : *list) {
      const double w = ts > 0.0 ? std::abs(std::log(r)) / ts : std::abs(r);
      if (w > 0.0 && std::isfinite(w)) logsum += std::log(w), ++count;
    }
  double w = count > 0 ? std::exp(logsum / count) : (ts > 0.0 ? 0.3 / ts : 1.0);
  if (ts > 0.0) w = std::min(w, 0.9 * M_PI / ts);
  return w * 0.8660254037844386;  // an irrational-looking factor: off exact root frequencies
}

}  // namespace

std::vector<Complex> deflated_zeros(const StateSpace& sys) {
  Reduced s{sys.a(), sys.b().col(0), sys.c().row(0), sys.d()(0, 0)};
  const double a_norm = sys.a().norm();
  while (s.a.rows() > 0 && feedthrough_is_zero(s, a_norm)) {
    if (s.b.norm() == 0.0) return {};  // the rest never reaches the output
    s = deflate(std::move(s));
  }
  if (s.a.rows() == 0) return {};
  const Matrix closed = s.a - s.b * s.c / s.d;
  return group_eigenvalues(closed, sys.is_discrete());
}

Zpk zpk_by_deflation(const StateSpace& sys, const std::vector<Complex>& poles) {
  const double x0 = sys.is_discrete() ? 1.0 : 0.0;
  std::vector<Complex> zeros, other_poles;
  int m = 0;
  for (const Complex& z : deflated_zeros(sys)) {
    if (z == Complex(x0, 0.0)) {
      ++m;
    } else {
      zeros.push_back(z);
    }
  }
  for (const Complex& p : poles) {
    if (p == Complex(x0, 0.0)) {
      --m;
    } else {
      other_poles.push_back(p);
    }
  }
  const Zpk shape(1.0, m, zeros, other_poles, sys.ts());
  const double w = reading_frequency(zeros, other_poles, sys.ts());
  const Complex x = sys.is_discrete() ? std::polar(1.0, w * sys.ts()) : Complex(0.0, w);
  const auto n = sys.num_states();
  const Eigen::MatrixXcd pencil = x * Eigen::MatrixXcd::Identity(n, n) - sys.a().cast<Complex>();
  const Eigen::VectorXcd v = Eigen::PartialPivLU<Eigen::MatrixXcd>(pencil).solve(sys.b().col(0).cast<Complex>());
  const Complex g = (sys.c().row(0).cast<Complex>() * v)(0) + sys.d()(0, 0);
  if (g == Complex(0.0)) return Zpk(0.0, 0, {}, {}, sys.ts());
  // k = G(x) / shape(x), real up to rounding: its sign from the real part.
  const Complex ratio = std::log(g) - shape.log_response(w);
  const double k = std::exp(ratio.real()) * (std::cos(ratio.imag()) < 0.0 ? -1.0 : 1.0);
  return Zpk(k, m, std::move(zeros), std::move(other_poles), sys.ts());
}

}  // namespace dmbd::blocks
