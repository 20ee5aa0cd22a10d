// Plant: the robot's equations in generalized coordinates (plant_dynamics.hpp) and the
// fixed or accurate integrator (plant_steppers.hpp). The state is Q = [q, s],
// V = [v, s'] (tree coordinates, then one spring deflection per actuator that has a
// spring: PlantDynamics::spring_q(k), -1 for a ROTARY).
#include "dmbd/model/plant.hpp"

#include "actuator_terms.hpp"
#include "dmbd/model/error.hpp"
#include "plant_dynamics.hpp"
#include "plant_steppers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace dmbd::model {

using detail::PlantDynamics;

struct Plant::Impl {
  RobotDescription robot;
  PlantOptions opt;
  PlantDynamics dyn;
  detail::FixedStepper fixed;
  detail::AccurateIntegrator accurate;
  Eigen::VectorXd Q, V;
  std::vector<char> locked;   // per entry of V
  double t = 0;
  long long steps = 0;
  std::vector<double> effort;        // per joint: the ideal torque's limit (0: none)
  std::vector<long long> clamps;     // per joint: torques clamped to it since reset()

  Impl(const RobotDescription& r, const PlantOptions& o)
      : robot(r), opt(o), dyn(robot, o), fixed(dyn), accurate(dyn, o.accuracy), Q(dyn.nq()), V(dyn.nv()),
        locked(static_cast<std::size_t>(dyn.nv()), 0) {
    if (o.integration == Integration::Fixed && !(o.step_s > 0 && std::isfinite(o.step_s)))
      throw ModelError("plant: fixed step " + std::to_string(o.step_s) + " s is not positive");
    if (!(o.accuracy > 0)) throw ModelError("plant: accuracy " + std::to_string(o.accuracy) + " is not positive");
    effort.assign(static_cast<std::size_t>(dyn.num_joints()), 0.0);
    clamps.assign(effort.size(), 0);
    for (int c = 0; c < dyn.num_joints(); ++c) {
      const Joint& j = robot.joints[static_cast<std::size_t>(dyn.kernel().joint_description_index()[static_cast<std::size_t>(c)])];
      if (o.effort_limits && dyn.actuator_of_joint(c) < 0 && j.effort > 0) effort[static_cast<std::size_t>(c)] = j.effort;
    }
  }

  int root_body() const { return dyn.kernel().body_of_link(0); }
  void sync() { dyn.set_state(Q, V); }
  int check_joint(int c, const char* what) const {
    if (c < 0 || c >= dyn.num_joints()) throw ModelError(std::string(what) + ": no joint with index " + std::to_string(c));
    return c;
  }
  void set_joints(const Eigen::VectorXd& x, bool velocity, const char* what) {
    const int n = dyn.num_joints();
    if (x.size() != n)
      throw ModelError(std::string(what) + ": " + std::to_string(x.size()) + " values for " + std::to_string(n) + " joints");
    for (int c = 0; c < n; ++c) {
      if (velocity) V[dyn.joint_v(c)] = x[c];
      else Q[dyn.joint_q(c)] = x[c];
    }
    sync();
  }
  // Floating base: moved along the ground normal so that the contacts' static normal
  // forces carry the weight's normal component (docs/model.md, "Contact").
  void place_on_ground() {
    const detail::ContactElements& ce = dyn.contact_elements();
    if (!dyn.kernel().base_dofs() || ce.shapes.empty()) return;
    sync();
    const bool spheres_only = ce.points.empty() && ce.rims.empty();
    const double lift = spheres_only && dyn.ground().is_z() ? sphere_lift() : contact_lift();
    Eigen::Isometry3d X = dyn.kernel().pose(root_body());
    if (dyn.ground().is_z()) X.translation().z() += lift;
    else X.translation() += lift * dyn.ground().n();
    dyn.kernel().set_base_pose(Q.head(dyn.tree_nq()), X);
  }
  // Spheres on level ground (the rule before other shapes could touch, kept bit for bit):
  // the lowest spheres (within 1 nm) share the weight equally and sink by its Hertz
  // deflection.
  double sphere_lift() const {
    double lowest = std::numeric_limits<double>::infinity(), radius = 0;
    int touching = 0;
    for (const auto& sp : dyn.spheres()) lowest = std::min(lowest, dyn.world_point(sp.body, sp.center_B).z() - sp.radius_m);
    for (const auto& sp : dyn.spheres())
      if (dyn.world_point(sp.body, sp.center_B).z() - sp.radius_m < lowest + 1e-9) {
        ++touching;
        radius = sp.radius_m;
      }
    const double sink = detail::hertz_sinkage(dyn.total_mass_kg() * opt.gravity_m_s2 / touching, radius, opt.contact_params.stiffness_Pa);
    return -lowest - sink;
  }
  // Any elements: the lift along n at which the static loads sum to m g n_z, by bisection
  // (the load falls monotonically with the lift, to zero at -lowest).
  double contact_lift() const {
    const double weight = dyn.total_mass_kg() * opt.gravity_m_s2 * dyn.ground().n().z();
    double hi = -dyn.lowest_contact_height(), lo = hi - 1e-3;
    while (dyn.static_contact_load(lo) < weight && hi - lo < 10.0) lo = hi - 2 * (hi - lo);
    for (int k = 0; k < 200; ++k) {
      const double mid = 0.5 * (lo + hi);
      if (mid <= lo || mid >= hi) break;
      (dyn.static_contact_load(mid) < weight ? hi : lo) = mid;
    }
    return 0.5 * (lo + hi);
  }
  [[noreturn]] void diverged(const std::string& why) const {
    throw ModelError("simulation diverged at t = " + std::to_string(t) + " s: " + why);
  }
  void advance_fixed(double t_end) {
    const double span = t_end - t;
    const long long n = std::max<long long>(1, static_cast<long long>(std::ceil(span / opt.step_s - 1e-9)));
    const double h = span / static_cast<double>(n);
    for (long long k = 0; k < n; ++k) {
      if (!fixed.step(Q, V, h, locked)) diverged("the step's linear system is not positive definite");
      t = k + 1 == n ? t_end : t + h;
      ++steps;
    }
  }
};

Plant::Plant(const RobotDescription& robot, const PlantOptions& options) : impl_(std::make_unique<Impl>(robot, options)) {
  reset();
}
Plant::~Plant() = default;

const RobotDescription& Plant::description() const { return impl_->robot; }
const PlantOptions& Plant::options() const { return impl_->opt; }
int Plant::num_joints() const { return impl_->dyn.num_joints(); }
const std::vector<std::string>& Plant::joint_names() const { return impl_->dyn.kernel().joint_names(); }
int Plant::joint_index(const std::string& name) const {
  const auto& n = joint_names();
  const auto it = std::find(n.begin(), n.end(), name);
  return it == n.end() ? -1 : static_cast<int>(it - n.begin());
}
int Plant::num_actuators() const { return impl_->dyn.num_actuators(); }
int Plant::actuator_of_joint(int joint) const {
  return joint < 0 || joint >= num_joints() ? -1 : impl_->dyn.actuator_of_joint(joint);
}
const ActuatorParams& Plant::actuator(int k) const {
  if (k < 0 || k >= num_actuators()) throw ModelError("no actuator with index " + std::to_string(k));
  return impl_->dyn.actuator(k);
}

void Plant::reset() {
  Impl& m = *impl_;
  m.steps = 0;
  m.t = 0;
  std::fill(m.clamps.begin(), m.clamps.end(), 0);
  m.Q.setZero();
  m.Q.head(m.dyn.tree_nq()) = m.dyn.kernel().neutral_q();
  m.dyn.kernel().set_base_pose(m.Q.head(m.dyn.tree_nq()), m.opt.X_WB);
  m.V.setZero();
  std::fill(m.locked.begin(), m.locked.end(), 0);
  m.dyn.reset_anchors();
  m.place_on_ground();
  m.sync();
}

void Plant::place_on_ground() {
  impl_->place_on_ground();
  impl_->sync();
}

void Plant::set_joint_positions(const Eigen::VectorXd& q) { impl_->set_joints(q, false, "set_joint_positions"); }
void Plant::set_joint_velocities(const Eigen::VectorXd& v) { impl_->set_joints(v, true, "set_joint_velocities"); }

void Plant::set_base_pose(const Eigen::Isometry3d& X_WB) {
  Impl& m = *impl_;
  if (!m.dyn.kernel().base_dofs()) throw ModelError("set_base_pose: the robot's base is fixed");
  m.dyn.kernel().set_base_pose(m.Q.head(m.dyn.tree_nq()), X_WB);
  m.sync();
}

void Plant::lock_joint(int joint, double q) {
  Impl& m = *impl_;
  m.check_joint(joint, "lock_joint");
  m.Q[m.dyn.joint_q(joint)] = q;
  m.V[m.dyn.joint_v(joint)] = 0;
  m.locked[static_cast<std::size_t>(m.dyn.joint_v(joint))] = 1;
  m.sync();
}

void Plant::unlock_joint(int joint) {
  Impl& m = *impl_;
  m.check_joint(joint, "unlock_joint");
  m.locked[static_cast<std::size_t>(m.dyn.joint_v(joint))] = 0;
}

void Plant::set_currents(const Eigen::VectorXd& current_A) {
  Impl& m = *impl_;
  if (current_A.size() != num_actuators())
    throw ModelError("set_currents: " + std::to_string(current_A.size()) + " values for " + std::to_string(num_actuators()) + " actuators");
  for (int k = 0; k < num_actuators(); ++k) {
    const double lim = m.dyn.actuator(k).applied_current_limit_A();
    m.dyn.currents[k] = std::clamp(current_A[k], -lim, lim);
  }
}

void Plant::set_joint_torques(const Eigen::VectorXd& tau) {
  Impl& m = *impl_;
  if (tau.size() != num_joints())
    throw ModelError("set_joint_torques: " + std::to_string(tau.size()) + " values for " + std::to_string(num_joints()) + " joints");
  for (int c = 0; c < num_joints(); ++c) {
    const double lim = m.effort[static_cast<std::size_t>(c)];
    double v = tau[c];
    if (lim > 0 && std::abs(v) > lim) {
      v = std::clamp(v, -lim, lim);
      ++m.clamps[static_cast<std::size_t>(c)];
    }
    m.dyn.joint_torques[c] = v;
  }
}

void Plant::set_external_force(int link, const Eigen::Vector3d& p_L, const Eigen::Vector3d& f_W) {
  Impl& m = *impl_;
  if (link < 0 || link >= static_cast<int>(m.robot.links.size())) throw ModelError("set_external_force: no link " + std::to_string(link));
  m.dyn.external.push_back({m.dyn.kernel().body_of_link(link), p_L, f_W});
}

void Plant::clear_external_forces() { impl_->dyn.external.clear(); }

void Plant::advance_to(double t) {
  Impl& m = *impl_;
  if (!(t > m.t)) return;
  try {
    if (m.opt.integration == Integration::Fixed) m.advance_fixed(t);
    else m.steps += m.accurate.advance(m.Q, m.V, m.t, t, m.locked);
  } catch (const ModelError&) {
    m.sync();
    throw;
  }
  m.sync();
  if (!m.Q.allFinite() || !m.V.allFinite()) m.diverged("non-finite state");
}

double Plant::time() const { return impl_->t; }

Eigen::VectorXd Plant::joint_positions() const {
  Eigen::VectorXd q(num_joints());
  joint_positions(q);
  return q;
}
void Plant::joint_positions(Eigen::Ref<Eigen::VectorXd> q) const {
  for (int c = 0; c < num_joints(); ++c) q[c] = impl_->Q[impl_->dyn.joint_q(c)];
}
Eigen::VectorXd Plant::joint_velocities() const {
  Eigen::VectorXd v(num_joints());
  joint_velocities(v);
  return v;
}
void Plant::joint_velocities(Eigen::Ref<Eigen::VectorXd> v) const {
  for (int c = 0; c < num_joints(); ++c) v[c] = impl_->V[impl_->dyn.joint_v(c)];
}
Eigen::Isometry3d Plant::base_pose() const { return impl_->dyn.kernel().pose(impl_->root_body()); }
Eigen::Matrix<double, 6, 1> Plant::base_velocity() const {
  const auto& k = impl_->dyn.kernel();
  const int b = impl_->root_body();
  Eigen::Matrix<double, 6, 1> out;
  out << k.angular_velocity(b), k.point_velocity(b, k.origin(b));
  return out;
}
Eigen::VectorXd Plant::spring_deflections() const {
  Eigen::VectorXd s(num_actuators());
  spring_deflections(s);
  return s;
}
void Plant::spring_deflections(Eigen::Ref<Eigen::VectorXd> s) const {
  const Impl& m = *impl_;
  for (int k = 0; k < num_actuators(); ++k) s[k] = m.dyn.spring_q(k) >= 0 ? m.Q[m.dyn.spring_q(k)] : 0.0;
}
// Spring kinds: the sensed spring force K_s s. ROTARY: the drive's estimate from the
// applied current, efficiency k_tau N i (N m): what its current loop reports.
Eigen::VectorXd Plant::actuator_forces() const {
  Eigen::VectorXd f(num_actuators());
  actuator_forces(f);
  return f;
}
void Plant::actuator_forces(Eigen::Ref<Eigen::VectorXd> f) const {
  const Impl& m = *impl_;
  spring_deflections(f);
  for (int k = 0; k < num_actuators(); ++k) {
    const ActuatorParams& p = m.dyn.actuator(k);
    if (p.has_spring()) f[k] *= p.K_s_N_per_m;
    else f[k] = p.efficiency * p.force_per_amp_N_per_A() * m.dyn.currents[k];
  }
}
Eigen::VectorXd Plant::motor_angles() const {
  Eigen::VectorXd a(num_actuators());
  motor_angles(a);
  return a;
}
// Each actuator's angle from its own deflection (a[k] is read before it is written).
void Plant::motor_angles(Eigen::Ref<Eigen::VectorXd> a) const {
  const Impl& m = *impl_;
  spring_deflections(a);
  for (int k = 0; k < num_actuators(); ++k)
    a[k] = detail::motor_angle(m.dyn.actuator(k), m.Q[m.dyn.joint_q(m.dyn.actuator_joint(k))], a[k]);
}
Eigen::VectorXd Plant::motor_velocities() const {
  const Impl& m = *impl_;
  Eigen::VectorXd a(num_actuators());
  for (int k = 0; k < num_actuators(); ++k) {
    const int c = m.dyn.actuator_joint(k), sv = m.dyn.spring_v(k);
    a[k] = detail::motor_velocity(m.dyn.actuator(k), m.Q[m.dyn.joint_q(c)], m.V[m.dyn.joint_v(c)], sv < 0 ? 0.0 : m.V[sv]);
  }
  return a;
}
Eigen::VectorXd Plant::applied_currents() const { return impl_->dyn.currents; }
void Plant::applied_currents(Eigen::Ref<Eigen::VectorXd> i) const { i = impl_->dyn.currents; }
Eigen::VectorXd Plant::joint_torque_estimates() const {
  const Impl& m = *impl_;
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(num_joints());
  const Eigen::VectorXd f = actuator_forces();
  for (int k = 0; k < num_actuators(); ++k) {
    const int c = m.dyn.actuator_joint(k);
    tau[c] = f[k] * m.dyn.actuator(k).moment_arm(m.Q[m.dyn.joint_q(c)]);
  }
  return tau;
}
std::vector<Eigen::Isometry3d> Plant::link_poses() const {
  std::vector<Eigen::Isometry3d> out;
  for (std::size_t l = 0; l < impl_->robot.links.size(); ++l)
    out.push_back(impl_->dyn.kernel().pose(impl_->dyn.kernel().body_of_link(static_cast<int>(l))));
  return out;
}
std::vector<ContactReading> Plant::contacts() const {
  std::vector<ContactReading> out;
  contacts(out);
  return out;
}
void Plant::contacts(std::vector<ContactReading>& out) const {
  const Impl& m = *impl_;
  const auto n = m.dyn.contact_elements().shapes.size();
  out.resize(n);  // allocates on the first call only
  for (std::size_t i = 0; i < n; ++i) out[i] = m.dyn.contact_reading(static_cast<int>(i));
}
Eigen::Vector3d Plant::com_position() const {
  const Impl& m = *impl_;
  // The tree's centre of mass with the housings' point masses.
  const Eigen::Vector3d h = m.dyn.kernel().com() * m.dyn.kernel().total_mass_kg();
  return (h + m.dyn.housing_moment()) / m.dyn.total_mass_kg();
}
double Plant::total_mass_kg() const { return impl_->dyn.total_mass_kg(); }
double Plant::kinetic_energy() const { return impl_->dyn.kinetic_energy(); }
double Plant::potential_energy() const { return impl_->dyn.potential_energy(); }
Eigen::Vector3d Plant::imu_angular_velocity_B() const {
  const auto& k = impl_->dyn.kernel();
  const int b = impl_->root_body();
  return k.rotation(b).transpose() * k.angular_velocity(b);
}
Eigen::Vector3d Plant::imu_specific_force_B() const {
  Impl& m = *impl_;
  const auto& k = m.dyn.kernel();
  const int b = m.root_body();
  Eigen::VectorXd vdot(m.dyn.nv());
  m.accurate.accelerations(m.Q, m.V, m.locked, vdot);
  m.sync();
  Eigen::MatrixXd J(3, m.dyn.tree_nv());
  const Eigen::Vector3d o = k.origin(b);
  k.point_jacobian(b, o, J);
  const Eigen::Vector3d a = J * vdot.head(m.dyn.tree_nv()) + k.point_bias_acceleration(b, o) + Eigen::Vector3d(0, 0, m.opt.gravity_m_s2);
  return k.rotation(b).transpose() * a;
}
long long Plant::integrator_steps() const { return impl_->steps; }
const std::vector<long long>& Plant::effort_clamp_events() const { return impl_->clamps; }
const std::vector<double>& Plant::effort_limits() const { return impl_->effort; }

}  // namespace dmbd::model
