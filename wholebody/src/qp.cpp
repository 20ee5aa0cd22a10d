// The Goldfarb–Idnani dual active-set QP solver (qp.hpp).
//
// Invariants (Goldfarb & Idnani 1983, section 3): with G = L Lᵀ and N the normals of the
// q constraints in the working set, J = L⁻ᵀ Q is kept so that Jᵀ N = [R; 0] with R upper
// triangular (q x q). For a constraint normal n, d = Jᵀ n splits into d₁ (first q) and
// d₂; the primal step direction is z = J₂ d₂ (z = H n, H the inverse Hessian reduced to
// the working set's null space) and the dual one r = R⁻¹ d₁ (the change of the working
// set's multipliers per unit of the new one). zᵀ n = ‖d₂‖² ≥ 0 is the curvature along z.
#include "dmbd/wholebody/qp.hpp"

#include "dmbd/base/dense_cholesky.hpp"

#include <Eigen/Householder>
#include <Eigen/Jacobi>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace dmbd::wholebody {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// zᵀn ≤ kDependent ‖d‖²: the normal lies (to rounding) in the span of the working set's.
constexpr double kDependent = 1e-13;
// A constraint counts as violated below −kFeasible · its scale (|b|, ‖c‖ ‖x‖, 1).
constexpr double kFeasible = 1e-10;

// Every off-diagonal entry exactly 0. A double is ±0 exactly when its bits other than
// the sign are all 0: the bits, shifted left by one, or-ed over a column's entries above
// and below its diagonal (a loop the compiler vectorises; a NaN is not 0).
std::uint64_t magnitude_bits(const double* x, Eigen::Index count) {
  std::uint64_t any = 0;
  for (Eigen::Index i = 0; i < count; ++i) {
    std::uint64_t b;
    std::memcpy(&b, x + i, sizeof b);
    any |= b << 1;
  }
  return any;
}

bool is_diagonal(const Eigen::Ref<const Eigen::MatrixXd>& G) {
  const Eigen::Index n = G.rows();
  for (Eigen::Index j = 0; j < n; ++j) {
    const double* c = G.col(j).data();
    if ((magnitude_bits(c, j) | magnitude_bits(c + j + 1, n - j - 1)) != 0) return false;
  }
  return true;
}

}  // namespace

const char* to_string(QpStatus s) {
  switch (s) {
    case QpStatus::Optimal: return "optimal";
    case QpStatus::Infeasible: return "infeasible";
    case QpStatus::NotPositiveDefinite: return "Hessian not positive definite";
    case QpStatus::IterationLimit: return "iteration limit";
  }
  return "?";
}

QpSolver::QpSolver(int n, int m_eq, int m_in)
    : n_(n),
      m_eq_(m_eq),
      m_in_(m_in),
      CeqT_(n, m_eq),
      CinT_(n, m_in),
      U_(n, n),
      L_(n, n),
      inv_diag_(n),
      J_(n, n),
      R_(n, n),
      x_(n),
      d_(n),
      z_(n),
      r_(n),
      u_(n),
      lambda_eq_(m_eq),
      mu_in_(m_in),
      Gx_(n),
      norm_in_(m_in),
      slack_in_(m_in),
      house_(n),
      working_(n),
      previous_(n),
      is_active_(m_in) {}

void QpSolver::set_warm_start(bool on) {
  warm_ = on;
  previous_count_ = 0;
  J_start_.resize(on ? n_ : 0, on ? n_ : 0);  // sized here, so that solve() allocates nothing
  x_start_.resize(on ? n_ : 0);
  Y_.resize(on ? n_ : 0, on ? n_ : 0);
  S_.resize(on ? n_ : 0, on ? n_ : 0);
  y0_.resize(on ? n_ : 0);
}

int QpSolver::active_inequalities() const { return q_ - std::min(q_, m_eq_); }

Eigen::Ref<const Eigen::VectorXd> QpSolver::normal(int k) const {
  return k < m_eq_ ? CeqT_.col(k) : CinT_.col(k - m_eq_);
}

QpStatus QpSolver::solve(const Eigen::Ref<const Eigen::MatrixXd>& G, const Eigen::Ref<const Eigen::VectorXd>& a,
                         const Eigen::Ref<const Eigen::MatrixXd>& C_eq, const Eigen::Ref<const Eigen::VectorXd>& b_eq,
                         const Eigen::Ref<const Eigen::MatrixXd>& C_in, const Eigen::Ref<const Eigen::VectorXd>& b_in) {
  assert(G.rows() == n_ && G.cols() == n_ && a.size() == n_);
  assert(C_eq.rows() == m_eq_ && C_eq.cols() == n_ && b_eq.size() == m_eq_);
  assert(C_in.rows() == m_in_ && C_in.cols() == n_ && b_in.size() == m_in_);
  CeqT_ = C_eq.transpose();
  CinT_ = C_in.transpose();
  for (int i = 0; i < m_in_; ++i) norm_in_[i] = CinT_.col(i).norm();  // most_violated's scales, once a solve
  iterations_ = 0;
  warm_used_ = direct_ = false;
  x_ = -a;
  const bool diagonal = is_diagonal(G);
  if (!(diagonal ? start_diagonal(G) : factor(G))) return QpStatus::NotPositiveDefinite;
  const bool warm = warm_ && previous_count_ > 0;
  if (warm && !diagonal && solve_on_previous(a, b_eq, b_in)) {
    finish(G, a);
    remember_active_set(QpStatus::Optimal);
    return QpStatus::Optimal;
  }
  start(a, diagonal);
  if (warm) {
    J_start_ = J_;
    x_start_ = x_;
  }
  if (!add_equalities(b_eq)) return QpStatus::Infeasible;
  if (warm) {
    warm_used_ = add_previous(b_in);
    if (!warm_used_) {
      restart();
      add_equalities(b_eq);  // succeeded above from the same state
    }
  }
  const QpStatus status = add_inequalities(b_in);
  finish(G, a);
  remember_active_set(status);
  return status;
}

// The last Optimal solve's active inequalities make the next warm start's guess.
void QpSolver::remember_active_set(QpStatus status) {
  previous_count_ = 0;
  if (!warm_ || status != QpStatus::Optimal) return;
  for (int k = 0; k < q_; ++k)
    if (working_[k] >= m_eq_) previous_[previous_count_++] = working_[k] - m_eq_;
}

// The previous active inequalities added as equalities are (a full step of either sign
// onto each); true when every inequality's multiplier is then ≥ 0, the dual method's
// invariant. False (start cold) as well when one has become dependent on the others.
bool QpSolver::add_previous(const Eigen::Ref<const Eigen::VectorXd>& b_in) {
  for (int k = 0; k < previous_count_; ++k) {
    const int i = previous_[k];
    const Eigen::Ref<const Eigen::VectorXd> n = normal(m_eq_ + i);
    ++iterations_;
    step_directions(n);
    const double curvature = z_.dot(n);
    if (!(curvature > kDependent * d_.squaredNorm())) return false;
    const double t = (b_in[i] - n.dot(x_)) / curvature;
    x_ += t * z_;
    u_.head(q_) -= t * r_.head(q_);
    if (!add_to_working_set(m_eq_ + i)) return false;
    u_[q_ - 1] = t;
    is_active_[i] = true;
  }
  for (int k = 0; k < q_; ++k)
    if (working_[k] >= m_eq_ && !(u_[k] >= 0.0)) return false;
  return true;
}

// start()'s state again: J and x as it left them, an empty working set.
void QpSolver::restart() {
  J_ = J_start_;
  x_ = x_start_;
  R_.setZero();
  u_.setZero();
  is_active_.setConstant(false);
  q_ = 0;
}

// The unconstrained minimum x = −G⁻¹ a, J = L⁻ᵀ, an empty working set; G factored by
// factor() (start_diagonal() has done both for a diagonal G).
void QpSolver::start(const Eigen::Ref<const Eigen::VectorXd>& a, bool diagonal) {
  if (!diagonal) {
    invert_upper_factor();
    d_.noalias() = J_.transpose() * a;  // x = −G⁻¹ a = −J Jᵀ a
    x_.noalias() = -J_ * d_;
  }
  R_.setZero();
  u_.setZero();
  is_active_.setConstant(false);
  q_ = 0;
}

// The warm start's short cut: the optimality conditions on the equalities and the last
// solve's active inequalities A, solved directly. With G = UᵀU, Y = U⁻ᵀ C_Aᵀ and
// y₀ = −U⁻ᵀ a: x = U⁻¹ (y₀ + Y u), where (YᵀY) u = b_A − Yᵀ y₀ (YᵀY = C_A G⁻¹ C_Aᵀ; the
// constraints in A then hold with equality and G x + a = C_Aᵀ u). Taken only when that
// is the minimiser: the normals independent by the dual method's own test (each one's
// part outside the others' span, squared, above kDependent of its ‖U⁻ᵀ n‖²: the
// Cholesky pivots of YᵀY), every inequality multiplier ≥ 0 and no other inequality
// violated beyond add_inequalities' tolerance. The method's J = U⁻¹ Q is then never
// formed, nor the constraints added one at a time. False: nothing of the solver's state
// but x has changed, and solve() goes on as without it.
bool QpSolver::solve_on_previous(const Eigen::Ref<const Eigen::VectorXd>& a, const Eigen::Ref<const Eigen::VectorXd>& b_eq,
                                 const Eigen::Ref<const Eigen::VectorXd>& b_in) {
  const int q = m_eq_ + previous_count_;
  if (q > n_) return false;
  for (int k = 0; k < q; ++k) {
    working_[k] = k < m_eq_ ? k : m_eq_ + previous_[k - m_eq_];
    Y_.col(k) = normal(working_[k]);
    solve_upper_transposed(Y_.col(k));
  }
  y0_ = -a;
  solve_upper_transposed(y0_);
  // YᵀY = L Lᵀ in S_ (lower), and the right-hand side b_A − Yᵀ y₀ in u_.
  for (int j = 0; j < q; ++j) {
    const int i = working_[j];
    u_[j] = (i < m_eq_ ? b_eq[i] : b_in[i - m_eq_]) - Y_.col(j).dot(y0_);
    for (int k = j; k < q; ++k) S_(k, j) = Y_.col(k).dot(Y_.col(j));
  }
  // L column by column; a pivot at or below kDependent of its ‖U⁻ᵀ n‖² is a dependent normal.
  for (int j = 0; j < q; ++j) {
    double pivot = S_(j, j);
    for (int k = 0; k < j; ++k) pivot -= S_(j, k) * S_(j, k);
    if (!(pivot > kDependent * S_(j, j))) return false;
    S_(j, j) = std::sqrt(pivot);
    const double inv = 1.0 / S_(j, j);
    for (int i = j + 1; i < q; ++i) {
      double v = S_(i, j);
      for (int k = 0; k < j; ++k) v -= S_(i, k) * S_(j, k);
      S_(i, j) = v * inv;
    }
  }
  for (int i = 0; i < q; ++i) {  // L w = rhs, then Lᵀ u = w
    for (int k = 0; k < i; ++k) u_[i] -= S_(i, k) * u_[k];
    u_[i] /= S_(i, i);
  }
  for (int i = q - 1; i >= 0; --i) {
    for (int k = i + 1; k < q; ++k) u_[i] -= S_(k, i) * u_[k];
    u_[i] /= S_(i, i);
  }
  for (int k = m_eq_; k < q; ++k)
    if (!(u_[k] >= 0.0)) return false;
  x_ = y0_;
  x_.noalias() += Y_.leftCols(q) * u_.head(q);
  solve_upper(x_);
  is_active_.setConstant(false);
  for (int k = m_eq_; k < q; ++k) is_active_[working_[k] - m_eq_] = true;
  q_ = q;
  double slack = 0;
  if (!x_.allFinite() || most_violated(b_in, slack) >= 0) {
    q_ = 0;
    return false;
  }
  u_.tail(n_ - q).setZero();
  iterations_ = previous_count_;
  warm_used_ = direct_ = true;
  return true;
}

// Uᵀ y = v in place (forward substitution; U's columns are Uᵀ's rows).
void QpSolver::solve_upper_transposed(Eigen::Ref<Eigen::VectorXd> v) const {
  for (int i = 0; i < n_; ++i) v[i] = (v[i] - U_.col(i).head(i).dot(v.head(i))) * inv_diag_[i];
}

// U x = v in place (back substitution, a contiguous column of U per step).
void QpSolver::solve_upper(Eigen::Ref<Eigen::VectorXd> v) const {
  for (int k = n_ - 1; k >= 0; --k) {
    v[k] *= inv_diag_[k];
    v.head(k) -= v[k] * U_.col(k).head(k);
  }
}

// G = Uᵀ U with U upper triangular: L = Uᵀ by the left-looking factor over contiguous
// columns of base/dense_cholesky.hpp (which also gives 1 / the diagonal: the solves
// here multiply by it), then transposed for the solver's column-wise uses of U. Eigen's
// LLT of these few rows (16 for the whole-body QP) spends most of its instructions
// dispatching a matrix-vector product per column, and a factor by dot products of U's
// columns waits on their dependent chains (9 % of issue 29's tick under perf). False
// unless G is positive definite (a pivot ≤ 0 or not a number).
bool QpSolver::factor(const Eigen::Ref<const Eigen::MatrixXd>& G) {
  L_ = G;
  if (!base::cholesky_in_place(L_.data(), L_.outerStride(), n_, inv_diag_.data())) return false;
  U_.triangularView<Eigen::Upper>() = L_.transpose();  // only U's upper triangle is read
  return true;
}

// J = U⁻¹ (so that Jᵀ G J = I), upper triangular, a column at a time by back
// substitution in column form (an axpy with U's contiguous column per step). Written
// out because Eigen's triangular solve with the identity as its right-hand side runs
// its blocked level-3 path on these few rows and ignores that the result is
// triangular: 14.1 k instructions for the whole-body QP's 16 x 16 against 7.3 k (issue
// 27's tick).
void QpSolver::invert_upper_factor() {
  J_.setZero();
  for (int j = 0; j < n_; ++j) {
    J_(j, j) = 1.0;
    for (int k = j; k >= 0; --k) {
      J_(k, j) *= inv_diag_[k];
      J_.col(j).head(k) -= J_(k, j) * U_.col(k).head(k);
    }
  }
}

// G = diag(g) (the whole-body QP's cost): L = diag(√g), J = L⁻ᵀ = diag(1/√g) and
// x = −a/g without the dense factorisation and triangular solves (most of a solve's
// start). Evaluated as those solves do on a diagonal L, to the bit: the matrix solve
// multiplies by the reciprocal 1/√g, the vector solves divide by √g twice. Fails as
// the Cholesky factorisation does, on a diagonal entry ≤ 0.
bool QpSolver::start_diagonal(const Eigen::Ref<const Eigen::MatrixXd>& G) {
  J_.setZero();
  for (int i = 0; i < n_; ++i) {
    if (G(i, i) <= 0.0) return false;
    const double l = std::sqrt(G(i, i));
    J_(i, i) = 1.0 / l;
    x_[i] = x_[i] / l / l;
  }
  return true;
}

// d = Jᵀ n, z = J₂ d₂, r = R⁻¹ d₁.
void QpSolver::step_directions(const Eigen::Ref<const Eigen::VectorXd>& n) {
  d_.noalias() = J_.transpose() * n;
  z_.noalias() = J_.rightCols(n_ - q_) * d_.tail(n_ - q_);
  r_.head(q_) = d_.head(q_);
  // R r = d₁ by back substitution, a column at a time (Eigen's triangular solve splits
  // even these few rows into panels and a matrix-vector product).
  for (int k = q_ - 1; k >= 0; --k) {
    r_[k] /= R_(k, k);
    r_.head(k) -= r_[k] * R_.col(k).head(k);
  }
}

// Each equality by a full step of either sign onto it: x += t z with t = (b − nᵀx)/zᵀn.
bool QpSolver::add_equalities(const Eigen::Ref<const Eigen::VectorXd>& b_eq) {
  for (int i = 0; i < m_eq_; ++i) {
    const Eigen::Ref<const Eigen::VectorXd> n = normal(i);
    step_directions(n);
    const double curvature = z_.dot(n);
    if (!(curvature > kDependent * d_.squaredNorm())) return false;  // dependent on earlier ones
    const double t = (b_eq[i] - n.dot(x_)) / curvature;
    x_ += t * z_;
    u_.head(q_) -= t * r_.head(q_);
    const double u_new = t;
    if (!add_to_working_set(i)) return false;
    u_[q_ - 1] = u_new;
  }
  return true;
}

// The inequality with the most negative slack nᵀx − b among those not in the working
// set, or −1 when none is violated beyond its tolerance. The slacks by one product
// C_in x (one matrix-vector product rather than a dot product per row).
int QpSolver::most_violated(const Eigen::Ref<const Eigen::VectorXd>& b_in, double& slack) {
  int p = -1;
  slack = 0;
  const double x_norm = x_.norm();
  slack_in_.noalias() = CinT_.transpose() * x_;
  slack_in_ -= b_in;
  for (int i = 0; i < m_in_; ++i) {
    if (is_active_[i]) continue;
    const double s = slack_in_[i];
    const double scale = std::max({1.0, std::abs(b_in[i]), norm_in_[i] * x_norm});
    if (s < -kFeasible * scale && (p < 0 || s < slack)) {
      p = i;
      slack = s;
    }
  }
  return p;
}

// The largest dual step before an active inequality's multiplier reaches zero:
// min u_k / r_k over inequalities with r_k > 0 (its position in `position`), or ∞.
double QpSolver::partial_step(int& position) const {
  double t = kInf;
  position = -1;
  for (int k = 0; k < q_; ++k)
    if (working_[k] >= m_eq_ && r_[k] > 0.0 && u_[k] / r_[k] < t) {
      t = u_[k] / r_[k];
      position = k;
    }
  return t;
}

// Step 1 and 2 of the method: take the most violated inequality p and move x (primal
// step) and the multipliers (dual step) until p holds, dropping an active inequality
// whenever its multiplier would turn negative first.
QpStatus QpSolver::add_inequalities(const Eigen::Ref<const Eigen::VectorXd>& b_in) {
  const int max_iterations = 10 * (n_ + m_eq_ + m_in_) + 10;
  double slack = 0;
  for (int p = most_violated(b_in, slack); p >= 0; p = most_violated(b_in, slack)) {
    const Eigen::Ref<const Eigen::VectorXd> n = normal(m_eq_ + p);
    double u_p = 0.0;  // the new constraint's multiplier as it grows
    for (;;) {
      if (++iterations_ > max_iterations) return QpStatus::IterationLimit;
      step_directions(n);
      const double curvature = z_.dot(n);
      const bool primal = curvature > kDependent * d_.squaredNorm();
      const double t2 = primal ? -slack / curvature : kInf;  // full step: p holds with equality
      int drop = -1;
      const double t1 = partial_step(drop);
      const double t = std::min(t1, t2);
      if (t == kInf) return QpStatus::Infeasible;  // nothing can make p hold
      if (primal) x_ += t * z_;
      u_.head(q_) -= t * r_.head(q_);
      u_p += t;
      if (t == t2) {
        if (!add_to_working_set(m_eq_ + p)) return QpStatus::Infeasible;
        u_[q_ - 1] = u_p;
        is_active_[p] = true;
        break;
      }
      is_active_[working_[drop] - m_eq_] = false;
      drop_from_working_set(drop);
      slack = n.dot(x_) - b_in[p];
    }
  }
  return QpStatus::Optimal;
}

// Turns d₂ into β e₁ (J₂ transformed alike) so that Jᵀ n = [R(:, q); 0]: one Householder
// reflection H = I − τ v vᵀ (v = [1; essential part], H d₂ = β e₁, |β| = ‖d₂‖) and
// J₂ ← J₂ H, so that (J₂ H)ᵀ n = H d₂. A matrix-vector product and a rank-one update
// of J₂ instead of n − q − 1 Givens rotations, whose chain through d (each rotation's
// sine and cosine wait for the last one's) was the solver's largest cost.
bool QpSolver::add_to_working_set(int k) {
  const int m = n_ - q_;
  auto d2 = d_.tail(m);
  double tau = 0.0, beta = 0.0;
  d2.makeHouseholderInPlace(tau, beta);
  reflect_columns(q_, tau);
  d2[0] = beta;
  d2.tail(m - 1).setZero();
  if (!(d_[q_] * d_[q_] > kDependent * d_.squaredNorm())) return false;
  R_.col(q_).head(q_ + 1) = d_.head(q_ + 1);
  working_[q_] = k;
  ++q_;
  return true;
}

// J's columns q.. times the reflection H = I − τ h hᵀ, h = [1; d_ below q+1] (the
// essential part makeHouseholderInPlace left there): w = J_q h, then J_q −= τ w hᵀ,
// column by contiguous column. Written out: Eigen's applyHouseholderOnTheRight does the
// same through a general matrix-vector product and a rank-one update, whose set-up
// outweighs the arithmetic at these sizes (3.7 k instructions an added constraint
// against about 1 k here, callgrind, issue 29's tick).
void QpSolver::reflect_columns(int q, double tau) {
  const int m = n_ - q;
  const Eigen::Index n = J_.rows();
  double* w = house_.data();
  const double* h = d_.data() + q;  // h[0] is taken as 1
  const double* c0 = &J_(0, q);
  for (Eigen::Index r = 0; r < n; ++r) w[r] = c0[r];
  for (int j = 1; j < m; ++j) {
    const double e = h[j];
    const double* c = &J_(0, q + j);
    for (Eigen::Index r = 0; r < n; ++r) w[r] += e * c[r];
  }
  for (int j = 0; j < m; ++j) {
    const double e = tau * (j == 0 ? 1.0 : h[j]);
    double* c = &J_(0, q + j);
    for (Eigen::Index r = 0; r < n; ++r) c[r] -= e * w[r];
  }
}

// Removes position l: R loses column l, and the Hessenberg part left behind is made
// triangular again by rotations of R's rows (and J's columns) l .. q−1.
void QpSolver::drop_from_working_set(int l) {
  for (int k = l; k + 1 < q_; ++k) {
    R_.col(k) = R_.col(k + 1);
    working_[k] = working_[k + 1];
    u_[k] = u_[k + 1];
  }
  R_.col(q_ - 1).setZero();
  u_[q_ - 1] = 0.0;
  --q_;
  for (int j = l; j < q_; ++j) {
    Eigen::JacobiRotation<double> g;
    g.makeGivens(R_(j, j), R_(j + 1, j), &R_(j, j));
    R_(j + 1, j) = 0.0;
    R_.rightCols(n_ - j - 1).applyOnTheLeft(j, j + 1, g.adjoint());
    J_.applyOnTheRight(j, j + 1, g);
  }
}

// Multipliers by constraint and the objective at x.
void QpSolver::finish(const Eigen::Ref<const Eigen::MatrixXd>& G, const Eigen::Ref<const Eigen::VectorXd>& a) {
  lambda_eq_.setZero();
  mu_in_.setZero();
  for (int k = 0; k < q_; ++k) {
    if (working_[k] < m_eq_) lambda_eq_[working_[k]] = u_[k];
    else mu_in_[working_[k] - m_eq_] = u_[k];
  }
  Gx_.noalias() = G * x_;
  f_ = 0.5 * x_.dot(Gx_) + a.dot(x_);
}

}  // namespace dmbd::wholebody
