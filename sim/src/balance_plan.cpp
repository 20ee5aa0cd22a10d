// BalanceController: what happens at the phase machine's events (balance_controller.hpp,
// steps 2 and 3): the start-up's starting points, the estimator's stance foot, the TVR
// footstep at the swing's start and again at mid-swing, the swing spline, and the
// landing's record (where the foot landed against where it was planned to).
#include "balance_impl.hpp"

namespace dmbd::sim {

using wholebody::Phase;

void BalanceController::Impl::on_events(const wholebody::PhaseInfo& ph) {
  const wholebody::PhaseEvents& ev = ph.events;
  const Side sw = ph.swing_side;
  if (ev.phase_started && ph.phase == Phase::JointMove) move_start_q = joint_q;
  if (ev.phase_started && ph.phase == Phase::BodyLift)
    lift_start_height = data.frames[static_cast<size_t>(torso_frame)].X_WF.translation().z();
  if (ev.phase_started && ph.phase == Phase::Lift) {
    // The other foot carries the robot from now on: the estimator's stance, latched here.
    estimator.set_stance(wholebody::other(sw), foot_point(wholebody::other(sw)));
    if (!com_desired_set) {
      com_desired = data.com.head<2>();
      com_desired_set = true;
    }
  }
  if (ev.swing_started) {
    swing_ankle_start = joint_q[ankle[static_cast<size_t>(sw)]];
    plan_step(ph, false);
  }
  if (ev.mid_swing) plan_step(ph, true);
  if (ev.touch_down) {
    landed = foot_point(sw).head<2>();
    planned = swing.target_m().head<2>();
  }
}

// The TVR foothold for the swing foot with the time left until touch-down; at the
// swing's start a new spline from where the foot is, at mid-swing the spline's target
// moved (its height kept: flat ground).
void BalanceController::Impl::plan_step(const wholebody::PhaseInfo& ph, bool replan) {
  const Side sw = ph.swing_side;
  wholebody::TvrInput in;
  in.com_m = data.com.head<2>();
  in.com_velocity_m_s = (data.J_com * v).head<2>();
  in.stance_foot_m = foot_point(wholebody::other(sw)).head<2>();
  in.com_desired_m = com_desired;
  in.swing = sw;
  in.time_to_switch_s = ph.phase_duration_s - ph.time_in_phase_s;
  const wholebody::TvrPlan plan = tvr.plan(in);
  foothold = plan.foothold_m;
  if (!replan) {
    const Eigen::Vector3d lift_off = foot_point(sw);
    swing.start(lift_off, Eigen::Vector3d(foothold.x(), foothold.y(), lift_off.z()), ph.phase_duration_s);
  } else {
    const Eigen::Vector3d target = swing.target_m();
    swing.replan(ph.time_in_phase_s, Eigen::Vector3d(foothold.x(), foothold.y(), target.z()));
  }
}

}  // namespace dmbd::sim
