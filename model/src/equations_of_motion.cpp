// A v̇ + b + g = τ solved either way (equations_of_motion.hpp).
#include "dmbd/model/equations_of_motion.hpp"

#include "dmbd/model/error.hpp"

#include <Eigen/Cholesky>

#include <string>

namespace dmbd::model {

namespace {

void check_size(const RobotDynamics& d, Eigen::Index n, const char* what) {
  if (n != d.nv()) throw ModelError(std::string(what) + " has " + std::to_string(n) + " entries, expected " + std::to_string(d.nv()));
}

}  // namespace

Eigen::VectorXd inverse_dynamics(const RobotDynamics& dynamics, const Eigen::Ref<const Eigen::VectorXd>& vdot) {
  check_size(dynamics, vdot.size(), "acceleration");
  return dynamics.mass_matrix() * vdot + dynamics.coriolis_and_gravity();
}

Eigen::VectorXd forward_dynamics(const RobotDynamics& dynamics, const Eigen::Ref<const Eigen::VectorXd>& tau) {
  check_size(dynamics, tau.size(), "generalized force");
  const Eigen::LLT<Eigen::MatrixXd> A(dynamics.mass_matrix());
  if (A.info() != Eigen::Success)
    throw ModelError("forward dynamics: the mass matrix is not positive definite here (a joint that moves no inertia?)");
  return A.solve(tau - dynamics.coriolis_and_gravity());
}

}  // namespace dmbd::model
