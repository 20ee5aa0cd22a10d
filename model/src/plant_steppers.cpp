#include "plant_steppers.hpp"

#include "dmbd/base/dense_cholesky.hpp"

#include "dmbd/model/error.hpp"

#include <boost/numeric/odeint.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace dmbd::model::detail {

namespace odeint = boost::numeric::odeint;

LockedSolver::LockedSolver(int n) : A_(n, n), inv_diag_(n) {}

bool LockedSolver::solve(const Eigen::MatrixXd& A, const std::vector<char>& locked, Eigen::Ref<Eigen::VectorXd> b) {
  A_ = A;
  for (std::size_t i = 0; i < locked.size(); ++i) {
    if (!locked[i]) continue;
    const auto k = static_cast<Eigen::Index>(i);
    A_.row(k).setZero();
    A_.col(k).setZero();
    A_(k, k) = 1.0;
  }
  if (!base::cholesky_in_place(A_.data(), A_.outerStride(), A_.rows(), inv_diag_.data())) return false;
  base::cholesky_solve_in_place(A_.data(), A_.outerStride(), A_.rows(), inv_diag_.data(), b.data());
  return b.allFinite();
}

FixedStepper::FixedStepper(PlantDynamics& dyn) : dyn_(dyn), solver_(dyn.nv()), b_(dyn.nv()) {}

bool FixedStepper::step(Eigen::VectorXd& Q, Eigen::VectorXd& V, double h, const std::vector<char>& locked) {
  dyn_.set_state(Q, V);
  dyn_.update_anchors();
  dyn_.assemble(h);
  b_ = h * dyn_.r() - (h * h) * dyn_.kv();
  for (std::size_t i = 0; i < locked.size(); ++i)
    if (locked[i]) b_[static_cast<Eigen::Index>(i)] = -V[static_cast<Eigen::Index>(i)];
  if (!solver_.solve(dyn_.A(), locked, b_)) return false;
  V += b_;
  const int ntq = dyn_.tree_nq(), ntv = dyn_.tree_nv(), ns = dyn_.num_springs();
  dyn_.kernel().integrate(Q.head(ntq), V.head(ntv), h);
  Q.tail(ns) += h * V.tail(ns);
  return true;
}

namespace {

using OdeState = std::vector<double>;

// err = max_i |e_i| / (atol_i + rtol |x_i|): each coordinate weighed in its own unit.
struct WeightedErrorChecker {
  using value_type = double;
  using algebra_type = odeint::range_algebra;
  using operations_type = odeint::default_operations;
  const std::vector<double>* atol = nullptr;
  double rtol = 1e-5;
  template <class State, class Deriv, class Err, class Time>
  double error(algebra_type&, const State& x_old, const Deriv&, Err& x_err, Time) const {
    double e = 0;
    for (std::size_t i = 0; i < x_err.size(); ++i) {
      const double r = std::abs(x_err[i]) / ((*atol)[i] + rtol * std::abs(x_old[i]));
      if (!(r <= e)) e = std::isfinite(r) ? r : 1e300;  // a non-finite error rejects the step
    }
    return e;
  }
  template <class State, class Deriv, class Err, class Time>
  double error(const State& x_old, const Deriv& d, Err& x_err, Time t) const {
    algebra_type a;
    return error(a, x_old, d, x_err, t);
  }
};

using Dopri = odeint::runge_kutta_dopri5<OdeState>;
using Controlled = odeint::controlled_runge_kutta<Dopri, WeightedErrorChecker>;

}  // namespace

struct AccurateIntegrator::Impl {
  PlantDynamics& dyn;
  LockedSolver solver;
  std::vector<double> atol;
  Controlled stepper;
  OdeState y;
  Eigen::VectorXd Q, V, b, qd;
  const std::vector<char>* locked = nullptr;
  double dt = 1e-5;
  bool failed = false;

  Impl(PlantDynamics& d, double accuracy)
      : dyn(d), solver(d.nv()), atol(weights(d, accuracy)), stepper(WeightedErrorChecker{&atol, accuracy}),
        y(static_cast<std::size_t>(d.nq() + d.nv())), Q(d.nq()), V(d.nv()), b(d.nv()), qd(d.tree_nq()) {}

  // Absolute tolerances: accuracy x the unit of each component (plant_steppers.hpp). A
  // spring's unit depends on its kind: 1e-4 m and 1e-2 m/s for a VLCA's elastomer, 1e-3
  // rad and 1e-1 rad/s for a rotary SEA's torsion spring.
  static std::vector<double> weights(const PlantDynamics& d, double accuracy) {
    std::vector<double> w;
    auto springs = [&](double linear, double rotary) {
      for (int k = 0; k < d.num_actuators(); ++k)
        if (d.spring_q(k) >= 0) w.push_back(accuracy * (d.actuator(k).is_rotary() ? rotary : linear));
    };
    w.insert(w.end(), static_cast<std::size_t>(d.tree_nq()), accuracy);
    springs(1e-4, 1e-3);
    w.insert(w.end(), static_cast<std::size_t>(d.tree_nv()), accuracy);
    springs(1e-2, 1e-1);
    return w;
  }

  // V' into vdot, at (Q, V) already set on dyn.
  bool solve_accelerations(Eigen::Ref<Eigen::VectorXd> vdot) {
    dyn.assemble(0.0);
    vdot = dyn.r();
    for (std::size_t i = 0; i < locked->size(); ++i)
      if ((*locked)[i]) vdot[static_cast<Eigen::Index>(i)] = 0.0;
    return solver.solve(dyn.A(), *locked, vdot);
  }

  void rhs(const OdeState& x, OdeState& dxdt) {
    const int nq = dyn.nq(), nv = dyn.nv(), ntq = dyn.tree_nq(), ntv = dyn.tree_nv(), ns = dyn.num_springs();
    Q = Eigen::Map<const Eigen::VectorXd>(x.data(), nq);
    V = Eigen::Map<const Eigen::VectorXd>(x.data() + nq, nv);
    dyn.set_state(Q, V);
    Eigen::Map<Eigen::VectorXd> d(dxdt.data(), nq + nv);
    if (!solve_accelerations(d.tail(nv))) {
      failed = true;
      d.setConstant(std::numeric_limits<double>::quiet_NaN());
      return;
    }
    dyn.kernel().qdot(V.head(ntv), qd);
    d.head(ntq) = qd;
    d.segment(ntq, ns) = V.tail(ns);
  }
};

AccurateIntegrator::AccurateIntegrator(PlantDynamics& dyn, double accuracy)
    : impl_(std::make_unique<Impl>(dyn, accuracy)) {}
AccurateIntegrator::~AccurateIntegrator() = default;

long long AccurateIntegrator::advance(Eigen::VectorXd& Q, Eigen::VectorXd& V, double& t, double t_end,
                                      const std::vector<char>& locked) {
  Impl& m = *impl_;
  m.locked = &locked;
  const int nq = m.dyn.nq(), nv = m.dyn.nv();
  Eigen::Map<Eigen::VectorXd> y(m.y.data(), nq + nv);
  y.head(nq) = Q;
  y.tail(nv) = V;
  auto sys = [&m](const OdeState& x, OdeState& dxdt, double) { m.rhs(x, dxdt); };
  m.stepper.reset();  // the inputs may have changed since the last call
  long long steps = 0;
  while (t_end - t > 1e-12 * std::max(1.0, std::abs(t_end))) {
    const bool last = m.dt >= t_end - t;
    double dt = last ? t_end - t : m.dt, tt = t;
    m.failed = false;
    if (m.stepper.try_step(sys, m.y, tt, dt) == odeint::success) {
      if (m.failed) throw ModelError("simulation diverged at t = " + std::to_string(t) + " s: the mass matrix is not positive definite");
      t = last ? t_end : tt;
      if (!last || dt > m.dt) m.dt = dt;
      ++steps;
      m.dyn.kernel().normalize(y.head(m.dyn.tree_nq()));
      m.dyn.set_state(y.head(nq), y.tail(nv));
      m.dyn.update_anchors();
    } else {
      m.dt = std::min(m.dt, dt);
      if (m.dt < 1e-12) throw ModelError("simulation diverged at t = " + std::to_string(t) + " s: the step size fell below 1e-12 s");
    }
  }
  t = t_end;
  Q = y.head(nq);
  V = y.tail(nv);
  return steps;
}

void AccurateIntegrator::accelerations(const Eigen::VectorXd& Q, const Eigen::VectorXd& V, const std::vector<char>& locked,
                                       Eigen::Ref<Eigen::VectorXd> vdot) {
  impl_->locked = &locked;
  impl_->dyn.set_state(Q, V);
  if (!impl_->solve_accelerations(vdot)) vdot.setConstant(std::numeric_limits<double>::quiet_NaN());
}

}  // namespace dmbd::model::detail
