// BalanceController: construction, ports and the tick (balance_controller.hpp).
#include <cmath>

#include "balance_impl.hpp"
#include "dmbd/base/error.hpp"

namespace dmbd::control {

namespace {

model::DynamicsOptions floating(double gravity) {
  model::DynamicsOptions o;
  o.base = model::BaseMode::Floating;
  o.gravity_m_s2 = gravity;
  return o;
}

// The centre of a link's collision spheres: the point contact the controller assumes
// (one per foot, at the foot's centre, as the authors' controller).
Eigen::Vector3d collision_centre(const model::RobotDescription& r, const std::string& link, const std::string& where) {
  if (link.empty()) throw InputError(where + ": balance: option 'foot_links' is not set (set it in the scenario or in the robot folder's controllers.balance)");
  const int l = r.link_index(link);
  if (l < 0) throw InputError(where + ": balance: the robot has no link '" + link + "'");
  const auto& shapes = r.links[static_cast<size_t>(l)].collisions;
  if (shapes.empty()) throw InputError(where + ": balance: link '" + link + "' has no collision geometry to stand on");
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& s : shapes) c += s.X_LG.translation();
  return c / static_cast<double>(shapes.size());
}

// The planner's parameters on this plant: the scenario's gravity (the pendulum's ω) and
// the phase machine's step period (touch-down to touch-down).
wholebody::TvrParams planner_params(const BalanceSetup& s, double gravity) {
  wholebody::TvrParams p = s.tvr;
  p.gravity_m_s2 = gravity;
  p.step_period_s = s.phases.step_period_s();
  return p;
}

}  // namespace

BalanceController::Impl::Impl(const model::RobotDescription& robot, double gravity, const BalanceSetup& s)
    : setup(s),
      model(robot, floating(gravity)),
      estimator(robot, {s.foot_link[0], collision_centre(robot, s.foot_link[0], s.where)},
                {s.foot_link[1], collision_centre(robot, s.foot_link[1], s.where)}),
      rng(s.seed),
      phases(s.phases),
      tvr(planner_params(s, gravity)),
      swing(s.swing) {}

void BalanceController::Impl::find_frames_and_joints(const model::RobotDescription& robot) {
  const wholebody::Layout& l = model.layout();
  auto joint = [&](const std::string& name, const char* option) {
    if (name.empty())
      throw InputError(setup.where + ": balance: option '" + option + "' is not set (set it in the scenario or in the robot folder's controllers.balance)");
    const int j = l.joint_index(name);
    if (j < 0) throw InputError(setup.where + ": balance: the robot has no joint '" + name + "'");
    return j;
  };
  for (int s = 0; s < 2; ++s) {
    foot_frame[static_cast<size_t>(s)] =
        model.add_frame({setup.foot_link[static_cast<size_t>(s)], collision_centre(robot, setup.foot_link[static_cast<size_t>(s)], setup.where)});
    ankle[static_cast<size_t>(s)] = joint(setup.ankle[static_cast<size_t>(s)], "ankle_joints");
    hip_yaw[static_cast<size_t>(s)] = joint(setup.hip_yaw[static_cast<size_t>(s)], "hip_yaw_joints");
  }
  if (setup.torso_link.empty())
    throw InputError(setup.where + ": balance: option 'torso_link' is not set (set it in the scenario or in the robot folder's controllers.balance)");
  if (robot.link_index(setup.torso_link) < 0) throw InputError(setup.where + ": balance: the robot has no link '" + setup.torso_link + "'");
  torso_frame = model.add_frame({setup.torso_link, Eigen::Vector3d::Zero()});
  nj = static_cast<int>(l.joints.size());
  for (const auto& [name, angle] : setup.stance_posture) joint(name, "stance_posture");
  for (const auto& [name, g] : setup.joint_feedback) joint(name, "joint_feedback");
}

// The tasks of every phase and the three IK problems (both feet, the weight shift, or the
// stance foot alone), then the QP. The tasks' gains are the setup's (none: the authors').
void BalanceController::Impl::make_tasks() {
  const wholebody::Layout& l = model.layout();
  const int nv = l.nv;
  hip_yaws = std::make_unique<wholebody::PostureTask>(l, std::vector<int>{hip_yaw[0], hip_yaw[1]});
  std::vector<int> every(static_cast<size_t>(nj));
  for (int j = 0; j < nj; ++j) every[static_cast<size_t>(j)] = j;
  all_joints = std::make_unique<wholebody::PostureTask>(l, every);
  for (int s = 0; s < 2; ++s) {
    swing_ankle[static_cast<size_t>(s)] = std::make_unique<wholebody::PostureTask>(l, std::vector<int>{ankle[static_cast<size_t>(s)]});
    swing_foot[static_cast<size_t>(s)] =
        std::make_unique<wholebody::PointTask>(foot_frame[static_cast<size_t>(s)], nv, setup.swing_relative_to_torso ? torso_frame : -1);
    foot_orientation[static_cast<size_t>(s)] = std::make_unique<wholebody::OrientationTask>(foot_frame[static_cast<size_t>(s)], nv);
    foot_pitch[static_cast<size_t>(s)] = std::make_unique<wholebody::SelectionTask>(
        std::vector<std::pair<wholebody::Task*, int>>{{foot_orientation[static_cast<size_t>(s)].get(), 1}}, nv);
  }
  torso_orientation = std::make_unique<wholebody::OrientationTask>(torso_frame, nv);
  torso_position = std::make_unique<wholebody::PointTask>(torso_frame, nv);
  torso = std::make_unique<wholebody::SelectionTask>(
      std::vector<std::pair<wholebody::Task*, int>>{{torso_orientation.get(), 0}, {torso_orientation.get(), 1}, {torso_position.get(), 2}}, nv);
  com = std::make_unique<wholebody::ComTask>(nv);
  com_y = std::make_unique<wholebody::SelectionTask>(std::vector<std::pair<wholebody::Task*, int>>{{com.get(), 1}}, nv);
  const BalanceTaskGains& g = setup.task_gains;
  torso_orientation->set_gains(g.torso.kp, g.torso.kd);
  torso_position->set_gains(g.torso.kp, g.torso.kd);
  hip_yaws->set_gains(g.joints.kp, g.joints.kd);
  com->set_gains(g.com.kp, g.com.kd);
  for (int s = 0; s < 2; ++s) {
    swing_ankle[static_cast<size_t>(s)]->set_gains(g.joints.kp, g.joints.kd);
    foot_orientation[static_cast<size_t>(s)]->set_gains(g.joints.kp, g.joints.kd);
    swing_foot[static_cast<size_t>(s)]->set_gains(g.swing_foot.kp, g.swing_foot.kd);
  }
  ik_double = std::make_unique<wholebody::PrioritizedIk>(nv, 6, std::vector<int>{2, 3});
  ik_shift = std::make_unique<wholebody::PrioritizedIk>(nv, 6, std::vector<int>{2, 3, 1});
  Eigen::VectorXd w = Eigen::VectorXd::Ones(nv);
  w.head(6).setConstant(setup.ik_base_weight);  // the floating base's rotation and translation
  ik_single = std::make_unique<wholebody::PrioritizedIk>(nv, 3, std::vector<int>{2, 1, 3, 3});
  for (wholebody::PrioritizedIk* ik : {ik_double.get(), ik_shift.get(), ik_single.get()}) ik->set_weights(w);
  qp = std::make_unique<wholebody::WbcQp>(l, 2, setup.qp);
}

void BalanceController::Impl::bind_actuators(const std::vector<model::ActuatorParams>& actuators) {
  for (const auto& j : model.layout().joints) {
    std::optional<model::ActuatorParams> g;
    double mass = 0.0, damping = 0.0, eta = 1.0;
    for (const auto& a : actuators)
      if (a.joint == j.name) {
        g = a;
        mass = a.reflected_mass_kg();
        // Along the transmission: the rotor's, the gear's viscous friction and the output side's.
        damping = a.reflected_damping_Ns_per_m() + a.viscous_friction_Nms + a.B_l_Ns_per_m;
        eta = a.efficiency;
      }
    actuator.push_back(g);
    rotor_mass.push_back(mass);
    actuator_damping.push_back(damping);
    efficiency.push_back(eta);
  }
}

// F_ff = τ_ff N_l(q); with actuator_feedforward also what the actuator's own rotor and
// damping take at the commanded motion, ẋ = r q̇_des and ẍ = r q̈ + r' q̇_des² (r the
// moment arm, q̈ the QP's), all divided by the drive efficiency (the motor force that
// reaches the screw is η k_τ N_m i; the loop's k_ff = 1/(k_τ N_m) leaves η out).
double BalanceController::Impl::actuator_force(int j) const {
  const auto k = static_cast<size_t>(j);
  const model::ActuatorParams& g = *actuator[k];
  const model::LinkagePoint l = g.transmission(joint_q[j]);
  const double r = l.moment_arm_m, dr = l.dmoment_arm_dq_m;
  const double F = tau_ff[j] * (1.0 / r);
  if (!setup.actuator_feedforward) return F;
  const double xd = r * qd_des[j], xdd = r * qdd_joint[j] + dr * qd_des[j] * qd_des[j];
  return (F + rotor_mass[k] * xdd + actuator_damping[k] * xd) / efficiency[k];
}

void BalanceController::Impl::set_gains() {
  kp = kd = Eigen::VectorXd::Zero(nj);
  for (int j = 0; j < nj; ++j) {
    JointFeedback f;
    for (const auto& [name, g] : setup.joint_feedback)
      if (name == model.layout().joints[static_cast<size_t>(j)].name) f = g;
    kp[j] = f.kp;
    kd[j] = f.kd;
  }
}

void BalanceController::Impl::name_ports() {
  const auto& joints = model.layout().joints;
  for (const auto& j : joints) {
    in_names.push_back(j.name + "." + setup.q_signal);
    in_names.push_back(j.name + "." + setup.qd_signal);
  }
  for (const char* n : {"roll", "pitch", "yaw", "wx", "wy", "wz"}) in_names.push_back(std::string("base.") + n);
  if (setup.estimator == BalanceEstimator::MotionCapture)
    for (const char* n : {"x", "y", "z", "vx", "vy", "vz"}) in_names.push_back(std::string("base.") + n);
  auto out = [&](const std::string& n, const char* unit) {
    out_names.push_back(n);
    out_units.emplace_back(unit);
  };
  for (const auto& j : joints) out(j.name + ".q_des", "rad");
  for (const auto& j : joints) out(j.name + ".qd_des", "rad/s");
  for (const auto& j : joints) out(j.name + ".tau_ff", "N m");
  for (int k = 0; k < nj; ++k)
    if (actuator[static_cast<size_t>(k)]) out(joints[static_cast<size_t>(k)].name + ".force_ff", actuator[static_cast<size_t>(k)]->is_rotary() ? "N m" : "N");
  const std::string p = setup.name + ".";
  for (const char* n : {"phase", "swing_side", "step", "touch_downs", "landings", "qp_failures", "fallen"}) out(p + n, "");
  for (const char* n : {"com_x", "com_y", "com_z"}) out(p + n, "m");
  for (const char* n : {"com_vx", "com_vy"}) out(p + n, "m/s");
  for (const char* n : {"foothold_x", "foothold_y", "swing_x_d", "swing_y_d", "swing_z_d", "swing_x", "swing_y", "swing_z",
                        "stance_x", "stance_y", "landed_x", "landed_y", "planned_x", "planned_y"})
    out(p + n, "m");
  for (const char* n : {"fz_l", "fz_r"}) out(p + n, "N");
}

void BalanceController::Impl::start_at(const std::vector<std::pair<std::string, double>>& q0) {
  const wholebody::Layout& l = model.layout();
  data = model.make_data();
  joint_q = joint_v = Eigen::VectorXd::Zero(nj);
  q = model.dynamics().neutral_configuration();
  v = qdd_cmd = Eigen::VectorXd::Zero(l.nv);
  q_des = qd_des = tau_ff = move_start_q = stance_q = last_q_des = last_qd_des = qdd_joint = Eigen::VectorXd::Zero(nj);
  for (const auto& [name, angle] : q0)
    if (const int j = l.joint_index(name); j >= 0) q_des[j] = stance_q[j] = angle;
  for (const auto& [name, angle] : setup.stance_posture) stance_q[l.joint_index(name)] = angle;
  J_double = Eigen::MatrixXd::Zero(6, l.nv);
  J_single = Eigen::MatrixXd::Zero(3, l.nv);
  Jdv_double = Eigen::VectorXd::Zero(6);
  Jdv_single = Eigen::VectorXd::Zero(3);
}

BalanceController::BalanceController(const model::RobotDescription& robot, double gravity_m_s2,
                                     const std::vector<model::ActuatorParams>& actuators,
                                     const std::vector<std::pair<std::string, double>>& q0, const BalanceSetup& setup,
                                     long long max_ticks)
    : BusController(setup, max_ticks), impl_(std::make_unique<Impl>(robot, gravity_m_s2, setup)) {
  impl_->find_frames_and_joints(robot);
  impl_->make_tasks();
  impl_->bind_actuators(actuators);
  impl_->set_gains();
  impl_->name_ports();
  impl_->start_at(q0);
  for (const auto& n : impl_->in_names) add_input(n);
  for (std::size_t k = 0; k < impl_->out_names.size(); ++k) add_output(impl_->out_names[k], impl_->out_units[k]);
}

BalanceController::~BalanceController() = default;

long long BalanceController::qp_failures() const { return impl_->qp_failures; }

std::vector<JointCommand> BalanceController::joint_commands() const {
  std::vector<JointCommand> c;
  const auto& joints = impl_->model.layout().joints;
  for (std::size_t k = 0; k < joints.size(); ++k) {
    const std::string& j = joints[k].name;
    JointCommand jc{j, {j + ".q_des", j + ".qd_des", j + ".tau_ff"}};
    if (impl_->actuator[k]) jc.signals.push_back(j + ".force_ff");
    c.push_back(jc);
  }
  return c;
}

void BalanceController::record(const model::Plant& plant, std::map<std::string, double>& truth) const {
  truth["total_mass_kg"] = plant.total_mass_kg();
  truth["planner_gravity_m_s2"] = impl_->tvr.params().gravity_m_s2;  // the pendulum the footsteps are planned with
  truth["planner_omega_per_s"] = impl_->tvr.omega_per_s();
}

// One tick: state, phase, events, whole-body control, outputs. On a failed QP the last
// command (targets and torques) is kept.
void BalanceController::tick(const double* u, double* y) {
  Impl& m = *impl_;
  m.read_state(u);
  const double dt = m.tick == 0 ? 0.0 : 1.0 / m.setup.rate_hz;
  const Side swinging = m.phases.info().swing_side;  // the side that swings, if this tick is in a swing
  const double swing_height = m.foot_point(swinging).z() - m.foot_point(wholebody::other(swinging)).z();
  const wholebody::PhaseInfo& ph = m.phases.update(dt, m.joint_v[m.ankle[0]], m.joint_v[m.ankle[1]], swing_height);
  m.on_events(ph);
  m.fallen = m.fallen || m.tilt > m.setup.fall_tilt_rad;
  if (m.fallen) {
    m.q_des = m.joint_q;  // hold still where it lies, no feedforward
    m.qd_des.setZero();
    m.tau_ff.setZero();
    m.qdd_joint.setZero();
  } else if (!m.whole_body(ph)) {
    ++m.qp_failures;
  }
  m.write_outputs(ph, y);
  ++m.tick;
}

void BalanceController::Impl::write_outputs(const wholebody::PhaseInfo& ph, double* y) const {
  int o = 0;
  for (int j = 0; j < nj; ++j) y[o++] = q_des[j];
  for (int j = 0; j < nj; ++j) y[o++] = qd_des[j];
  for (int j = 0; j < nj; ++j) y[o++] = tau_ff[j];
  for (int j = 0; j < nj; ++j)
    if (actuator[static_cast<size_t>(j)]) y[o++] = actuator_force(j);
  const wholebody::SwingSample s = swing.at(ph.phase == wholebody::Phase::Swing ? ph.time_in_phase_s : 0.0);
  const Eigen::Vector3d stance = foot_point(wholebody::other(ph.swing_side)), moving = foot_point(ph.swing_side);
  const Eigen::Vector3d com_v = data.J_com * v;
  const double values[] = {static_cast<double>(static_cast<int>(ph.phase)), static_cast<double>(static_cast<int>(ph.swing_side)),
                           static_cast<double>(ph.step), static_cast<double>(ph.touch_downs), static_cast<double>(landings), static_cast<double>(qp_failures), fallen ? 1.0 : 0.0,
                           data.com.x(), data.com.y(), data.com.z(), com_v.x(), com_v.y(),
                           foothold.x(), foothold.y(), s.position_m.x(), s.position_m.y(), s.position_m.z(),
                           moving.x(), moving.y(), moving.z(), stance.x(), stance.y(), landed.x(), landed.y(), planned.x(), planned.y(),
                           qp->forces()[2], qp->forces()[5]};
  for (double x : values) y[o++] = x;
}

}  // namespace dmbd::control
