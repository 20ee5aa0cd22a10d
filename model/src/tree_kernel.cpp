// TreeKernel: Simbody builds the tree; its poses, hinge columns, velocities and bias
// accelerations are realised here by one outward pass per stage over the mobilizers
// (mobilizer.hpp), and the mass matrix, bias forces and Jacobians are assembled from them
// (see the header for why). Spatial vectors are [angular; linear] in world axes; "at O" means about
// the world origin, so composite inertias and forces add without shifting.
#include "tree_kernel.hpp"

#include "dmbd/model/error.hpp"
#include "mobilizer.hpp"
#include "simbody_tree.hpp"

#include <cmath>

namespace dmbd::model::detail {

namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d S;
  S << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return S;
}

Eigen::Matrix3d to_eigen3(const SimTK::Mat33& m) {
  Eigen::Matrix3d out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out(i, j) = m(i, j);
  return out;
}

// Spatial cross products at O, [angular; linear]: motion x motion and motion x force.
Vector6d cross_motion(const Vector6d& a, const Vector6d& b) {
  Vector6d c;
  c << a.head<3>().cross(b.head<3>()), a.head<3>().cross(b.tail<3>()) + a.tail<3>().cross(b.head<3>());
  return c;
}
Vector6d cross_force(const Vector6d& a, const Vector6d& f) {
  Vector6d c;
  c << a.head<3>().cross(f.head<3>()) + a.tail<3>().cross(f.tail<3>()), a.head<3>().cross(f.tail<3>());
  return c;
}

MobilizerKind kind_of(const SimTK::MobilizedBody& mb) {
  if (SimTK::MobilizedBody::Weld::isInstanceOf(mb)) return MobilizerKind::Weld;
  if (SimTK::MobilizedBody::Pin::isInstanceOf(mb)) return MobilizerKind::Pin;
  if (SimTK::MobilizedBody::Slider::isInstanceOf(mb)) return MobilizerKind::Slider;
  if (SimTK::MobilizedBody::Free::isInstanceOf(mb)) return MobilizerKind::Free;
  if (SimTK::MobilizedBody::Planar::isInstanceOf(mb)) return MobilizerKind::Planar;
  throw ModelError("tree kernel: a mobilizer of a kind it does not know");
}

}  // namespace

struct TreeKernel::Impl {
  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter{system};
  Tree tree;
  mutable SimTK::State state;
  double gravity = 9.81, mass = 0;
  int nb = 0, nq = 0, nv = 0;
  Eigen::VectorXd q, v;
  mutable bool pos_ok = false, vel_ok = false;

  // Per body (index 0 = ground, unused).
  std::vector<double> m;
  std::vector<Eigen::Vector3d> com_B;
  std::vector<Eigen::Matrix3d> Icom_B;
  std::vector<int> parent, first_u, num_u;
  std::vector<std::vector<int>> anc_u;  // mobilities moving the body, ascending
  std::vector<int> quat_q;              // first q of each quaternion
  std::vector<int> joint_q, joint_v, joint_body;
  std::vector<Mobilizer> mob;           // per body
  std::vector<Vector6d> H;              // per mobility: its hinge column in F

  // Caches at q.
  mutable std::vector<Eigen::Matrix3d> R, R_F;  // R_WB; R_WF of the body's mobilizer
  mutable std::vector<Eigen::Vector3d> o, o_M, com_W, hsub;
  mutable std::vector<double> msub;
  mutable std::vector<Matrix6d> Ib, Ic;  // the body's and its subtree's spatial inertia at O
  mutable std::vector<Vector6d> S;       // per mobility: motion at O
  // Caches at (q, v).
  mutable std::vector<Eigen::Vector3d> w, vo;
  mutable std::vector<Vector6d> V, A;        // spatial velocity and bias acceleration at O
  mutable std::vector<Vector6d> cor, fcent;  // Coriolis acceleration at the origin; centrifugal force at O
  mutable std::vector<Vector6d> fsub;       // scratch: subtree forces
  mutable SimTK::Vector u_sim, qdot_sim;
  mutable Eigen::VectorXd qdot_buf;
  int root_q = 0;

  Impl(const RobotDescription& r, BaseMode base, const Eigen::Isometry3d& X_WB, double g, const std::vector<double>& taken)
      : gravity(g) {
    tree = build_tree(r, matter, base, X_WB, taken);
    system.setUseUniformBackground(true);
    state = system.realizeTopology();
    system.realizeModel(state);
    system.realize(state, SimTK::Stage::Instance);
    nb = matter.getNumBodies();
    nq = state.getNQ();
    nv = state.getNU();
    q = Eigen::VectorXd::Zero(nq);
    v = Eigen::VectorXd::Zero(nv);
    for (int i = 0; i < nq; ++i) q[i] = state.getQ()[i];
    size_caches();
    describe_bodies();
    for (SimTK::MobilizedBodyIndex b : tree.coord_body) {
      const SimTK::MobilizedBody& mb = matter.getMobilizedBody(b);
      joint_q.push_back(mb.getFirstQIndex(state));
      joint_v.push_back(mb.getFirstUIndex(state));
      joint_body.push_back(b);
    }
    root_q = matter.getMobilizedBody(tree.root).getFirstQIndex(state);
    u_sim.resize(nv);
    qdot_sim.resize(nq);
    qdot_buf = Eigen::VectorXd::Zero(nq);
  }

  void size_caches() {
    const auto n = static_cast<std::size_t>(nb);
    m.assign(n, 0.0);
    com_B.assign(n, Eigen::Vector3d::Zero());
    Icom_B.assign(n, Eigen::Matrix3d::Zero());
    parent.assign(n, -1);
    first_u.assign(n, 0);
    num_u.assign(n, 0);
    anc_u.assign(n, {});
    R.assign(n, Eigen::Matrix3d::Identity());
    R_F.assign(n, Eigen::Matrix3d::Identity());
    o.assign(n, Eigen::Vector3d::Zero());
    o_M.assign(n, Eigen::Vector3d::Zero());
    mob.assign(n, Mobilizer{});
    H.assign(static_cast<std::size_t>(nv), Vector6d::Zero());
    com_W.assign(n, Eigen::Vector3d::Zero());
    hsub.assign(n, Eigen::Vector3d::Zero());
    msub.assign(n, 0.0);
    Ib.assign(n, Matrix6d::Zero());
    Ic.assign(n, Matrix6d::Zero());
    S.assign(static_cast<std::size_t>(nv), Vector6d::Zero());
    w.assign(n, Eigen::Vector3d::Zero());
    vo.assign(n, Eigen::Vector3d::Zero());
    V.assign(n, Vector6d::Zero());
    A.assign(n, Vector6d::Zero());
    cor.assign(n, Vector6d::Zero());
    fcent.assign(n, Vector6d::Zero());
    fsub.assign(n, Vector6d::Zero());
  }

  void describe_bodies() {
    for (int b = 1; b < nb; ++b) {
      const SimTK::MobilizedBody& mb = matter.getMobilizedBody(SimTK::MobilizedBodyIndex(b));
      const SimTK::MassProperties& mp = mb.getBodyMassProperties(state);
      const auto k = static_cast<std::size_t>(b);
      m[k] = mp.getMass();
      com_B[k] = to_eigen(mp.getMassCenter());
      if (m[k] > 0) Icom_B[k] = to_eigen3(mp.calcCentralInertia().toMat33());
      parent[k] = mb.getParentMobilizedBody().getMobilizedBodyIndex();
      first_u[k] = mb.getFirstUIndex(state);
      num_u[k] = mb.getNumU(state);
      if (mb.getNumQ(state) - mb.getNumU(state) == 1) quat_q.push_back(mb.getFirstQIndex(state));
      mass += m[k];
      describe_mobilizer(mb, k);
      // Ancestors are built before their children (parent index < child index).
      if (parent[k] > 0) anc_u[k] = anc_u[static_cast<std::size_t>(parent[k])];
      for (int u = 0; u < num_u[k]; ++u) anc_u[k].push_back(first_u[k] + u);
    }
  }

  void describe_mobilizer(const SimTK::MobilizedBody& mb, std::size_t k) {
    Mobilizer& d = mob[k];
    d.kind = kind_of(mb);
    d.first_q = mb.getFirstQIndex(state);
    d.first_u = first_u[k];
    d.nq = mb.getNumQ(state);
    d.nu = num_u[k];
    const SimTK::Transform& X_PF = mb.getDefaultInboardFrame();
    const SimTK::Transform X_MB = ~mb.getDefaultOutboardFrame();
    d.R_PF = to_eigen3(X_PF.R().asMat33());
    d.p_PF = to_eigen(X_PF.p());
    d.R_MB = to_eigen3(X_MB.R().asMat33());
    d.p_MB = to_eigen(X_MB.p());
    for (int u = 0; u < d.nu; ++u) H[static_cast<std::size_t>(d.first_u + u)] = mobilizer_column(d.kind, u);
  }

  // Simbody's state at the kernel's q (and v), realised: for the reference operators only.
  void realize_simbody(bool velocity) const {
    for (int i = 0; i < nq; ++i) state.updQ()[i] = q[i];
    for (int i = 0; i < nv; ++i) state.updU()[i] = v[i];
    system.realize(state, velocity ? SimTK::Stage::Velocity : SimTK::Stage::Position);
  }

  void need_position() const {
    if (pos_ok) return;
    for (int b = 1; b < nb; ++b) {
      place(b);
      position_terms(b);
    }
    composite_terms();
    pos_ok = true;
  }

  // X_WB = X_WP X_PF X_FM(q) X_MB (the parent is placed first: its index is smaller).
  void place(int b) const {
    const auto k = static_cast<std::size_t>(b), p = static_cast<std::size_t>(parent[k]);
    const Mobilizer& d = mob[k];
    Eigen::Matrix3d R_FM;
    Eigen::Vector3d p_FM;
    mobilizer_transform(d, q, R_FM, p_FM);
    R_F[k] = R[p] * d.R_PF;
    o_M[k] = o[p] + R[p] * d.p_PF + R_F[k] * p_FM;
    const Eigen::Matrix3d R_M = R_F[k] * R_FM;
    R[k] = R_M * d.R_MB;
    o[k] = o_M[k] + R_M * d.p_MB;
  }

  void position_terms(int b) const {
    const auto k = static_cast<std::size_t>(b);
    com_W[k] = o[k] + R[k] * com_B[k];
    for (int u = 0; u < num_u[k]; ++u) {
      const auto i = static_cast<std::size_t>(first_u[k] + u);
      const Eigen::Vector3d hw = R_F[k] * H[i].head<3>(), hv = R_F[k] * H[i].tail<3>();
      S[i] << hw, hv - hw.cross(o_M[k]);  // the velocity at O of a point moving with M
    }
    // Spatial inertia at O: [I_c + m [c]x [c]x^T, m [c]x; m [c]x^T, m 1].
    const Eigen::Matrix3d cx = skew(com_W[k]);
    Matrix6d& I = Ib[k];
    I.topLeftCorner<3, 3>() = R[k] * Icom_B[k] * R[k].transpose() + m[k] * cx * cx.transpose();
    I.topRightCorner<3, 3>() = m[k] * cx;
    I.bottomLeftCorner<3, 3>() = m[k] * cx.transpose();
    I.bottomRightCorner<3, 3>() = m[k] * Eigen::Matrix3d::Identity();
    Ic[k] = I;
    msub[k] = m[k];
    hsub[k] = m[k] * com_W[k];
  }

  // Ic, msub and hsub become the subtree sums (children have larger indices).
  void composite_terms() const {
    for (int b = nb - 1; b >= 1; --b) {
      const int p = parent[static_cast<std::size_t>(b)];
      if (p < 1) continue;
      Ic[static_cast<std::size_t>(p)] += Ic[static_cast<std::size_t>(b)];
      msub[static_cast<std::size_t>(p)] += msub[static_cast<std::size_t>(b)];
      hsub[static_cast<std::size_t>(p)] += hsub[static_cast<std::size_t>(b)];
    }
  }

  void need_velocity() const {
    need_position();
    if (vel_ok) return;
    for (int b = 1; b < nb; ++b) velocity_terms(b);
    vel_ok = true;
  }

  // V_B = V_P + sum S_u v_u; the bias acceleration (vdot = 0) A_B = A_P + V_P x V_B, plus,
  // when M's origin slides in F (Free, Planar), v_rel x w_rel from the hinge columns
  // about that moving origin; the force that acceleration takes, I A_B + V_B x* (I V_B).
  void velocity_terms(int b) const {
    const auto k = static_cast<std::size_t>(b), p = static_cast<std::size_t>(parent[k]);
    Vector6d dV = Vector6d::Zero();
    Eigen::Vector3d v_rel_F = Eigen::Vector3d::Zero();
    for (int u = 0; u < num_u[k]; ++u) {
      const auto i = static_cast<std::size_t>(first_u[k] + u);
      dV += S[i] * v[static_cast<Eigen::Index>(i)];
      v_rel_F += H[i].tail<3>() * v[static_cast<Eigen::Index>(i)];
    }
    V[k] = V[p] + dV;
    A[k] = A[p] + cross_motion(V[p], V[k]);
    A[k].tail<3>() += (R_F[k] * v_rel_F).cross(dV.head<3>());
    w[k] = V[k].head<3>();
    vo[k] = V[k].tail<3>() + w[k].cross(o[k]);
    cor[k] << A[k].head<3>(), A[k].tail<3>() + A[k].head<3>().cross(o[k]) + w[k].cross(vo[k]);
    fcent[k] = Ib[k] * A[k] + cross_force(V[k], Ib[k] * V[k]);
  }

  // tau_u = S_u^T (sum over the subtree of body(u) of f_b), f_b spatial forces at O.
  template <class BodyForce>
  void generalized_forces(Eigen::Ref<Eigen::VectorXd> tau, BodyForce force) const {
    for (int b = 1; b < nb; ++b) fsub[static_cast<std::size_t>(b)] = force(b);
    for (int b = nb - 1; b >= 1; --b) {
      const int p = parent[static_cast<std::size_t>(b)];
      if (p >= 1) fsub[static_cast<std::size_t>(p)] += fsub[static_cast<std::size_t>(b)];
    }
    for (int b = 1; b < nb; ++b)
      for (int u = 0; u < num_u[static_cast<std::size_t>(b)]; ++u) {
        const int i = first_u[static_cast<std::size_t>(b)] + u;
        tau[i] = S[static_cast<std::size_t>(i)].dot(fsub[static_cast<std::size_t>(b)]);
      }
  }

  Vector6d gravity_force(int b) const {
    const auto k = static_cast<std::size_t>(b);
    const Eigen::Vector3d F(0, 0, -gravity * m[k]);
    Vector6d f;
    f << com_W[k].cross(F), F;
    return f;
  }
};

TreeKernel::TreeKernel(const RobotDescription& robot, BaseMode base, const Eigen::Isometry3d& X_WB, double gravity_m_s2,
                       const std::vector<double>& mass_taken)
    : impl_(std::make_unique<Impl>(robot, base, X_WB, gravity_m_s2, mass_taken)) {}
TreeKernel::~TreeKernel() = default;

int TreeKernel::nq() const { return impl_->nq; }
int TreeKernel::nv() const { return impl_->nv; }
int TreeKernel::base_dofs() const { return impl_->tree.base_dofs; }
int TreeKernel::num_bodies() const { return impl_->nb; }
int TreeKernel::body_of_link(int link) const {
  if (link < 0 || link >= static_cast<int>(impl_->tree.link_body.size()))
    throw ModelError("no link with index " + std::to_string(link));
  return impl_->tree.link_body[static_cast<std::size_t>(link)];
}
const std::vector<std::string>& TreeKernel::joint_names() const { return impl_->tree.joint_names; }
const std::vector<int>& TreeKernel::joint_description_index() const { return impl_->tree.coord_joint; }
const std::vector<std::string>& TreeKernel::welded_joints() const { return impl_->tree.welded; }
int TreeKernel::joint_q(int joint) const { return impl_->joint_q.at(static_cast<std::size_t>(joint)); }
int TreeKernel::joint_v(int joint) const { return impl_->joint_v.at(static_cast<std::size_t>(joint)); }
int TreeKernel::joint_body(int joint) const { return impl_->joint_body.at(static_cast<std::size_t>(joint)); }
int TreeKernel::parent_body(int body) const { return impl_->parent.at(static_cast<std::size_t>(body)); }
double TreeKernel::total_mass_kg() const { return impl_->mass; }
double TreeKernel::body_mass_kg(int body) const { return impl_->m.at(static_cast<std::size_t>(body)); }
double TreeKernel::gravity_m_s2() const { return impl_->gravity; }

void TreeKernel::set_q(const Eigen::Ref<const Eigen::VectorXd>& q) {
  if (q.size() != impl_->nq)
    throw ModelError("configuration has " + std::to_string(q.size()) + " entries, expected " + std::to_string(impl_->nq));
  impl_->q = q;
  normalize(impl_->q);
  impl_->pos_ok = impl_->vel_ok = false;
}
void TreeKernel::set_v(const Eigen::Ref<const Eigen::VectorXd>& v) {
  if (v.size() != impl_->nv)
    throw ModelError("velocity has " + std::to_string(v.size()) + " entries, expected " + std::to_string(impl_->nv));
  impl_->v = v;
  impl_->vel_ok = false;
}
const Eigen::VectorXd& TreeKernel::q() const { return impl_->q; }
const Eigen::VectorXd& TreeKernel::v() const { return impl_->v; }

Eigen::VectorXd TreeKernel::neutral_q() const {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(impl_->nq);
  for (int i : impl_->quat_q) q[i] = 1.0;
  return q;
}

void TreeKernel::set_base_pose(Eigen::Ref<Eigen::VectorXd> q, const Eigen::Isometry3d& X_WB) const {
  if (!impl_->tree.base_dofs) return;
  const Eigen::Quaterniond Q(X_WB.linear());
  const int i = impl_->root_q;
  q.segment<4>(i) << Q.w(), Q.x(), Q.y(), Q.z();
  q.segment<3>(i + 4) = X_WB.translation();
}

Eigen::Isometry3d TreeKernel::pose(int body) const {
  impl_->need_position();
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = impl_->R[static_cast<std::size_t>(body)];
  X.translation() = impl_->o[static_cast<std::size_t>(body)];
  return X;
}
const Eigen::Matrix3d& TreeKernel::rotation(int body) const {
  impl_->need_position();
  return impl_->R[static_cast<std::size_t>(body)];
}
const Eigen::Vector3d& TreeKernel::origin(int body) const {
  impl_->need_position();
  return impl_->o[static_cast<std::size_t>(body)];
}
Eigen::Vector3d TreeKernel::angular_velocity(int body) const {
  impl_->need_velocity();
  return impl_->w[static_cast<std::size_t>(body)];
}
Eigen::Vector3d TreeKernel::point_velocity(int body, const Eigen::Vector3d& p_W) const {
  impl_->need_velocity();
  const auto k = static_cast<std::size_t>(body);
  return impl_->vo[k] + impl_->w[k].cross(p_W - impl_->o[k]);
}

const std::vector<int>& TreeKernel::body_mobilities(int body) const { return impl_->anc_u.at(static_cast<std::size_t>(body)); }

void TreeKernel::point_jacobian(int body, const Eigen::Vector3d& p_W, Eigen::Ref<Eigen::MatrixXd> J) const {
  impl_->need_position();
  J.setZero();
  for (int u : impl_->anc_u[static_cast<std::size_t>(body)]) {
    const Vector6d& s = impl_->S[static_cast<std::size_t>(u)];
    J.col(u) = s.tail<3>() + s.head<3>().cross(p_W);
  }
}

void TreeKernel::frame_jacobian(int body, const Eigen::Vector3d& p_W, Eigen::Ref<Eigen::MatrixXd> J) const {
  impl_->need_position();
  J.setZero();
  for (int u : impl_->anc_u[static_cast<std::size_t>(body)]) {
    const Vector6d& s = impl_->S[static_cast<std::size_t>(u)];
    J.col(u).head<3>() = s.head<3>();
    J.col(u).tail<3>() = s.tail<3>() + s.head<3>().cross(p_W);
  }
}

void TreeKernel::point_jacobian_columns(int body, const Eigen::Vector3d& p_W, Eigen::Ref<Eigen::Matrix3Xd> J) const {
  impl_->need_position();
  const std::vector<int>& a = impl_->anc_u[static_cast<std::size_t>(body)];
  for (std::size_t c = 0; c < a.size(); ++c) {
    const Vector6d& s = impl_->S[static_cast<std::size_t>(a[c])];
    J.col(static_cast<Eigen::Index>(c)) = s.tail<3>() + s.head<3>().cross(p_W);
  }
}

void TreeKernel::frame_jacobian_columns(int body, const Eigen::Vector3d& p_W,
                                        Eigen::Ref<Eigen::Matrix<double, 6, Eigen::Dynamic>> J) const {
  impl_->need_position();
  const std::vector<int>& a = impl_->anc_u[static_cast<std::size_t>(body)];
  for (std::size_t c = 0; c < a.size(); ++c) {
    const Vector6d& s = impl_->S[static_cast<std::size_t>(a[c])];
    const auto i = static_cast<Eigen::Index>(c);
    J.col(i).head<3>() = s.head<3>();
    J.col(i).tail<3>() = s.tail<3>() + s.head<3>().cross(p_W);
  }
}

Eigen::Vector3d TreeKernel::point_bias_acceleration(int body, const Eigen::Vector3d& p_W) const {
  impl_->need_velocity();
  const auto k = static_cast<std::size_t>(body);
  const Eigen::Vector3d r = p_W - impl_->o[k], &w = impl_->w[k];
  return impl_->cor[k].tail<3>() + impl_->cor[k].head<3>().cross(r) + w.cross(w.cross(r));
}

Vector6d TreeKernel::frame_bias_acceleration(int body, const Eigen::Vector3d& p_W) const {
  Vector6d a;
  a << impl_->cor[static_cast<std::size_t>(body)].head<3>(), point_bias_acceleration(body, p_W);
  return a;
}

void TreeKernel::mass_matrix(Eigen::Ref<Eigen::MatrixXd> M) const {
  const Impl& k = *impl_;
  k.need_position();
  M.setZero();
  for (int b = 1; b < k.nb; ++b) {
    const auto bi = static_cast<std::size_t>(b);
    for (int du = 0; du < k.num_u[bi]; ++du) {
      const int i = k.first_u[bi] + du;
      const Vector6d F = k.Ic[bi] * k.S[static_cast<std::size_t>(i)];
      for (int j : k.anc_u[bi]) {
        if (j > i) break;  // ascending; the rest of this body's own mobilities come later
        const double mij = k.S[static_cast<std::size_t>(j)].dot(F);
        M(j, i) = mij;
        M(i, j) = mij;
      }
    }
  }
}

void TreeKernel::coriolis_and_gravity(Eigen::Ref<Eigen::VectorXd> c) const {
  impl_->need_velocity();
  impl_->generalized_forces(c, [&](int b) -> Vector6d { return impl_->fcent[static_cast<std::size_t>(b)] - impl_->gravity_force(b); });
}
void TreeKernel::gravity(Eigen::Ref<Eigen::VectorXd> g) const {
  impl_->need_position();
  impl_->generalized_forces(g, [&](int b) -> Vector6d { return -impl_->gravity_force(b); });
}
void TreeKernel::coriolis(Eigen::Ref<Eigen::VectorXd> c) const {
  impl_->need_velocity();
  impl_->generalized_forces(c, [&](int b) -> Vector6d { return impl_->fcent[static_cast<std::size_t>(b)]; });
}

Eigen::Vector3d TreeKernel::com() const {
  impl_->need_position();
  const int root = impl_->tree.root;
  // The root's subtree is the whole moving tree (the root is the only child of ground).
  return impl_->mass > 0 ? Eigen::Vector3d(impl_->hsub[static_cast<std::size_t>(root)] / impl_->mass) : Eigen::Vector3d::Zero();
}

void TreeKernel::com_jacobian(Eigen::Ref<Eigen::MatrixXd> J) const {
  const Impl& k = *impl_;
  k.need_position();
  J.setZero();
  if (k.mass <= 0) return;
  for (int b = 1; b < k.nb; ++b) {
    const auto bi = static_cast<std::size_t>(b);
    for (int du = 0; du < k.num_u[bi]; ++du) {
      const int i = k.first_u[bi] + du;
      const Vector6d& s = k.S[static_cast<std::size_t>(i)];
      J.col(i) = (k.msub[bi] * s.tail<3>() + s.head<3>().cross(k.hsub[bi])) / k.mass;
    }
  }
}

Eigen::Vector3d TreeKernel::com_bias_acceleration() const {
  const Impl& k = *impl_;
  k.need_velocity();
  Eigen::Vector3d a = Eigen::Vector3d::Zero();
  if (k.mass <= 0) return a;
  for (int b = 1; b < k.nb; ++b) a += k.m[static_cast<std::size_t>(b)] * point_bias_acceleration(b, k.com_W[static_cast<std::size_t>(b)]);
  return a / k.mass;
}

double TreeKernel::kinetic_energy() const {
  const Impl& k = *impl_;
  k.need_velocity();
  double e = 0;
  for (int b = 1; b < k.nb; ++b) {
    const auto bi = static_cast<std::size_t>(b);
    const Eigen::Vector3d vc = k.vo[bi] + k.w[bi].cross(k.com_W[bi] - k.o[bi]);
    const Eigen::Matrix3d I = k.R[bi] * k.Icom_B[bi] * k.R[bi].transpose();
    e += 0.5 * (k.m[bi] * vc.squaredNorm() + k.w[bi].dot(I * k.w[bi]));
  }
  return e;
}

double TreeKernel::gravity_potential() const {
  const Impl& k = *impl_;
  k.need_position();
  double e = 0;
  for (int b = 1; b < k.nb; ++b) e += k.m[static_cast<std::size_t>(b)] * k.gravity * k.com_W[static_cast<std::size_t>(b)].z();
  return e;
}

void TreeKernel::reference_mass_matrix(Eigen::Ref<Eigen::MatrixXd> M) const {
  impl_->realize_simbody(false);
  SimTK::Matrix Ms;
  impl_->matter.calcM(impl_->state, Ms);
  for (int i = 0; i < Ms.nrow(); ++i)
    for (int j = 0; j < Ms.ncol(); ++j) M(i, j) = Ms(i, j);
}

void TreeKernel::reference_coriolis_and_gravity(Eigen::Ref<Eigen::VectorXd> c) const {
  const Impl& k = *impl_;
  k.need_position();
  k.realize_simbody(true);
  SimTK::Vector_<SimTK::SpatialVec> bf(k.nb, SimTK::SpatialVec(SimTK::Vec3(0), SimTK::Vec3(0)));
  for (int b = 1; b < k.nb; ++b) {
    const auto bi = static_cast<std::size_t>(b);
    const Eigen::Vector3d F(0, 0, -k.gravity * k.m[bi]);
    bf[b] = SimTK::SpatialVec(to_simtk(Eigen::Vector3d((k.com_W[bi] - k.o[bi]).cross(F))), to_simtk(F));
  }
  SimTK::Vector res;
  k.matter.calcResidualForceIgnoringConstraints(k.state, SimTK::Vector(k.nv, 0.0), bf, SimTK::Vector(k.nv, 0.0), res);
  for (int i = 0; i < k.nv; ++i) c[i] = res[i];
}

void TreeKernel::reference_point_jacobian(int body, const Eigen::Vector3d& p_W, Eigen::Ref<Eigen::MatrixXd> J) const {
  const Impl& k = *impl_;
  k.realize_simbody(false);
  const SimTK::MobilizedBodyIndex bx(body);
  const SimTK::Vec3 p_B = k.matter.getMobilizedBody(bx).findStationAtGroundPoint(k.state, to_simtk(p_W));
  SimTK::Matrix Js;
  k.matter.calcStationJacobian(k.state, bx, p_B, Js);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < k.nv; ++j) J(i, j) = Js(i, j);
}

Eigen::Vector3d TreeKernel::reference_point_bias_acceleration(int body, const Eigen::Vector3d& p_W) const {
  const Impl& k = *impl_;
  k.realize_simbody(true);
  const SimTK::MobilizedBodyIndex bx(body);
  const SimTK::Vec3 p_B = k.matter.getMobilizedBody(bx).findStationAtGroundPoint(k.state, to_simtk(p_W));
  return to_eigen(k.matter.calcBiasForStationJacobian(k.state, bx, p_B));
}

Eigen::Isometry3d TreeKernel::reference_pose(int body) const {
  impl_->realize_simbody(false);
  return to_eigen(impl_->matter.getMobilizedBody(SimTK::MobilizedBodyIndex(body)).getBodyTransform(impl_->state));
}

Vector6d TreeKernel::reference_velocity(int body) const {
  impl_->realize_simbody(true);
  const SimTK::SpatialVec& V = impl_->matter.getMobilizedBody(SimTK::MobilizedBodyIndex(body)).getBodyVelocity(impl_->state);
  Vector6d out;
  out << to_eigen(V[0]), to_eigen(V[1]);
  return out;
}

void TreeKernel::reference_qdot(const Eigen::Ref<const Eigen::VectorXd>& v, Eigen::Ref<Eigen::VectorXd> qd) const {
  Impl& k = *impl_;
  k.realize_simbody(false);
  for (int i = 0; i < k.nv; ++i) k.u_sim[i] = v[i];
  k.matter.multiplyByN(k.state, false, k.u_sim, k.qdot_sim);
  for (int i = 0; i < k.nq; ++i) qd[i] = k.qdot_sim[i];
}

void TreeKernel::qdot(const Eigen::Ref<const Eigen::VectorXd>& v, Eigen::Ref<Eigen::VectorXd> qd) const {
  const Impl& k = *impl_;
  for (int b = 1; b < k.nb; ++b) mobilizer_qdot(k.mob[static_cast<std::size_t>(b)], k.q, v, qd);
}

void TreeKernel::integrate(Eigen::Ref<Eigen::VectorXd> q, const Eigen::Ref<const Eigen::VectorXd>& v, double h) const {
  const Impl& k = *impl_;
  for (int b = 1; b < k.nb; ++b) mobilizer_qdot(k.mob[static_cast<std::size_t>(b)], k.q, v, k.qdot_buf);
  q += h * k.qdot_buf;
  normalize(q);
}

void TreeKernel::normalize(Eigen::Ref<Eigen::VectorXd> q) const {
  for (int i : impl_->quat_q) q.segment<4>(i).normalize();
}

}  // namespace dmbd::model::detail
