// balanceinertia (MuJoCo's rule): see dmbd/model/inertia_repair.hpp.
#include "dmbd/model/inertia_repair.hpp"

#include <Eigen/Eigenvalues>

namespace dmbd::model {

Eigen::Vector3d principal_moments(const Eigen::Matrix3d& inertia) {
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(inertia, Eigen::EigenvaluesOnly).eigenvalues();
}

double triangle_excess(const Eigen::Vector3d& m) {
  const double ab = m[0] + m[1];
  return (m[2] - ab) / ab;
}

Eigen::Matrix3d balance_inertia(const Eigen::Matrix3d& inertia) {
  // R diag(m, m, m) R^T = m R R^T = m I for any rotation R: written as m I, so the
  // result is exact (no rounding from the eigenvectors) and the same in every frame.
  // The trace is the sum of the principal moments.
  return (inertia.trace() / 3.0) * Eigen::Matrix3d::Identity();
}

}  // namespace dmbd::model
