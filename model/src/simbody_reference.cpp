// SimbodyReference: each quantity from Simbody's own operator on its own Simbody system
// (see the header). Nothing here is shared with the tree kernel but build_tree, so the
// Python model's engine="simbody" and the tests compare two computations.
#include "dmbd/model/simbody_reference.hpp"

#include "dmbd/model/error.hpp"
#include "simbody_tree.hpp"

#include <string>

namespace dmbd::model {

struct SimbodyReference::Impl {
  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter{system};
  SimTK::GeneralForceSubsystem forces{system};
  detail::Tree tree;
  mutable SimTK::State state;
  Eigen::VectorXd q, v;
  std::vector<int> quaternion_q;  // first q of each quaternion (Free mobilizers)

  Impl(const RobotDescription& robot, const DynamicsOptions& o) {
    tree = detail::build_tree(robot, matter, o.base, o.X_WB);
    SimTK::Force::Gravity(forces, matter, SimTK::UnitVec3(0, 0, -1), o.gravity_m_s2);
    state = system.realizeTopology();
    system.realizeModel(state);
    for (int b = 1; b < matter.getNumBodies(); ++b) {
      const SimTK::MobilizedBody& mb = matter.getMobilizedBody(SimTK::MobilizedBodyIndex(b));
      if (mb.getNumQ(state) - mb.getNumU(state) == 1) quaternion_q.push_back(mb.getFirstQIndex(state));
    }
    q = Eigen::VectorXd::Zero(state.getNQ());
    for (int i = 0; i < q.size(); ++i) q[i] = state.getQ()[i];
    v = Eigen::VectorXd::Zero(state.getNU());
  }

  int nq() const { return static_cast<int>(q.size()); }
  int nv() const { return static_cast<int>(v.size()); }

  // Simbody's State at q and the velocity u, realised to `stage`.
  void realize(const Eigen::VectorXd& u, SimTK::Stage stage) const {
    for (int i = 0; i < nq(); ++i) state.updQ()[i] = q[i];
    for (int i = 0; i < nv(); ++i) state.updU()[i] = u[i];
    system.realize(state, stage);
  }

  SimTK::MobilizedBodyIndex body(int link) const {
    if (link < 0 || link >= static_cast<int>(tree.link_body.size()))
      throw ModelError("no link with index " + std::to_string(link));
    return tree.link_body[static_cast<std::size_t>(link)];
  }

  // M vdot + b + g at velocity u, the applied forces those of Force::Gravity (the State
  // realised to Dynamics so that the force subsystem has computed them).
  Eigen::VectorXd residual(const Eigen::VectorXd& u, const Eigen::Ref<const Eigen::VectorXd>& vdot) const {
    realize(u, SimTK::Stage::Dynamics);
    SimTK::Vector udot(nv()), res;
    for (int i = 0; i < nv(); ++i) udot[i] = vdot[i];
    matter.calcResidualForceIgnoringConstraints(state, system.getMobilityForces(state, SimTK::Stage::Dynamics),
                                                system.getRigidBodyForces(state, SimTK::Stage::Dynamics), udot, res);
    return to_eigen(res);
  }

  static Eigen::VectorXd to_eigen(const SimTK::Vector& x) {
    Eigen::VectorXd out(x.size());
    for (int i = 0; i < x.size(); ++i) out[i] = x[i];
    return out;
  }
  static Eigen::MatrixXd to_eigen(const SimTK::Matrix& x) {
    Eigen::MatrixXd out(x.nrow(), x.ncol());
    for (int i = 0; i < x.nrow(); ++i)
      for (int j = 0; j < x.ncol(); ++j) out(i, j) = x(i, j);
    return out;
  }
};

SimbodyReference::SimbodyReference(const RobotDescription& robot, const DynamicsOptions& options)
    : impl_(std::make_unique<Impl>(robot, options)) {}
SimbodyReference::~SimbodyReference() = default;

int SimbodyReference::nq() const { return impl_->nq(); }
int SimbodyReference::nv() const { return impl_->nv(); }

void SimbodyReference::set_state(const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& v) {
  if (q.size() != nq())
    throw ModelError("configuration has " + std::to_string(q.size()) + " entries, expected " + std::to_string(nq()));
  if (v.size() != nv())
    throw ModelError("velocity has " + std::to_string(v.size()) + " entries, expected " + std::to_string(nv()));
  impl_->q = q;
  impl_->v = v;
  for (int i : impl_->quaternion_q) impl_->q.segment<4>(i).normalize();
}

Eigen::MatrixXd SimbodyReference::mass_matrix() const {
  impl_->realize(impl_->v, SimTK::Stage::Position);
  SimTK::Matrix M;
  impl_->matter.calcM(impl_->state, M);
  return Impl::to_eigen(M);
}

Eigen::VectorXd SimbodyReference::coriolis_and_gravity() const {
  return impl_->residual(impl_->v, Eigen::VectorXd::Zero(nv()));
}

Eigen::VectorXd SimbodyReference::gravity() const {
  return impl_->residual(Eigen::VectorXd::Zero(nv()), Eigen::VectorXd::Zero(nv()));
}

Eigen::VectorXd SimbodyReference::inverse_dynamics(const Eigen::Ref<const Eigen::VectorXd>& vdot) const {
  if (vdot.size() != nv())
    throw ModelError("acceleration has " + std::to_string(vdot.size()) + " entries, expected " + std::to_string(nv()));
  return impl_->residual(impl_->v, vdot);
}

Eigen::VectorXd SimbodyReference::forward_dynamics(const Eigen::Ref<const Eigen::VectorXd>& tau) const {
  if (tau.size() != nv())
    throw ModelError("generalized force has " + std::to_string(tau.size()) + " entries, expected " + std::to_string(nv()));
  const Impl& k = *impl_;
  k.realize(k.v, SimTK::Stage::Dynamics);
  SimTK::Vector f = k.system.getMobilityForces(k.state, SimTK::Stage::Dynamics);
  for (int i = 0; i < nv(); ++i) f[i] += tau[i];
  SimTK::Vector udot;
  SimTK::Vector_<SimTK::SpatialVec> A_GB;
  k.matter.calcAccelerationIgnoringConstraints(k.state, f, k.system.getRigidBodyForces(k.state, SimTK::Stage::Dynamics),
                                               udot, A_GB);
  return Impl::to_eigen(udot);
}

Eigen::Isometry3d SimbodyReference::link_pose(int link) const {
  impl_->realize(impl_->v, SimTK::Stage::Position);
  return detail::to_eigen(impl_->matter.getMobilizedBody(impl_->body(link)).getBodyTransform(impl_->state));
}

Eigen::MatrixXd SimbodyReference::frame_jacobian(int link, const Eigen::Vector3d& p_L) const {
  impl_->realize(impl_->v, SimTK::Stage::Position);
  SimTK::Matrix J;
  impl_->matter.calcFrameJacobian(impl_->state, impl_->body(link), detail::to_simtk(p_L), J);
  return Impl::to_eigen(J);
}

Eigen::Vector3d SimbodyReference::com_position() const {
  impl_->realize(impl_->v, SimTK::Stage::Position);
  return detail::to_eigen(impl_->matter.calcSystemMassCenterLocationInGround(impl_->state));
}

Eigen::MatrixXd SimbodyReference::com_jacobian() const {
  Eigen::MatrixXd J(3, nv());
  for (int i = 0; i < nv(); ++i) {
    impl_->realize(Eigen::VectorXd::Unit(nv(), i), SimTK::Stage::Velocity);
    J.col(i) = detail::to_eigen(impl_->matter.calcSystemMassCenterVelocityInGround(impl_->state));
  }
  return J;
}

}  // namespace dmbd::model
