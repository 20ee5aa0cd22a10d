#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/schur_exponential.hpp"
#include "dmbd/blocks/sparse_state_space.hpp"

namespace dmbd::blocks {

namespace {

constexpr int kDenseStates = 60;

// [A B(:, in); 0 0]: the state [x; u] of a system driven by a constant input.
SparseMatrix augmented(const SparseStateSpace& sys, int in) {
  const int n = sys.num_states();
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    for (SparseMatrix::InnerIterator it(sys.a(), i); it; ++it) t.emplace_back(i, it.col(), it.value());
    for (SparseMatrix::InnerIterator it(sys.b(), i); it; ++it)
      if (it.col() == in) t.emplace_back(i, n, it.value());
  }
  SparseMatrix m(n + 1, n + 1);
  m.setFromTriplets(t.begin(), t.end());
  return m;
}

}  // namespace

ExponentialAction::ExponentialAction(SparseMatrix m) : m_(std::move(m)) {
  const auto n = m_.rows();
  if (n == 0) return;
  double trace = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) trace += m_.coeff(i, i);
  mu_ = trace / static_cast<double>(n);
  Vector col = Vector::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    bool diagonal = false;
    for (SparseMatrix::InnerIterator it(m_, i); it; ++it) {
      const double v = it.col() == i ? it.value() - mu_ : it.value();
      diagonal = diagonal || it.col() == i;
      col(it.col()) += std::abs(v);
    }
    if (!diagonal) col(i) += std::abs(mu_);
  }
  norm1_ = col.maxCoeff();
}

Vector ExponentialAction::apply(const Vector& v, double t) const {
  if (m_.rows() == 0 || t == 0.0) return v;
  // Steps of 1-norm <= kStepNorm: no term of the series exceeds 4^4/4! = 10.7 times the
  // state (rounding grows by no more), and about 8 products per unit of norm x time
  // are needed instead of 18 with steps of norm 1.
  constexpr double kStepNorm = 4.0;
  const double s = std::max(1.0, std::ceil(norm1_ * std::abs(t) / kStepNorm));
  if (s > 1e9) throw InputError("time response: the horizon is too long for the system's fastest dynamics");
  const double h = t / s, decay = std::exp(mu_ * h);
  Vector x = v, term(v.size()), next(v.size());
  for (double step = 0; step < s; ++step) {
    Vector sum = x;
    term = x;
    double previous = std::numeric_limits<double>::infinity();
    for (int k = 1; k <= 60; ++k) {
      next.noalias() = m_ * term;
      next -= mu_ * term;
      term = next * (h / k);
      sum += term;
      const double size = term.lpNorm<Eigen::Infinity>();
      if (std::max(size, previous) <= std::numeric_limits<double>::epsilon() * sum.lpNorm<Eigen::Infinity>()) break;
      previous = size;
    }
    x = decay * sum;
  }
  return x;
}

SparseStep::SparseStep(const SparseStateSpace& sys, double t_end, int n, int in) : sys_(sys), in_(in) {
  if (in < 0 || in >= sys.num_inputs()) throw InputError("step: input " + std::to_string(in) + " does not exist");
  if (!(t_end > 0.0) || !std::isfinite(t_end)) throw InputError("the final time must be a positive number of seconds");
  if (sys.is_discrete()) {
    n = static_cast<int>(std::floor(t_end / sys.ts() + 1e-9)) + 1;
    if (n > 50'000'000) throw InputError("step: too many samples for this sample time and final time");
  }
  if (n < 2) throw InputError("a time response needs at least 2 samples");
  const int nx = sys.num_states();
  dt_ = sys.is_discrete() ? sys.ts() : t_end / (n - 1);
  response_.t.resize(static_cast<size_t>(n));
  response_.y.resize(n, sys.num_outputs());
  for (int k = 0; k < n; ++k) response_.t[static_cast<size_t>(k)] = k * dt_;
  if (!sys.is_discrete() && nx <= kDenseStates) {
    exact_samples(n);
    return;
  }
  augmented_ = augmented(sys, in);
  if (!sys.is_discrete()) action_.emplace(augmented_);
  const double per_sample = static_cast<double>(nx) + 1.0;
  stride_ = static_cast<int>(std::max(1.0, std::ceil(static_cast<double>(n) * per_sample / 2e7)));
  Vector z = Vector::Zero(nx + 1);
  z(nx) = 1.0;
  const Matrix d = sys.d();
  for (int k = 0; k < n; ++k) {
    if (k % stride_ == 0) checkpoints_.push_back(z);
    const Vector y = sys.c() * z.head(nx);
    for (int o = 0; o < sys.num_outputs(); ++o) response_.y(k, o) = y(o) + d(o, in);
    if (k + 1 >= n) break;
    if (sys.is_discrete()) {
      z = augmented_ * z;  // x[k+1] = A x[k] + B u[k]; u stays 1
      z(nx) = 1.0;
    } else {
      z = advance(z, dt_);
    }
  }
}

// A small continuous system: every sample from e^{M t_k} of the augmented M = [A B; 0 0]
// (Van Loan: its last column holds x(t_k) = integral of e^{A s} B over [0, t_k]), with no
// cancellation at small t and no drift at large t (SchurExponential). The states are
// balanced first (an exact power-of-two diagonal similarity, the transfer unchanged): a
// companion realisation of 1e6/((s + 1e-6)(s + 1e6)) has entries 1e6 apart, and
// balancing shrinks ||M||, hence the squarings, and the rounding relative to the states.
void SparseStep::exact_samples(int n) {
  sys_ = sys_.balanced();
  const int nx = sys_.num_states();
  augmented_ = augmented(sys_, in_);
  exact_.emplace(Matrix(augmented_));
  Vector z0 = Vector::Zero(nx + 1);
  z0(nx) = 1.0;
  const Matrix z = exact_->samples(z0, dt_, n);
  const Matrix y = sys_.c() * z.topRows(nx);
  for (int k = 0; k < n; ++k)
    for (int o = 0; o < sys_.num_outputs(); ++o) response_.y(k, o) = y(o, k) + sys_.d()(o, in_);
}

Vector SparseStep::advance(const Vector& z, double t) const { return action_->apply(z, t); }

double SparseStep::at(double t, int out) const {
  if (out < 0 || out >= sys_.num_outputs()) throw InputError("step: output " + std::to_string(out) + " does not exist");
  const int last = static_cast<int>(response_.t.size()) - 1;
  const int k = std::clamp(static_cast<int>(std::floor(t / dt_)), 0, last);
  if (sys_.is_discrete()) return response_.y(k, out);
  const int nx = sys_.num_states();
  Vector z;
  if (exact_) {
    z = Vector::Zero(nx + 1);
    z(nx) = 1.0;
    z = exact_->apply(z, std::max(t, 0.0));
  } else {
    const int c = k / stride_;
    z = checkpoints_[static_cast<size_t>(c)];
    const double t0 = static_cast<double>(c) * stride_ * dt_;
    if (t > t0) z = advance(z, t - t0);
  }
  return (sys_.c().row(out) * z.head(nx))(0, 0) + sys_.d()(out, in_);
}

}  // namespace dmbd::blocks
