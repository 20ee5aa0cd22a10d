// BalanceController: what happens at the phase machine's events (balance_controller.hpp,
// steps 2 and 3): the start-up's starting points, the estimator's stance foot, the TVR
// footstep at the swing's start and again at mid-swing, the swing spline, the heading
// hold's hip yaw offsets, and the
// landing's record (where the foot stands once it has come down, at the next lift's
// start, against where it was planned to at touch-down).
#include <algorithm>
#include <cmath>

#include "balance_impl.hpp"
#include "dmbd/wholebody/momentum.hpp"

namespace dmbd::control {

using wholebody::Phase;

void BalanceController::Impl::on_events(const wholebody::PhaseInfo& ph) {
  const wholebody::PhaseEvents& ev = ph.events;
  const Side sw = ph.swing_side;
  if (ev.phase_started && ph.phase == Phase::JointMove) move_start_q = joint_q;
  if (ev.phase_started && ph.phase == Phase::BodyLift)
    lift_start_height = data.frames[static_cast<size_t>(torso_frame)].X_WF.translation().z();
  if (ev.phase_started && ph.phase == Phase::WeightShift) plan_weight_shift(ph);
  if (ev.phase_started && ph.phase == Phase::Lift) {
    // The other foot carries the robot from now on: the estimator's stance, latched here.
    estimator.set_stance(wholebody::other(sw), foot_point(wholebody::other(sw)));
    foot_flat_R[static_cast<size_t>(sw)] = data.frames[static_cast<size_t>(foot_frame[static_cast<size_t>(sw)])].X_WF.linear();
    if (landing_pending) {  // it came down in the last step and has settled: where it stands
      landed = foot_point(wholebody::other(sw)).head<2>();
      ++landings;
      landing_pending = false;
    }
    if (!com_desired_set) {
      Eigen::Vector2d velocity;
      pendulum_state(wholebody::other(sw), com_desired, velocity);
      com_desired_set = true;
    }
  }
  if (ev.swing_started) {
    swing_ankle_start = joint_q[ankle[static_cast<size_t>(sw)]];
    plan_heading(sw);
    plan_step(ph, false);
  }
  if (ev.mid_swing) plan_step(ph, true);
  if (ev.touch_down) {
    planned = swing.target_m().head<2>();
    landing_pending = true;
  }
}

// The heading hold (BalanceSetup::heading_gain): the stance hip yaw's offset moves by
// -dpsi / a_z over the swing, a_z its axis's world z component (the stance foot's angular
// Jacobian column): with that foot planted the torso turns by dpsi. The swing hip yaw
// returns to its stance angle while its foot is in the air.
void BalanceController::Impl::plan_heading(Side sw) {
  hip_yaw_offset_start = hip_yaw_offset;
  hip_yaw_offset_end = hip_yaw_offset;
  hip_yaw_offset_end[static_cast<Eigen::Index>(sw)] = 0.0;
  if (setup.heading_gain <= 0.0) return;
  const Eigen::Matrix3d& R = data.frames[static_cast<size_t>(torso_frame)].X_WF.linear();
  const double yaw = std::atan2(R(1, 0), R(0, 0));
  if (!heading_set) {
    heading = yaw;
    heading_set = true;
  }
  const double limit = setup.heading_step_max_rad;
  const double dpsi = std::clamp(setup.heading_gain * std::remainder(heading - yaw, 2 * M_PI), -limit, limit);
  const auto st = static_cast<size_t>(wholebody::other(sw));
  const int column = model.layout().joints[static_cast<size_t>(hip_yaw[st])].v_index;
  const double a_z = data.frames[static_cast<size_t>(foot_frame[st])].J(2, column);
  if (std::abs(a_z) < 0.5) return;  // a hip yaw far from vertical turns the torso little
  hip_yaw_offset_end[static_cast<Eigen::Index>(st)] -= dpsi / a_z;
}

// The planner's pendulum state (TvrPoint): its position and its velocity, world xy.
void BalanceController::Impl::pendulum_state(Side stance, Eigen::Vector2d& position_m,
                                            Eigen::Vector2d& velocity_m_s) const {
  if (setup.tvr_point == TvrPoint::AngularMomentum) {
    position_m = data.com.head<2>();
    velocity_m_s = wholebody::contact_pendulum_velocity(data, foot_point(stance), tvr.params().com_height_m);
    return;
  }
  if (setup.tvr_point == TvrPoint::Com) {
    position_m = data.com.head<2>();
    velocity_m_s.noalias() = data.J_com.topRows<2>() * v;
    return;
  }
  const Eigen::Isometry3d& X = data.frames[static_cast<size_t>(torso_frame)].X_WF;
  const double yaw = std::atan2(X.linear()(1, 0), X.linear()(0, 0));
  const Eigen::Vector2d offset = Eigen::Rotation2Dd(yaw) * setup.tvr_torso_offset_m;
  position_m = X.translation().head<2>() + offset;
  velocity_m_s = v.segment<2>(3);  // the torso origin's (world)
}

// The weight shift's CoM path (balance_controller.hpp, BalanceWeightShift): from where the
// CoM is to midway between the feet (plus the offset), arriving at the stepping orbit's
// lateral speed toward the first stance foot.
void BalanceController::Impl::plan_weight_shift(const wholebody::PhaseInfo& ph) {
  const Eigen::Vector3d swing_foot = foot_point(ph.swing_side), stance_foot = foot_point(wholebody::other(ph.swing_side));
  shift_start = data.com.head<2>();
  shift_end = 0.5 * (swing_foot + stance_foot).head<2>() + setup.weight_shift.offset_m;
  const double step_s = tvr.params().step_period_s;
  const double w = tvr.omega_per_s();
  const double half_width = 0.5 * std::abs(swing_foot.y() - stance_foot.y());
  const double speed = setup.weight_shift.speed_scale * half_width * w * std::tanh(0.5 * w * step_s);
  shift_end_velocity = Eigen::Vector2d(0.0, stance_foot.y() > swing_foot.y() ? speed : -speed);
}

// The TVR foothold for the swing foot with the time left until touch-down; at the
// swing's start a new spline from where the foot is, at mid-swing the spline's target
// moved (its height kept: flat ground).
void BalanceController::Impl::plan_step(const wholebody::PhaseInfo& ph, bool replan) {
  const Side sw = ph.swing_side;
  wholebody::TvrInput in;
  pendulum_state(wholebody::other(sw), in.com_m, in.com_velocity_m_s);
  in.stance_foot_m = foot_point(wholebody::other(sw)).head<2>();
  in.com_desired_m = com_desired + com_integral;
  in.swing = sw;
  in.time_to_switch_s = ph.phase_duration_s - ph.time_in_phase_s;
  const wholebody::TvrPlan plan = tvr.plan(in);
  foothold = plan.foothold_m;
  if (!replan) {
    const double limit = setup.tvr_integral_limit_m;
    com_integral = (com_integral + setup.tvr_integral_gain.cwiseProduct(com_desired - plan.switching_com_m)).cwiseMax(-limit).cwiseMin(limit);
    const Eigen::Vector3d lift_off = foot_point(sw);
    swing.start(lift_off, Eigen::Vector3d(foothold.x(), foothold.y(), lift_off.z()), ph.phase_duration_s);
  } else {
    const Eigen::Vector3d target = swing.target_m();
    swing.replan(ph.time_in_phase_s, Eigen::Vector3d(foothold.x(), foothold.y(), target.z()));
  }
}

}  // namespace dmbd::control
