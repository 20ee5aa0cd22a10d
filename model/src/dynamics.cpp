// RobotDynamics: the URDF's bare multibody tree, queried through the tree kernel
// (Simbody's kinematics, the dynamics terms assembled without allocation).
#include "dmbd/model/dynamics.hpp"

#include "dmbd/model/error.hpp"
#include "tree_kernel.hpp"

namespace dmbd::model {

struct RobotDynamics::Impl {
  const RobotDescription* robot;
  detail::TreeKernel kernel;
  Impl(const RobotDescription& r, const DynamicsOptions& o) : robot(&r), kernel(r, o.base, o.X_WB, o.gravity_m_s2) {}
  int body(int link) const { return kernel.body_of_link(link); }
  Eigen::Vector3d world(int link, const Eigen::Vector3d& p_L) const {
    const int b = body(link);
    return kernel.origin(b) + kernel.rotation(b) * p_L;
  }
};

RobotDynamics::RobotDynamics(const RobotDescription& robot, const DynamicsOptions& options)
    : impl_(std::make_unique<Impl>(robot, options)) {}
RobotDynamics::~RobotDynamics() = default;

int RobotDynamics::nq() const { return impl_->kernel.nq(); }
int RobotDynamics::nv() const { return impl_->kernel.nv(); }
int RobotDynamics::base_dofs() const { return impl_->kernel.base_dofs(); }
const std::vector<std::string>& RobotDynamics::joint_names() const { return impl_->kernel.joint_names(); }
const std::vector<std::string>& RobotDynamics::welded_joints() const { return impl_->kernel.welded_joints(); }
int RobotDynamics::joint_index(const std::string& name) const {
  const auto& n = joint_names();
  for (std::size_t i = 0; i < n.size(); ++i)
    if (n[i] == name) return static_cast<int>(i);
  return -1;
}
int RobotDynamics::joint_q_index(int joint) const { return impl_->kernel.joint_q(joint); }
int RobotDynamics::joint_v_index(int joint) const { return impl_->kernel.joint_v(joint); }
int RobotDynamics::link_index(const std::string& name) const { return impl_->robot->link_index(name); }
double RobotDynamics::total_mass_kg() const { return impl_->kernel.total_mass_kg(); }

Eigen::VectorXd RobotDynamics::neutral_configuration() const { return impl_->kernel.neutral_q(); }

void RobotDynamics::set_state(const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& v) {
  impl_->kernel.set_q(q);
  impl_->kernel.set_v(v);
}

void RobotDynamics::mass_matrix(Eigen::Ref<Eigen::MatrixXd> A) const { impl_->kernel.mass_matrix(A); }
void RobotDynamics::coriolis_and_gravity(Eigen::Ref<Eigen::VectorXd> bg) const { impl_->kernel.coriolis_and_gravity(bg); }
void RobotDynamics::gravity(Eigen::Ref<Eigen::VectorXd> g) const { impl_->kernel.gravity(g); }
void RobotDynamics::coriolis(Eigen::Ref<Eigen::VectorXd> b) const { impl_->kernel.coriolis(b); }
void RobotDynamics::point_jacobian(int link, const Eigen::Vector3d& p_L, Eigen::Ref<Eigen::MatrixXd> J) const {
  impl_->kernel.point_jacobian(impl_->body(link), impl_->world(link, p_L), J);
}
void RobotDynamics::frame_jacobian(int link, const Eigen::Vector3d& p_L, Eigen::Ref<Eigen::MatrixXd> J) const {
  impl_->kernel.frame_jacobian(impl_->body(link), impl_->world(link, p_L), J);
}
void RobotDynamics::com_jacobian(Eigen::Ref<Eigen::MatrixXd> J) const { impl_->kernel.com_jacobian(J); }

Eigen::MatrixXd RobotDynamics::mass_matrix() const {
  Eigen::MatrixXd A(nv(), nv());
  mass_matrix(A);
  return A;
}
Eigen::VectorXd RobotDynamics::coriolis_and_gravity() const {
  Eigen::VectorXd c(nv());
  coriolis_and_gravity(c);
  return c;
}
Eigen::VectorXd RobotDynamics::gravity() const {
  Eigen::VectorXd g(nv());
  gravity(g);
  return g;
}
Eigen::VectorXd RobotDynamics::coriolis() const {
  Eigen::VectorXd c(nv());
  coriolis(c);
  return c;
}

Eigen::Isometry3d RobotDynamics::link_pose(int link) const { return impl_->kernel.pose(impl_->body(link)); }
Eigen::Vector3d RobotDynamics::point_position(int link, const Eigen::Vector3d& p_L) const { return impl_->world(link, p_L); }
Eigen::MatrixXd RobotDynamics::point_jacobian(int link, const Eigen::Vector3d& p_L) const {
  Eigen::MatrixXd J(3, nv());
  point_jacobian(link, p_L, J);
  return J;
}
Eigen::Vector3d RobotDynamics::point_jacobian_dot_v(int link, const Eigen::Vector3d& p_L) const {
  return impl_->kernel.point_bias_acceleration(impl_->body(link), impl_->world(link, p_L));
}
Eigen::MatrixXd RobotDynamics::frame_jacobian(int link, const Eigen::Vector3d& p_L) const {
  Eigen::MatrixXd J(6, nv());
  frame_jacobian(link, p_L, J);
  return J;
}
Eigen::Matrix<double, 6, 1> RobotDynamics::frame_jacobian_dot_v(int link, const Eigen::Vector3d& p_L) const {
  return impl_->kernel.frame_bias_acceleration(impl_->body(link), impl_->world(link, p_L));
}

Eigen::Vector3d RobotDynamics::com_position() const { return impl_->kernel.com(); }
Eigen::MatrixXd RobotDynamics::com_jacobian() const {
  Eigen::MatrixXd J(3, nv());
  com_jacobian(J);
  return J;
}
Eigen::Vector3d RobotDynamics::com_jacobian_dot_v() const { return impl_->kernel.com_bias_acceleration(); }

double RobotDynamics::kinetic_energy() const { return impl_->kernel.kinetic_energy(); }
double RobotDynamics::potential_energy() const { return impl_->kernel.gravity_potential(); }

}  // namespace dmbd::model
