// RobotDynamics: the URDF's bare multibody tree in Simbody, queried through Simbody's
// O(n) operators (calcM, residual forces, station/frame Jacobians and their bias terms).
#include "dmbd/model/dynamics.hpp"

#include "dmbd/model/error.hpp"
#include "simbody_tree.hpp"

namespace dmbd::model {

using detail::to_eigen;
using detail::to_simtk;

struct RobotDynamics::Impl {
  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter{system};
  SimTK::GeneralForceSubsystem forces{system};
  SimTK::Force::Gravity gravity;
  detail::Tree tree;
  SimTK::State state;
  std::vector<std::string> names;
  double mass = 0;
  const RobotDescription* robot = nullptr;

  Impl(const RobotDescription& r, const DynamicsOptions& o) : robot(&r) {
    gravity = SimTK::Force::Gravity(forces, matter, -SimTK::ZAxis, o.gravity_m_s2);
    tree = detail::build_tree(r, matter, o.base, o.X_WB);
    system.setUseUniformBackground(true);
    state = system.realizeTopology();
    system.realizeModel(state);
    system.realize(state, SimTK::Stage::Position);
    mass = matter.calcSystemMass(state);
  }
  const SimTK::MobilizedBody& body(int link) const {
    if (link < 0 || link >= static_cast<int>(tree.link_body.size()))
      throw ModelError("no link with index " + std::to_string(link));
    return matter.getMobilizedBody(tree.link_body[static_cast<std::size_t>(link)]);
  }
  void need(SimTK::Stage st) const { system.realize(state, st); }
};

namespace {
Eigen::MatrixXd to_eigen(const SimTK::Matrix& m) {
  Eigen::MatrixXd out(m.nrow(), m.ncol());
  for (int i = 0; i < m.nrow(); ++i)
    for (int j = 0; j < m.ncol(); ++j) out(i, j) = m(i, j);
  return out;
}
Eigen::VectorXd to_eigen(const SimTK::Vector& v) {
  Eigen::VectorXd out(v.size());
  for (int i = 0; i < v.size(); ++i) out[i] = v[i];
  return out;
}
}  // namespace

RobotDynamics::RobotDynamics(const RobotDescription& robot, const DynamicsOptions& options)
    : impl_(std::make_unique<Impl>(robot, options)) {}
RobotDynamics::~RobotDynamics() = default;

int RobotDynamics::nq() const { return impl_->state.getNQ(); }
int RobotDynamics::nv() const { return impl_->state.getNU(); }
int RobotDynamics::base_dofs() const { return impl_->tree.base_dofs; }
const std::vector<std::string>& RobotDynamics::joint_names() const { return impl_->tree.joint_names; }
const std::vector<std::string>& RobotDynamics::welded_joints() const { return impl_->tree.welded; }
int RobotDynamics::joint_index(const std::string& name) const {
  for (std::size_t i = 0; i < impl_->tree.joint_names.size(); ++i)
    if (impl_->tree.joint_names[i] == name) return static_cast<int>(i);
  return -1;
}
int RobotDynamics::link_index(const std::string& name) const { return impl_->robot->link_index(name); }
double RobotDynamics::total_mass_kg() const { return impl_->mass; }

Eigen::VectorXd RobotDynamics::neutral_configuration() const {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(nq());
  if (base_dofs()) q[0] = 1.0;
  return q;
}

void RobotDynamics::set_state(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
  detail::scatter_q(impl_->tree, impl_->matter, impl_->state, q);
  detail::scatter_u(impl_->tree, impl_->matter, impl_->state, v);
  // Quaternions are normalised by Simbody when realising Position (setQ does not).
  impl_->matter.normalizeQuaternions(impl_->state);
}

Eigen::MatrixXd RobotDynamics::mass_matrix() const {
  impl_->need(SimTK::Stage::Position);
  SimTK::Matrix M;
  impl_->matter.calcM(impl_->state, M);
  return to_eigen(M);
}

Eigen::VectorXd RobotDynamics::coriolis_and_gravity() const {
  impl_->need(SimTK::Stage::Dynamics);
  // Residual of M vdot + b = f_applied at vdot = 0 with gravity as the applied force:
  // b + g (g = -J^T f_gravity).
  const SimTK::Vector_<SimTK::SpatialVec>& fb = impl_->system.getRigidBodyForces(impl_->state, SimTK::Stage::Dynamics);
  const SimTK::Vector& fm = impl_->system.getMobilityForces(impl_->state, SimTK::Stage::Dynamics);
  SimTK::Vector res;
  impl_->matter.calcResidualForceIgnoringConstraints(impl_->state, fm, fb, SimTK::Vector(), res);
  return to_eigen(res);
}

Eigen::VectorXd RobotDynamics::coriolis() const {
  impl_->need(SimTK::Stage::Velocity);
  SimTK::Vector res;
  impl_->matter.calcResidualForceIgnoringConstraints(impl_->state, SimTK::Vector(), SimTK::Vector_<SimTK::SpatialVec>(),
                                                     SimTK::Vector(), res);
  return to_eigen(res);
}

Eigen::VectorXd RobotDynamics::gravity() const { return coriolis_and_gravity() - coriolis(); }

Eigen::Isometry3d RobotDynamics::link_pose(int link) const {
  impl_->need(SimTK::Stage::Position);
  return to_eigen(impl_->body(link).getBodyTransform(impl_->state));
}

Eigen::Vector3d RobotDynamics::point_position(int link, const Eigen::Vector3d& p_L) const {
  impl_->need(SimTK::Stage::Position);
  return to_eigen(impl_->body(link).findStationLocationInGround(impl_->state, to_simtk(p_L)));
}

Eigen::MatrixXd RobotDynamics::point_jacobian(int link, const Eigen::Vector3d& p_L) const {
  impl_->need(SimTK::Stage::Position);
  SimTK::Matrix J;
  impl_->matter.calcStationJacobian(impl_->state, impl_->body(link).getMobilizedBodyIndex(), to_simtk(p_L), J);
  return to_eigen(J);
}

Eigen::Vector3d RobotDynamics::point_jacobian_dot_v(int link, const Eigen::Vector3d& p_L) const {
  impl_->need(SimTK::Stage::Velocity);
  return to_eigen(impl_->matter.calcBiasForStationJacobian(impl_->state, impl_->body(link).getMobilizedBodyIndex(),
                                                           to_simtk(p_L)));
}

Eigen::MatrixXd RobotDynamics::frame_jacobian(int link, const Eigen::Vector3d& p_L) const {
  impl_->need(SimTK::Stage::Position);
  SimTK::Matrix J;
  impl_->matter.calcFrameJacobian(impl_->state, impl_->body(link).getMobilizedBodyIndex(), to_simtk(p_L), J);
  return to_eigen(J);
}

Eigen::Matrix<double, 6, 1> RobotDynamics::frame_jacobian_dot_v(int link, const Eigen::Vector3d& p_L) const {
  impl_->need(SimTK::Stage::Velocity);
  const SimTK::SpatialVec b =
      impl_->matter.calcBiasForFrameJacobian(impl_->state, impl_->body(link).getMobilizedBodyIndex(), to_simtk(p_L));
  Eigen::Matrix<double, 6, 1> out;
  out << to_eigen(b[0]), to_eigen(b[1]);
  return out;
}

Eigen::Vector3d RobotDynamics::com_position() const {
  impl_->need(SimTK::Stage::Position);
  return to_eigen(impl_->matter.calcSystemMassCenterLocationInGround(impl_->state));
}

Eigen::MatrixXd RobotDynamics::com_jacobian() const {
  impl_->need(SimTK::Stage::Position);
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(3, nv());
  if (impl_->mass <= 0) return J;
  const int nb = impl_->matter.getNumBodies();
  for (SimTK::MobilizedBodyIndex b(1); b < nb; ++b) {
    const SimTK::MassProperties& mp = impl_->matter.getMobilizedBody(b).getBodyMassProperties(impl_->state);
    if (mp.getMass() <= 0) continue;
    SimTK::Matrix Jb;
    impl_->matter.calcStationJacobian(impl_->state, b, mp.getMassCenter(), Jb);
    J += mp.getMass() / impl_->mass * to_eigen(Jb);
  }
  return J;
}

Eigen::Vector3d RobotDynamics::com_jacobian_dot_v() const {
  impl_->need(SimTK::Stage::Velocity);
  Eigen::Vector3d a = Eigen::Vector3d::Zero();
  if (impl_->mass <= 0) return a;
  const int nb = impl_->matter.getNumBodies();
  for (SimTK::MobilizedBodyIndex b(1); b < nb; ++b) {
    const SimTK::MassProperties& mp = impl_->matter.getMobilizedBody(b).getBodyMassProperties(impl_->state);
    if (mp.getMass() <= 0) continue;
    a += mp.getMass() / impl_->mass *
         to_eigen(impl_->matter.calcBiasForStationJacobian(impl_->state, b, mp.getMassCenter()));
  }
  return a;
}

double RobotDynamics::kinetic_energy() const {
  impl_->need(SimTK::Stage::Velocity);
  return impl_->matter.calcKineticEnergy(impl_->state);
}

double RobotDynamics::potential_energy() const {
  impl_->need(SimTK::Stage::Dynamics);
  return impl_->system.calcPotentialEnergy(impl_->state);
}

}  // namespace dmbd::model
