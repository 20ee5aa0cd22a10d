#include "plant_dynamics.hpp"

#include "actuator_terms.hpp"
#include "dmbd/model/error.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace dmbd::model::detail {

namespace {

// A link must keep this much mass after giving up a housing's reaction mass.
constexpr double kMinLinkMass = 0.2;

// The link whose mass carries each RFSEA's housing (-1 for an FSEA): the actuated
// joint's parent, or the nearest ancestor that can give M_r and keep kMinLinkMass.
std::vector<int> housing_donors(const RobotDescription& r, const PlantOptions& o) {
  check_actuators_against(o.actuators, r);
  std::vector<double> taken(r.links.size(), 0.0);
  std::vector<int> donor;
  for (const ActuatorParams& p : o.actuators) {
    const int j = r.joint_index(p.joint);
    if (p.kind != ActuatorKind::RFSEA) {
      donor.push_back(-1);
      continue;
    }
    if (!(p.M_r_kg > 0)) throw ModelError(r.source + ": actuator of '" + p.joint + "': an RFSEA needs a reaction mass M_r > 0");
    int l = r.link_index(r.joints[static_cast<std::size_t>(j)].parent);
    while (l >= 0 && r.links[static_cast<std::size_t>(l)].mass_kg - taken[static_cast<std::size_t>(l)] - p.M_r_kg < kMinLinkMass) {
      const int pj = r.parent_joint_of_link(l);
      l = pj < 0 ? -1 : r.link_index(r.joints[static_cast<std::size_t>(pj)].parent);
    }
    if (l < 0) throw ModelError(r.source + ": no link can carry the " + std::to_string(p.M_r_kg) + " kg housing of '" + p.joint + "'");
    taken[static_cast<std::size_t>(l)] += p.M_r_kg;
    donor.push_back(l);
  }
  return donor;
}

std::vector<double> taken_mass(const RobotDescription& r, const PlantOptions& o) {
  std::vector<double> taken(r.links.size(), 0.0);
  const std::vector<int> donor = housing_donors(r, o);
  for (std::size_t k = 0; k < donor.size(); ++k)
    if (donor[k] >= 0) taken[static_cast<std::size_t>(donor[k])] += o.actuators[k].M_r_kg;
  return taken;
}

// Hunt-Crossley joint stop (Simbody's MobilityLinearStop law): torque, and its
// negative derivatives with respect to q and qdot.
struct StopTorque {
  double tau = 0, k = 0, d = 0, energy = 0;
};
StopTorque stop_torque(double q, double qd, double lo, double hi, double k, double d) {
  StopTorque s;
  const double x = q > hi ? q - hi : (q < lo ? lo - q : 0.0);
  if (x <= 0) return s;
  const double sign = q > hi ? -1.0 : 1.0;  // pushes back into the range
  const double xdot = -sign * qd;           // penetration rate
  const double f = k * x * (1 + d * xdot);
  s.energy = 0.5 * k * x * x;
  if (f <= 0) return s;
  s.tau = sign * f;
  s.k = k * (1 + d * xdot);
  s.d = k * d * x;
  return s;
}

// The contact parameters of boxes, meshes and cylinders: stiffnesses positive, the
// dissipation not negative, all finite.
void check_contact_params(const ContactParams& c) {
  auto check = [](double v, bool zero_ok, const char* name) {
    if (!std::isfinite(v) || v < 0 || (!zero_ok && v == 0))
      throw ModelError(std::string("plant: contact_params.") + name + " = " + std::to_string(v) + " (expected " +
                       (zero_ok ? "a finite value >= 0)" : "a finite value > 0)"));
  };
  check(c.point_stiffness_N_per_m, false, "point_stiffness_N_per_m");
  check(c.point_dissipation_s_per_m, true, "point_dissipation_s_per_m");
  check(c.rim_stiffness_N_per_m2, false, "rim_stiffness_N_per_m2");
}

}  // namespace

PlantDynamics::PlantDynamics(const RobotDescription& r, const PlantOptions& o)
    : kernel_(r, o.base, o.X_WB, o.gravity_m_s2, taken_mass(r, o)), opt_(o), acts_(o.actuators), ground_(o.ground_normal) {
  ntq_ = kernel_.nq();
  ntv_ = kernel_.nv();
  na_ = static_cast<int>(acts_.size());
  const int nj = num_joints();
  act_of_joint_.assign(static_cast<std::size_t>(nj), -1);
  const std::vector<int> donor = housing_donors(r, o);
  for (int k = 0; k < na_; ++k) {
    const ActuatorParams& p = acts_[static_cast<std::size_t>(k)];
    int c = -1;
    for (int j = 0; j < nj; ++j)
      if (kernel_.joint_names()[static_cast<std::size_t>(j)] == p.joint) c = j;
    const std::string at = (p.where.empty() ? r.source : p.where) + ": ";
    if (c < 0) throw ModelError(at + "actuated joint '" + p.joint + "' has no coordinate (welded: it moves no mass)");
    if (act_of_joint_[static_cast<std::size_t>(c)] >= 0) throw ModelError(at + "two actuators drive joint '" + p.joint + "'");
    act_of_joint_[static_cast<std::size_t>(c)] = k;
    act_joint_.push_back(c);
    spring_.push_back(p.has_spring() ? ns_++ : -1);
    const int l = donor[static_cast<std::size_t>(k)];
    if (l < 0) continue;
    housings_.push_back({k, kernel_.body_of_link(l), r.links[static_cast<std::size_t>(l)].com_m, Eigen::Vector3d::UnitZ(), p.M_r_kg});
    housing_mass_ += p.M_r_kg;
  }
  for (int j = 0; j < nj; ++j) {
    const Joint& jt = r.joints[static_cast<std::size_t>(kernel_.joint_description_index()[static_cast<std::size_t>(j)])];
    JointStop s{j, o.joint_limits && jt.has_limits && jt.type != JointType::Continuous, jt.lower, jt.upper,
                o.joint_damping ? jt.damping : 0.0, jt.armature};
    if (s.limited || s.damping > 0 || s.armature > 0) stops_.push_back(s);
  }
  if (o.contact) {
    check_contact_params(o.contact_params);
    contact_ = detail::contact_elements(r, kernel_);
    for (const ContactSphere& sp : contact_.spheres) sphere_hertz_.push_back(hertz_constant(sp.radius_m, o.contact_params.stiffness_Pa));
  }
  anchors.assign(contact_.spheres.size(), SphereAnchor{});
  point_anchors.assign(contact_.points.size(), SphereAnchor{});
  rim_friction.assign(contact_.rims.size(), RimFriction{});
  currents = Eigen::VectorXd::Zero(na_);
  joint_torques = Eigen::VectorXd::Zero(nj);
  external.reserve(16);
  Q_ = Eigen::VectorXd::Zero(nq());
  V_ = Eigen::VectorXd::Zero(nv());
  A_ = Eigen::MatrixXd::Zero(nv(), nv());
  r_ = kv_ = Eigen::VectorXd::Zero(nv());
  c_tree_ = Eigen::VectorXd::Zero(ntv_);
  G_ = WG_ = Eigen::Matrix3Xd::Zero(3, nv());
  J6_ = WJ6_ = Eigen::Matrix<double, 6, Eigen::Dynamic>::Zero(6, nv());
  idx_.reserve(static_cast<std::size_t>(nv()));
}

// The plant sets its state after every advance (for its readers) and each step sets it
// again: the kernel keeps its position and velocity passes when the tree's part of the
// state is bit for bit the one it holds (a NaN never compares equal: it is always set).
void PlantDynamics::set_state(const Eigen::Ref<const Eigen::VectorXd>& Q, const Eigen::Ref<const Eigen::VectorXd>& V) {
  const bool same_q = kernel_set_ && Q_.head(ntq_) == Q.head(ntq_);
  const bool same_v = same_q && V_.head(ntv_) == V.head(ntv_);
  Q_ = Q;
  V_ = V;
  if (!same_q) kernel_.set_q(Q_.head(ntq_));
  if (!same_v) kernel_.set_v(V_.head(ntv_));
  kernel_set_ = true;
}

Eigen::Vector3d PlantDynamics::world_point(int body, const Eigen::Vector3d& p_B) const {
  return kernel_.origin(body) + kernel_.rotation(body) * p_B;
}

void PlantDynamics::assemble(double h) {
  A_.setZero();
  r_.setZero();
  kv_.setZero();
  add_tree();
  add_joint_terms(h);
  add_actuators(h);
  add_housings();
  add_contacts(h);
  add_external();
}

void PlantDynamics::add_tree() {
  kernel_.mass_matrix(A_.topLeftCorner(ntv_, ntv_));
  kernel_.coriolis_and_gravity(c_tree_);
  r_.head(ntv_) = -c_tree_;
}

void PlantDynamics::add_joint_terms(double h) {
  for (int j = 0; j < num_joints(); ++j) r_[joint_v(j)] += joint_torques[j];
  for (const JointStop& s : stops_) {
    const int iq = joint_q(s.joint), iv = joint_v(s.joint);
    const double q = Q_[iq], qd = V_[iv];
    double tau = -s.damping * qd, k = 0, d = s.damping;
    if (s.limited) {
      const StopTorque st = stop_torque(q, qd, s.lower, s.upper, opt_.limit_stiffness_Nm_per_rad, opt_.limit_dissipation_s_per_rad);
      tau += st.tau;
      k += st.k;
      d += st.d;
    }
    r_[iv] += tau;
    A_(iv, iv) += s.armature + h * d + h * h * k;  // the armature is inertia: in A at every h (and in the kinetic energy)
    kv_[iv] += k * qd;
  }
}

// Each actuator's 2 x 2 terms over (q, s); an actuator without a spring (ROTARY) has
// only the q entries.
void PlantDynamics::add_actuators(double h) {
  for (int k = 0; k < na_; ++k) {
    const int c = act_joint_[static_cast<std::size_t>(k)];
    const int iq = joint_q(c), iv = joint_v(c), is = spring_v(k);
    const double qd = V_[iv], sd = spring_rate(k);
    const ActuatorTerms t = actuator_terms(acts_[static_cast<std::size_t>(k)], Q_[iq], qd, spring_deflection(k), sd, currents[k]);
    const int idx[2] = {iv, is};
    const int n = is < 0 ? 1 : 2;
    const Eigen::Matrix2d W = t.M + h * t.D + h * h * t.K;
    const Eigen::Vector2d kv = t.K * Eigen::Vector2d(qd, sd);
    for (int a = 0; a < n; ++a) {
      r_[idx[a]] += t.f[a];
      kv_[idx[a]] += kv[a];
      for (int b = 0; b <= a; ++b) A_(idx[a], idx[b]) += W(a, b);  // lower triangle (idx ascending)
    }
  }
}

// The housing at p_h = P + s u (P, u fixed in the donor body): its Jacobian over the
// tree is the body point Jacobian at p_h, over s it is u; its bias acceleration is the
// body point's plus the sliding Coriolis term 2 s' (omega x u).
void PlantDynamics::add_housings() {
  const Eigen::Vector3d g(0, 0, -opt_.gravity_m_s2);
  for (const HousingMass& hm : housings_) {
    const double s = spring_deflection(hm.actuator), sd = spring_rate(hm.actuator);
    const Eigen::Vector3d u = kernel_.rotation(hm.body) * hm.u_B;
    const Eigen::Vector3d p = world_point(hm.body, hm.p_B) + s * u;
    const std::vector<int>& mob = kernel_.body_mobilities(hm.body);
    const int m = static_cast<int>(mob.size());
    kernel_.point_jacobian_columns(hm.body, p, G_.leftCols(m));
    G_.col(m) = u;
    idx_.assign(mob.begin(), mob.end());
    idx_.push_back(spring_v(hm.actuator));
    const Eigen::Vector3d a = kernel_.point_bias_acceleration(hm.body, p) + 2 * sd * kernel_.angular_velocity(hm.body).cross(u);
    add_point_mass_term(idx_, m + 1, hm.mass_kg * (g - a), hm.mass_kg);
  }
}

// add_point_term with W = mass 1: A += mass Gᵀ G (the lower triangle), no W G product.
void PlantDynamics::add_point_mass_term(const std::vector<int>& idx, int cols, const Eigen::Vector3d& f, double mass) {
  const auto G = G_.leftCols(cols);
  for (int a = 0; a < cols; ++a) {
    const auto ia = static_cast<Eigen::Index>(idx[static_cast<std::size_t>(a)]);
    r_[ia] += G.col(a).dot(f);
    for (int b = 0; b <= a; ++b) A_(ia, idx[static_cast<std::size_t>(b)]) += mass * G.col(a).dot(G.col(b));
  }
}

void PlantDynamics::add_external() {
  for (const PointForce& f : external) {
    const std::vector<int>& mob = kernel_.body_mobilities(f.body);
    const int m = static_cast<int>(mob.size());
    kernel_.point_jacobian_columns(f.body, world_point(f.body, f.p_B), G_.leftCols(m));
    add_point_term(mob, m, f.f_W, Eigen::Matrix3d::Zero());
  }
}

void PlantDynamics::add_point_term(const std::vector<int>& idx, int cols, const Eigen::Vector3d& f, const Eigen::Matrix3d& W,
                                   const Eigen::Matrix3d* K, const Eigen::Vector3d* Gv) {
  const auto G = G_.leftCols(cols);
  for (int a = 0; a < cols; ++a) r_[idx[static_cast<std::size_t>(a)]] += G.col(a).dot(f);
  if (K && Gv) {
    const Eigen::Vector3d kf = *K * *Gv;
    for (int a = 0; a < cols; ++a) kv_[idx[static_cast<std::size_t>(a)]] += G.col(a).dot(kf);
  }
  if (W.isZero(0)) return;
  WG_.leftCols(cols).noalias() = W * G;
  for (int a = 0; a < cols; ++a)  // the lower triangle (idx ascending)
    for (int b = 0; b <= a; ++b) A_(idx[static_cast<std::size_t>(a)], idx[static_cast<std::size_t>(b)]) += G.col(a).dot(WG_.col(b));
}

void PlantDynamics::BodyTerms::add(const Eigen::Vector3d& p, const Eigen::Vector3d& f, const Eigen::Matrix3d& W,
                                   const Eigen::Vector3d& k) {
  const Eigen::Vector3d r = p - o;
  Eigen::Matrix3d X;  // -[r]x: v_p = v_o + omega x r = v_o + X omega
  X << 0, r.z(), -r.y(), -r.z(), 0, r.x(), r.y(), -r.x(), 0;
  const Eigen::Matrix3d WX = W * X;
  W6.topLeftCorner<3, 3>().noalias() += X.transpose() * WX;
  W6.topRightCorner<3, 3>().noalias() += X.transpose() * W;
  W6.bottomLeftCorner<3, 3>() += WX;
  W6.bottomRightCorner<3, 3>() += W;
  f6.head<3>() += r.cross(f);  // X^T f
  f6.tail<3>() += f;
  k6.head<3>() += r.cross(k);
  k6.tail<3>() += k;
  any = true;
}

void PlantDynamics::add_body_terms(const BodyTerms& t) {
  if (!t.any) return;
  const std::vector<int>& mob = kernel_.body_mobilities(t.body);
  const int m = static_cast<int>(mob.size());
  kernel_.frame_jacobian_columns(t.body, t.o, J6_.leftCols(m));
  const auto J = J6_.leftCols(m);
  WJ6_.leftCols(m).noalias() = t.W6 * J;
  for (int a = 0; a < m; ++a) {
    const auto ia = static_cast<Eigen::Index>(mob[static_cast<std::size_t>(a)]);
    r_[ia] += J.col(a).dot(t.f6);
    kv_[ia] += J.col(a).dot(t.k6);
    for (int b = 0; b <= a; ++b) A_(ia, mob[static_cast<std::size_t>(b)]) += J.col(a).dot(WJ6_.col(b));  // lower triangle
  }
}

Eigen::Vector3d PlantDynamics::housing_moment() const {
  Eigen::Vector3d h = Eigen::Vector3d::Zero();
  for (const HousingMass& hm : housings_) {
    const double s = spring_deflection(hm.actuator);
    h += hm.mass_kg * (world_point(hm.body, hm.p_B) + s * (kernel_.rotation(hm.body) * hm.u_B));
  }
  return h;
}

double PlantDynamics::kinetic_energy() {
  assemble(0.0);
  return 0.5 * V_.dot(A_.selfadjointView<Eigen::Lower>() * V_);
}

double PlantDynamics::potential_energy() const {
  double e = kernel_.gravity_potential();
  for (const HousingMass& hm : housings_) {
    const double s = spring_deflection(hm.actuator);
    const Eigen::Vector3d p = world_point(hm.body, hm.p_B) + s * (kernel_.rotation(hm.body) * hm.u_B);
    e += hm.mass_kg * opt_.gravity_m_s2 * p.z();
  }
  for (int k = 0; k < na_; ++k) e += actuator_potential_energy(acts_[static_cast<std::size_t>(k)], spring_deflection(k));
  add_contact_potential(e);
  for (const JointStop& s : stops_)
    if (s.limited)
      e += stop_torque(Q_[joint_q(s.joint)], 0.0, s.lower, s.upper, opt_.limit_stiffness_Nm_per_rad, 0.0).energy;
  return e;
}

}  // namespace dmbd::model::detail
