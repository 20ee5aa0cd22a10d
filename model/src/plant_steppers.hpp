#pragma once
// Internal to model/: the two integrators of the plant's equations (plant_dynamics.hpp).
//
// FixedStepper: one semi-implicit step of length h from (Q, V),
//   (M + h D + h^2 K) dV = h (f - c) - h^2 K V,   V+ = V + dV,
//   q+ = q + h N(q) v+ (quaternions renormalised),  s+ = s + h s'+,
// with the friction anchors updated (return map) at the start of the step: the stiff
// forces are taken implicitly (backward Euler, linearised once), everything else
// explicitly (symplectic Euler). Locked joints keep v = 0 (their rows become identity).
// AccurateIntegrator: Boost.Odeint's Dormand-Prince 5(4) with error control on the
// same equations V' = M^-1 (f - c); the error per component is weighed against
// accuracy x (a unit of each kind: 1 rad or m, 1e-4 m of a VLCA's spring or 1e-3 rad of
// a rotary SEA's, 1 rad/s, 1e-2 m/s or 1e-1 rad/s of spring rate). Both allocate nothing
// per step once running.
#include "plant_dynamics.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <memory>
#include <vector>

namespace dmbd::model::detail {

// Solves A x = b with the rows and columns of locked velocities replaced by identity
// (x_i = b_i there). Returns false if A is not positive definite.
class LockedSolver {
 public:
  explicit LockedSolver(int n);
  bool solve(const Eigen::MatrixXd& A, const std::vector<char>& locked, Eigen::Ref<Eigen::VectorXd> b);

 private:
  Eigen::MatrixXd A_;  // the locked copy of A, then its Cholesky factor
  Eigen::VectorXd inv_diag_;  // 1 / the factor's diagonal
};

class FixedStepper {
 public:
  explicit FixedStepper(PlantDynamics& dyn);
  // Returns false when the linear solve fails (the state is then unchanged).
  bool step(Eigen::VectorXd& Q, Eigen::VectorXd& V, double h, const std::vector<char>& locked);

 private:
  PlantDynamics& dyn_;
  LockedSolver solver_;
  Eigen::VectorXd b_;
};

class AccurateIntegrator {
 public:
  AccurateIntegrator(PlantDynamics& dyn, double accuracy);
  ~AccurateIntegrator();
  // Integrates from t to exactly t_end; returns the accepted steps. Throws ModelError
  // when the step size collapses or the solve fails.
  long long advance(Eigen::VectorXd& Q, Eigen::VectorXd& V, double& t, double t_end, const std::vector<char>& locked);
  // V' at (Q, V) with the current inputs (for readings such as the IMU).
  void accelerations(const Eigen::VectorXd& Q, const Eigen::VectorXd& V, const std::vector<char>& locked,
                     Eigen::Ref<Eigen::VectorXd> vdot);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dmbd::model::detail
