// The robot's momentum from the mass matrix's base rows (momentum.hpp).
#include "dmbd/wholebody/momentum.hpp"

namespace dmbd::wholebody {

Eigen::Vector3d angular_momentum_about(const ModelData& data, const Eigen::Vector3d& p) {
  Eigen::Matrix<double, 6, 1> h;
  h.noalias() = data.A.topRows<6>() * data.v;
  const Eigen::Vector3d origin = data.q.segment<3>(4);  // [quaternion (4), origin (3), joints]
  return h.head<3>() + (origin - p).cross(h.tail<3>());
}

Eigen::Vector2d contact_pendulum_velocity(const ModelData& data, const Eigen::Vector3d& p, double height_m) {
  const Eigen::Vector3d L = angular_momentum_about(data, p);
  const double mass = data.A(3, 3);  // the linear block is m I
  return Eigen::Vector2d(L.y(), -L.x()) / (mass * height_m);
}

}  // namespace dmbd::wholebody
