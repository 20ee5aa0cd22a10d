// OscController: operational space control on the bus (osc_controller.hpp).
#include "dmbd/control/osc_controller.hpp"

#include <cmath>
#include <optional>

#include "dmbd/base/error.hpp"
#include "dmbd/control/dynamics_model.hpp"
#include "dmbd/wholebody/osc.hpp"
#include "dmbd/wholebody/projection.hpp"
#include "dmbd/wholebody/task.hpp"

namespace dmbd::control {

void OscTrajectory::evaluate(double t, Eigen::Vector3d& p, Eigen::Vector3d& v, Eigen::Vector3d& a) const {
  // Minimum-jerk ramp s(t) = 10u³ − 15u⁴ + 6u⁵, u = t / ramp_s, and its derivatives.
  double s = 1.0, ds = 0.0, dds = 0.0;
  if (ramp_s > 0 && t < ramp_s) {
    const double u = std::max(t, 0.0) / ramp_s;
    s = u * u * u * (10.0 - 15.0 * u + 6.0 * u * u);
    ds = 30.0 * u * u * (1.0 - u) * (1.0 - u) / ramp_s;
    dds = 60.0 * u * (1.0 - u) * (1.0 - 2.0 * u) / (ramp_s * ramp_s);
  }
  const double w = 2.0 * M_PI * frequency_hz;
  const double sn = std::sin(w * t), cs = std::cos(w * t);
  // p = s a sin(wt); v = ṡ a sin + s a w cos; a = s̈ a sin + 2 ṡ a w cos − s a w² sin.
  p = amplitude_m * (s * sn);
  v = amplitude_m * (ds * sn + s * w * cs);
  a = amplitude_m * (dds * sn + 2.0 * ds * w * cs - s * w * w * sn);
}

struct OscController::Impl {
  OscSetup setup;
  DynamicsModel model;
  wholebody::ModelData data;
  std::unique_ptr<wholebody::PointTask> task;
  std::unique_ptr<wholebody::PostureTask> posture;
  std::unique_ptr<wholebody::OperationalSpaceControl> osc;
  std::vector<std::string> joints;
  std::vector<std::optional<model::ActuatorParams>> actuator;  // per joint: its actuator, if any
  std::vector<double> load_damping;  // per joint: its actuator's output-side damping B_l (N s/m), or 0
  std::vector<std::string> in_names, out_names, out_units;
  std::vector<int> ideal;  // the joints without an actuator (their torque drives the plant)
  Eigen::VectorXd q, v, tau;
  // Load-damping feedforward: D = diag(B_l r(q)²) at the joints, the least-dissipation
  // joint rates for the reference rate, q̇_ref = D⁻¹Jᵀ(J D⁻¹ Jᵀ)⁻¹ ẋ_d, and D q̇_ref.
  Eigen::MatrixXd D;
  std::unique_ptr<wholebody::DynamicallyConsistentInverse> damping_inv;
  Eigen::VectorXd qd_ref;
  Eigen::Vector3d p0;

  Impl(const model::RobotDescription& robot, const model::DynamicsOptions& options, const OscSetup& s)
      : setup(s), model(robot, options) {}
  int nj() const { return static_cast<int>(joints.size()); }
  void make_tasks();
  void bind_actuators(const std::vector<model::ActuatorParams>& actuators);
  void name_ports();
  void start_at(const std::vector<std::pair<std::string, double>>& q0);
  void add_load_damping(const Eigen::Vector3d& v_d);
  void write_outputs(const double* u, double* y, const Eigen::Vector3d& p_d) const;
};

namespace {

model::DynamicsOptions fixed_base(const Eigen::Isometry3d& X_WB, double gravity) {
  model::DynamicsOptions o;
  o.base = model::BaseMode::Fixed;
  o.X_WB = X_WB;
  o.gravity_m_s2 = gravity;
  return o;
}

}  // namespace

void OscController::Impl::name_ports() {
  for (const auto& j : joints) {
    in_names.push_back(j + "." + setup.q_signal);
    in_names.push_back(j + "." + setup.qd_signal);
  }
  for (int k = 0; k < nj(); ++k)
    if (actuator[static_cast<size_t>(k)]) in_names.push_back(joints[static_cast<size_t>(k)] + ".force");
  auto out = [&](const std::string& n, const char* unit) {
    out_names.push_back(n);
    out_units.emplace_back(unit);
  };
  for (const auto& j : joints) out(j + ".tau_d", "N m");
  for (int k = 0; k < nj(); ++k)
    if (actuator[static_cast<size_t>(k)]) {
      out(joints[static_cast<size_t>(k)] + ".force_d", actuator[static_cast<size_t>(k)]->is_rotary() ? "N m" : "N");
      out(joints[static_cast<size_t>(k)] + ".tau_s", "N m");
    }
  for (int k : ideal) out(joints[static_cast<size_t>(k)] + ".torque", "N m");
  for (const char* axis : {"x", "y", "z"}) out(setup.name + "." + axis + "_d", "m");
  for (const char* axis : {"x", "y", "z"}) out(setup.name + "." + axis, "m");
}

// The point task at setup's link and the posture of every joint, with their gains.
void OscController::Impl::make_tasks() {
  const wholebody::Layout& layout = model.layout();
  if (setup.link.empty())
    throw InputError(setup.where + ": " + setup.name + ": option 'link' is not set (the point's link: set it in the scenario or in the robot "
                     "folder's controllers." + setup.type + ")");
  try {
    task = std::make_unique<wholebody::PointTask>(model.add_frame({setup.link, setup.point_L}), layout.nv);
  } catch (InputError& e) {
    e.prepend(setup.where + ": " + setup.name + ".link: ");
    throw;
  }
  task->set_gains(setup.kp, setup.kd);
  std::vector<int> all(layout.joints.size());
  for (size_t k = 0; k < all.size(); ++k) all[k] = static_cast<int>(k);
  posture = std::make_unique<wholebody::PostureTask>(layout, all);
  posture->set_gains(setup.posture_kp, setup.posture_kd);
  osc = std::make_unique<wholebody::OperationalSpaceControl>(layout, 3, static_cast<int>(all.size()));
}

// Each joint's actuator and output-side damping (none for a joint without one).
void OscController::Impl::bind_actuators(const std::vector<model::ActuatorParams>& actuators) {
  for (const auto& j : model.layout().joints) {
    joints.push_back(j.name);
    std::optional<model::ActuatorParams> l;
    double b_l = 0.0;
    for (const auto& p : actuators)
      if (p.joint == j.name) l = p, b_l = p.B_l_Ns_per_m;
    if (!l) ideal.push_back(static_cast<int>(actuator.size()));
    actuator.push_back(l);
    load_damping.push_back(setup.compensate_load_damping ? b_l : 0.0);
  }
}

// Storage for a tick, the posture target and the path's centre p₀ at the angles q0.
void OscController::Impl::start_at(const std::vector<std::pair<std::string, double>>& q0) {
  const wholebody::Layout& layout = model.layout();
  data = model.make_data();
  q = Eigen::VectorXd::Zero(layout.nq);
  for (const auto& [name, angle] : q0)
    if (const int j = layout.joint_index(name); j >= 0) q[layout.joints[static_cast<size_t>(j)].q_index] = angle;
  v = tau = qd_ref = Eigen::VectorXd::Zero(layout.nv);
  D = Eigen::MatrixXd::Zero(layout.nv, layout.nv);
  damping_inv = std::make_unique<wholebody::DynamicallyConsistentInverse>(3, layout.nv);
  posture->set_reference(q, v, v);
  model.update(q, v, data);
  p0 = data.frames[0].X_WF.translation();
}

OscController::OscController(const model::RobotDescription& robot, const Eigen::Isometry3d& X_WB, double gravity_m_s2,
                             const std::vector<model::ActuatorParams>& actuators,
                             const std::vector<std::pair<std::string, double>>& q0, const OscSetup& setup,
                             long long max_ticks)
    : BusController(setup, max_ticks), impl_(std::make_unique<Impl>(robot, fixed_base(X_WB, gravity_m_s2), setup)) {
  impl_->make_tasks();
  impl_->bind_actuators(actuators);
  impl_->name_ports();
  impl_->start_at(q0);
  for (const auto& n : impl_->in_names) add_input(n);
  for (std::size_t k = 0; k < impl_->out_names.size(); ++k) add_output(impl_->out_names[k], impl_->out_units[k]);
}

OscController::~OscController() = default;

const std::vector<std::string>& OscController::joints() const { return impl_->joints; }

std::vector<JointCommand> OscController::joint_commands() const {
  std::vector<JointCommand> c;
  for (std::size_t k = 0; k < impl_->joints.size(); ++k)
    if (impl_->actuator[k]) c.push_back({impl_->joints[k], {impl_->joints[k] + ".force_d"}});
  return c;
}

void OscController::record(const model::Plant& plant, std::map<std::string, double>& truth) const {
  for (int k = 0; k < plant.num_actuators(); ++k) truth[plant.actuator(k).joint + ".current_limit_A"] = plant.actuator(k).current_limit_A;
}

void OscController::tick(const double* u, double* y) {
  Impl& m = *impl_;
  const wholebody::Layout& layout = m.model.layout();
  for (int k = 0; k < m.nj(); ++k) {
    const auto& j = layout.joints[static_cast<size_t>(k)];
    m.q[j.q_index] = u[2 * k];
    m.v[j.v_index] = u[2 * k + 1];
  }
  const double t = static_cast<double>(ticks()) / m.setup.rate_hz;
  Eigen::Vector3d p, v, a;
  m.setup.trajectory.evaluate(t, p, v, a);
  p += m.p0;
  m.task->set_reference(p, v, a);
  m.model.update(m.q, m.v, m.data);
  m.task->update(m.data);
  m.posture->update(m.data);
  m.osc->compute(m.data, *m.task, m.posture.get(), m.tau);
  if (m.setup.compensate_load_damping) m.add_load_damping(v);
  m.write_outputs(u, y, p);
}

// The actuators' output-side damping seen at the joints, D = diag(B_l r(q)²) (the
// load's damping of Table I along the actuator, moment arm r = dx/dq): the rigid-body
// model does not have it, the plant does (model/src/actuator_terms.cpp). It is fed
// forward, D q̇_ref, at the joint rates that move the point at the reference's rate
// with the least dissipation, q̇_ref = D⁻¹Jᵀ(J D⁻¹ Jᵀ)⁻¹ ẋ_d (a joint that does not move
// the point gets none). Not fed back from the measured rates: cancelling the joints'
// damping through a loop with delays made the hip yaw oscillate at about 5 Hz; and not
// through J̄ ẋ_d, which sends the light foot's ankle fast. A joint without an actuator
// is weighted by the largest damping (it is not made the cheap one to move).
void OscController::Impl::add_load_damping(const Eigen::Vector3d& v_d) {
  const wholebody::Layout& layout = model.layout();
  double largest = 0.0;
  for (int k = 0; k < nj(); ++k) {
    const auto& j = layout.joints[static_cast<size_t>(k)];
    const double b_l = load_damping[static_cast<size_t>(k)];
    const double r = b_l > 0.0 ? actuator[static_cast<size_t>(k)]->moment_arm(q[j.q_index]) : 0.0;
    D(j.v_index, j.v_index) = b_l * r * r;
    largest = std::max(largest, b_l * r * r);
  }
  if (largest <= 0.0) return;
  for (int i = 0; i < layout.nv; ++i)
    if (D(i, i) <= 0.0) D(i, i) = largest;
  damping_inv->compute(D, task->jacobian());
  qd_ref.noalias() = damping_inv->Jbar() * v_d;
  for (int k = 0; k < nj(); ++k) {
    const int i = layout.joints[static_cast<size_t>(k)].v_index;
    if (load_damping[static_cast<size_t>(k)] > 0.0) tau[i] += D(i, i) * qd_ref[i];
  }
}

// τ_d per joint; then per actuated joint F_d = τ_d N_l(q) and the sensed torque
// τ_s = F / N_l(q) (its force among the inputs after the joints' angles and rates);
// then the point's target and position.
void OscController::Impl::write_outputs(const double* u, double* y, const Eigen::Vector3d& p_d) const {
  const wholebody::Layout& layout = model.layout();
  int out = 0, force_in = 2 * nj();
  for (int k = 0; k < nj(); ++k) y[out++] = tau[layout.joints[static_cast<size_t>(k)].v_index];
  for (int k = 0; k < nj(); ++k) {
    const std::optional<model::ActuatorParams>& l = actuator[static_cast<size_t>(k)];
    if (!l) continue;
    const auto& j = layout.joints[static_cast<size_t>(k)];
    const double n_l = l->N_l(q[j.q_index]);
    y[out++] = tau[j.v_index] * n_l;
    y[out++] = u[force_in++] / n_l;
  }
  for (int k : ideal) y[out++] = tau[layout.joints[static_cast<size_t>(k)].v_index];
  const Eigen::Vector3d p = data.frames[0].X_WF.translation();
  for (int i = 0; i < 3; ++i) y[out + i] = p_d[i];
  for (int i = 0; i < 3; ++i) y[out + 3 + i] = p[i];
}

}  // namespace dmbd::control
