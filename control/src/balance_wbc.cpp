// BalanceController: the whole-body control of one tick (balance_controller.hpp, steps
// 4–6): the phase's tasks, the prioritised IK, joint feedback, the QP.
#include <algorithm>
#include <cmath>

#include "balance_impl.hpp"

namespace dmbd::control {

using wholebody::Phase;

namespace {

// Minimum-jerk blend from a to b over T: value, rate and acceleration at t.
struct Blend {
  double p, v, a;
};
Blend min_jerk(double a, double b, double t, double T) {
  const double u = std::clamp(t / T, 0.0, 1.0);
  const double s = u * u * u * (10.0 - 15.0 * u + 6.0 * u * u);
  const double ds = t < T ? 30.0 * u * u * (1.0 - u) * (1.0 - u) / T : 0.0;
  const double dds = t < T ? 60.0 * u * (1.0 - u) * (1.0 - 2.0 * u) / (T * T) : 0.0;
  return {a + (b - a) * s, (b - a) * ds, (b - a) * dds};
}

// The quintic from (a, 0, 0) to (b, v_end, 0) over T: value, rate and acceleration at t.
Blend quintic_to_rate(double a, double b, double v_end, double t, double T) {
  const double u = std::clamp(t / T, 0.0, 1.0);
  const Blend m = min_jerk(a, b, t, T);
  // v_end T (−4u³ + 7u⁴ − 3u⁵): value, rate and acceleration 0 at u = 0; 0, v_end, 0 at 1.
  const double f = u * u * u * (-4.0 + 7.0 * u - 3.0 * u * u);
  const double df = u * u * (-12.0 + 28.0 * u - 15.0 * u * u);
  const double ddf = u * (-24.0 + 84.0 * u - 60.0 * u * u);
  return {m.p + v_end * T * f, m.v + v_end * df, m.a + v_end * ddf / T};
}

wholebody::ContactSetting setting(const wholebody::FootContact& f) {
  return {f.values.max_normal_force_N, f.values.tangential_force_weight, f.values.normal_force_weight, f.values.slack_weight};
}

}  // namespace

// Start-up joint move: every joint on a minimum-jerk path to the stance posture, the
// base's accelerations left to the QP.
void BalanceController::Impl::joint_move(const wholebody::PhaseInfo& ph) {
  const wholebody::Layout& l = model.layout();
  qdd_cmd.setZero();
  for (int j = 0; j < nj; ++j) {
    const Blend b = min_jerk(move_start_q[j], stance_q[j], ph.time_in_phase_s, ph.phase_duration_s);
    q_des[j] = b.p;
    qd_des[j] = b.v;
    qdd_cmd[l.joints[static_cast<size_t>(j)].v_index] = b.a;
  }
}

// Torso: roll and pitch 0 (about its current heading), height to torso_height_m
// (a minimum-jerk rise through the body lift).
void BalanceController::Impl::set_torso_reference(const wholebody::PhaseInfo& ph) {
  const Eigen::Isometry3d& X = data.frames[static_cast<size_t>(torso_frame)].X_WF;
  const double yaw = std::atan2(X.linear()(1, 0), X.linear()(0, 0));
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  torso_orientation->set_reference(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix(), zero, zero);
  Blend h{setup.torso_height_m, 0.0, 0.0};
  if (ph.phase == Phase::BodyLift) h = min_jerk(lift_start_height, setup.torso_height_m, ph.time_in_phase_s, ph.phase_duration_s);
  torso_position->set_reference(Eigen::Vector3d(X.translation().x(), X.translation().y(), h.p), Eigen::Vector3d(0, 0, h.v),
                                Eigen::Vector3d(0, 0, h.a));
}

// The weight shift's CoM: on its quintic in x and y, its height free (the torso's task).
void BalanceController::Impl::set_com_reference(const wholebody::PhaseInfo& ph) {
  Eigen::Vector3d p(0, 0, data.com.z()), v = Eigen::Vector3d::Zero(), a = Eigen::Vector3d::Zero();
  for (int i = 0; i < 2; ++i) {
    const Blend b = quintic_to_rate(shift_start[i], shift_end[i], shift_end_velocity[i], ph.time_in_phase_s, ph.phase_duration_s);
    p[i] = b.p;
    v[i] = b.v;
    a[i] = b.a;
  }
  com->set_reference(p, v, a);
}

// The IK of the phase: both feet in contact except in the swing (then the stance foot,
// and the swing ankle and foot as tasks).
void BalanceController::Impl::solve_ik(const wholebody::PhaseInfo& ph) {
  const wholebody::Layout& l = model.layout();
  Eigen::Vector2d yaw_v = Eigen::Vector2d::Zero(), yaw_a = Eigen::Vector2d::Zero();  // named: a Ref to an expression would allocate
  if (ph.phase == Phase::Swing) {  // the heading hold's offsets (plan_heading)
    const Blend b = min_jerk(0.0, 1.0, ph.time_in_phase_s, ph.phase_duration_s);
    const Eigen::Vector2d d = hip_yaw_offset_end - hip_yaw_offset_start;
    hip_yaw_offset = hip_yaw_offset_start + b.p * d;
    yaw_v = b.v * d;
    yaw_a = b.a * d;
  }
  const Eigen::Vector2d yaw_d(stance_q[hip_yaw[0]] + hip_yaw_offset[0], stance_q[hip_yaw[1]] + hip_yaw_offset[1]);
  hip_yaws->set_reference(yaw_d, yaw_v, yaw_a);
  set_torso_reference(ph);
  hip_yaws->update(data);
  torso->update(data);
  const wholebody::PrioritizedIk* ik = ik_double.get();
  if (ph.phase == Phase::WeightShift) {
    set_com_reference(ph);
    com_y->update(data);
    const wholebody::Task* tasks[] = {hip_yaws.get(), torso.get(), com_y.get()};
    ik_shift->solve(data, J_double, Jdv_double, tasks);
    ik = ik_shift.get();
  } else if (ph.phase != Phase::Swing) {
    const wholebody::Task* tasks[] = {hip_yaws.get(), torso.get()};
    ik_double->solve(data, J_double, Jdv_double, tasks);
  } else {
    const auto sw = static_cast<size_t>(ph.swing_side);
    const auto st = static_cast<size_t>(wholebody::other(ph.swing_side));
    J_single = data.frames[static_cast<size_t>(foot_frame[st])].J.bottomRows<3>();
    Jdv_single = data.frames[static_cast<size_t>(foot_frame[st])].Jdot_v.tail<3>();
    const Blend a = min_jerk(swing_ankle_start, setup.swing_ankle_rad, ph.time_in_phase_s, 0.5 * ph.phase_duration_s);
    Eigen::Matrix<double, 1, 1> ad, vd, dd;
    ad << a.p;
    vd << a.v;
    dd << a.a;
    swing_ankle[sw]->set_reference(ad, vd, dd);
    wholebody::SwingSample s = swing.at(ph.time_in_phase_s);
    if (setup.swing_relative_to_torso) {  // from the torso as it is and moves (its acceleration unknown: 0)
      const auto& torso_data = data.frames[static_cast<size_t>(torso_frame)];
      s.position_m -= torso_data.X_WF.translation();
      s.velocity_m_s.noalias() -= torso_data.J.bottomRows<3>() * v;
    }
    swing_foot[sw]->set_reference(s.position_m, s.velocity_m_s, s.acceleration_m_s2);
    swing_ankle[sw]->update(data);
    swing_foot[sw]->update(data);
    const wholebody::Task* foot_angle = swing_ankle[sw].get();
    if (setup.swing_foot_level) {  // the sole kept as it stood, about the world's y axis
      const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
      foot_orientation[sw]->set_reference(foot_flat_R[sw], zero, zero);
      foot_pitch[sw]->update(data);
      foot_angle = foot_pitch[sw].get();
    }
    const wholebody::Task* tasks[] = {hip_yaws.get(), foot_angle, torso.get(), swing_foot[sw].get()};
    ik_single->solve(data, J_single, Jdv_single, tasks);
    ik = ik_single.get();
  }
  qdd_cmd = ik->qdd();
  for (int j = 0; j < nj; ++j) {
    const int i = l.joints[static_cast<size_t>(j)].v_index;
    q_des[j] = joint_q[j] + ik->delta_q()[i];
    qd_des[j] = ik->qd()[i];
  }
  clamp_to_limits();
}

// Targets within the joints' ranges: near a singularity (a straight knee) the IK's step
// grows without bound (a knee target of −20 rad was seen after a push), and no joint
// can follow a target past its stop. A target clamped at a limit gets no rate or
// acceleration beyond it.
void BalanceController::Impl::clamp_to_limits() {
  const wholebody::Layout& l = model.layout();
  for (int j = 0; j < nj; ++j) {
    const wholebody::JointLimits& lim = l.joints[static_cast<size_t>(j)].limits;
    const int i = l.joints[static_cast<size_t>(j)].v_index;
    const bool low = q_des[j] <= lim.lower_rad, high = q_des[j] >= lim.upper_rad;
    q_des[j] = std::clamp(q_des[j], lim.lower_rad, lim.upper_rad);
    if ((low && qd_des[j] < 0) || (high && qd_des[j] > 0)) qd_des[j] = 0;
    if ((low && qdd_cmd[i] < 0) || (high && qdd_cmd[i] > 0)) qdd_cmd[i] = 0;
  }
}

// q̈_cmd's joint rows get the joint feedback; then the QP with the phase's contact values.
bool BalanceController::Impl::solve_qp(const wholebody::PhaseInfo& ph) {
  const wholebody::Layout& l = model.layout();
  for (int j = 0; j < nj; ++j) {
    const int i = l.joints[static_cast<size_t>(j)].v_index;
    qdd_cmd[i] += kp[j] * (q_des[j] - joint_q[j]) + kd[j] * (qd_des[j] - joint_v[j]);
  }
  const wholebody::ContactSetting contacts[2] = {setting(ph.foot(Side::Left)), setting(ph.foot(Side::Right))};
  if (qp->solve(data, J_double, Jdv_double, qdd_cmd, contacts) != wholebody::QpStatus::Optimal) return false;
  for (int j = 0; j < nj; ++j) {
    tau_ff[j] = qp->tau()[j];
    qdd_joint[j] = qp->qdd()[l.joints[static_cast<size_t>(j)].v_index];
  }
  return true;
}

bool BalanceController::Impl::whole_body(const wholebody::PhaseInfo& ph) {
  for (int s = 0; s < 2; ++s) {
    const auto& f = data.frames[static_cast<size_t>(foot_frame[static_cast<size_t>(s)])];
    J_double.middleRows<3>(3 * s) = f.J.bottomRows<3>();
    Jdv_double.segment<3>(3 * s) = f.Jdot_v.tail<3>();
  }
  last_q_des = q_des;
  last_qd_des = qd_des;
  if (ph.phase == Phase::JointMove)
    joint_move(ph);
  else
    solve_ik(ph);
  if (solve_qp(ph)) return true;
  q_des = last_q_des;  // hold the last command
  qd_des = last_qd_des;
  return false;
}

}  // namespace dmbd::control
