// Reading a scenario's balance map (docs/scenario-format.md, "balance"; the controller:
// balance_controller.hpp): every key checked at its line, a variant's map merged key by
// key into the base's.
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "scenario_reader.hpp"

namespace dmbd::sim::detail {

// The balancing controller (balance_controller.hpp), merged key by key into the base's.
void Reader::balance(const YAML::Node& n, VariantSetup& v) const {
  keys(n, "balance", {"stance_posture", "torso_height_m", "swing_ankle_rad", "tvr_point", "rate_hz", "delay_s", "sensors", "estimator",
                      "motion_capture_noise", "joint_feedback", "task_gains", "ik_base_weight", "swing_relative_to_torso", "actuator_feedforward",
                      "swing_foot_level", "weight_shift", "phases", "tvr", "swing", "qp", "seed",
                      "fall_tilt_rad"});
  BalanceSetup b = v.balance.value_or(BalanceSetup{});
  b.where = at(n);
  optional(n, "stance_posture", [&](const YAML::Node& x) { b.stance_posture = angles(x, "balance.stance_posture"); });
  optional(n, "torso_height_m", [&](const YAML::Node& x) { b.torso_height_m = rd.number_in(x, "balance.torso_height_m", 0.1, 10.0, "m"); });
  optional(n, "swing_ankle_rad", [&](const YAML::Node& x) { b.swing_ankle_rad = rd.number_in(x, "balance.swing_ankle_rad", -M_PI, M_PI, "rad"); });
  optional(n, "fall_tilt_rad", [&](const YAML::Node& x) { b.fall_tilt_rad = rd.number_in(x, "balance.fall_tilt_rad", 0.0, M_PI, "rad"); });
  optional(n, "rate_hz", [&](const YAML::Node& r) { b.rate_hz = rate(r, "balance.rate_hz"); });
  optional(n, "delay_s", [&](const YAML::Node& d) {
    const double delay = rd.number_in(d, "balance.delay_s", 0.0, 1e9, "s");
    if (delay > 1.0 / b.rate_hz)
      fail(d, fmt::format("balance.delay_s: {} s is longer than one period of {} Hz ({} s)", delay, b.rate_hz, 1.0 / b.rate_hz));
    b.delay_s = delay;
  });
  optional(n, "sensors", [&](const YAML::Node& x) {
    keys(x, "balance.sensors", {"q", "qd"});
    optional(x, "q", [&](const YAML::Node& y) { b.q_signal = text(y, "balance.sensors.q"); });
    optional(x, "qd", [&](const YAML::Node& y) { b.qd_signal = text(y, "balance.sensors.qd"); });
  });
  optional(n, "estimator", [&](const YAML::Node& x) {
    const std::string e = text(x, "balance.estimator");
    if (e == "kinematic") b.estimator = BalanceEstimator::Kinematic;
    else if (e == "motion_capture") b.estimator = BalanceEstimator::MotionCapture;
    else fail(x, "balance.estimator: expected kinematic or motion_capture, got '" + e + "'");
  });
  optional(n, "motion_capture_noise", [&](const YAML::Node& x) {
    keys(x, "balance.motion_capture_noise", {"position_m", "velocity_m_s"});
    optional(x, "position_m", [&](const YAML::Node& y) { b.mocap_position_noise_m = rd.number_in(y, "balance.motion_capture_noise.position_m", 0.0, 1.0, "m"); });
    optional(x, "velocity_m_s", [&](const YAML::Node& y) { b.mocap_velocity_noise_m_s = rd.number_in(y, "balance.motion_capture_noise.velocity_m_s", 0.0, 10.0, "m/s"); });
  });
  optional(n, "seed", [&](const YAML::Node& x) { b.seed = static_cast<unsigned long long>(integer(x, "balance.seed", 0, kMaxExactInteger)); });
  optional(n, "joint_feedback", [&](const YAML::Node& x) {
    if (!x.IsMap()) fail(x, "balance.joint_feedback: expected a map of joint: [kp, kd]");
    b.joint_feedback.clear();
    for (const auto& kv : x) {
      const std::string j = key(kv.first, "balance.joint_feedback");
      const Eigen::Vector2d g = vec2(kv.second, "balance.joint_feedback." + j);
      if ((g.array() < 0).any()) fail(kv.second, "balance.joint_feedback." + j + ": expected gains of 0 or more");
      b.joint_feedback.push_back({j, {g[0], g[1]}});
    }
  });
  optional(n, "tvr_point", [&](const YAML::Node& x) {
    const char* expected = "balance.tvr_point: expected com or {torso_offset_m: [x, y]}";
    if (x.IsScalar()) {
      if (x.as<std::string>() != "com") fail(x, expected);
      b.tvr_point = TvrPoint::Com;
      return;
    }
    if (!x.IsMap() || !x["torso_offset_m"]) fail(x, expected);
    keys(x, "balance.tvr_point", {"torso_offset_m"});
    b.tvr_point = TvrPoint::Torso;
    b.tvr_torso_offset_m = vec2(x["torso_offset_m"], "balance.tvr_point.torso_offset_m");
  });
  optional(n, "task_gains", [&](const YAML::Node& x) {
    keys(x, "balance.task_gains", {"torso", "swing_foot", "joints", "com"});
    const std::pair<const char*, JointFeedback*> rows[] = {{"torso", &b.task_gains.torso}, {"swing_foot", &b.task_gains.swing_foot},
                                                           {"joints", &b.task_gains.joints}, {"com", &b.task_gains.com}};
    for (const auto& row : rows) {  // not a structured binding: C++17 lambdas cannot capture one
      const std::string what = std::string("balance.task_gains.") + row.first;
      JointFeedback* gains = row.second;
      optional(x, row.first, [&, gains](const YAML::Node& y) {
        const Eigen::Vector2d kpd = vec2(y, what);
        if ((kpd.array() < 0).any()) fail(y, what + ": expected gains [kp, kd] of 0 or more");
        *gains = {kpd[0], kpd[1]};
      });
    }
  });
  optional(n, "swing_foot_level", [&](const YAML::Node& x) { b.swing_foot_level = rd.boolean(x, "balance.swing_foot_level"); });
  optional(n, "actuator_feedforward", [&](const YAML::Node& x) { b.actuator_feedforward = rd.boolean(x, "balance.actuator_feedforward"); });
  optional(n, "swing_relative_to_torso", [&](const YAML::Node& x) { b.swing_relative_to_torso = rd.boolean(x, "balance.swing_relative_to_torso"); });
  optional(n, "ik_base_weight", [&](const YAML::Node& x) { b.ik_base_weight = rd.number_in(x, "balance.ik_base_weight", 1e-6, 1e9, ""); });
  optional(n, "weight_shift", [&](const YAML::Node& x) {
    keys(x, "balance.weight_shift", {"offset_m", "speed_scale"});
    optional(x, "offset_m", [&](const YAML::Node& y) { b.weight_shift.offset_m = vec2(y, "balance.weight_shift.offset_m"); });
    optional(x, "speed_scale", [&](const YAML::Node& y) { b.weight_shift.speed_scale = rd.number_in(y, "balance.weight_shift.speed_scale", 0.0, 10.0, ""); });
  });
  optional(n, "phases", [&](const YAML::Node& x) { balance_phases(x, b.phases); });
  optional(n, "tvr", [&](const YAML::Node& x) {
    keys(x, "balance.tvr", {"t_prime_s", "kappa", "com_height_m"});
    optional(x, "t_prime_s", [&](const YAML::Node& y) { b.tvr.t_prime_s = vec2(y, "balance.tvr.t_prime_s"); });
    optional(x, "kappa", [&](const YAML::Node& y) { b.tvr.kappa = vec2(y, "balance.tvr.kappa"); });
    optional(x, "com_height_m", [&](const YAML::Node& y) { b.tvr.com_height_m = rd.number_in(y, "balance.tvr.com_height_m", 0.1, 10.0, "m"); });
  });
  optional(n, "swing", [&](const YAML::Node& x) {
    keys(x, "balance.swing", {"mid_height_m", "landing_vertical_velocity_m_s", "horizontal_fraction"});
    optional(x, "horizontal_fraction", [&](const YAML::Node& y) {
      b.swing.horizontal_fraction = rd.number_in(y, "balance.swing.horizontal_fraction", 0.05, 1.0, "");
    });
    optional(x, "mid_height_m", [&](const YAML::Node& y) { b.swing.mid_height_m = rd.number_in(y, "balance.swing.mid_height_m", 0.0, 1.0, "m"); });
    optional(x, "landing_vertical_velocity_m_s", [&](const YAML::Node& y) {
      b.swing.landing_vertical_velocity_m_s = rd.number_in(y, "balance.swing.landing_vertical_velocity_m_s", -10.0, 0.0, "m/s");
    });
  });
  optional(n, "qp", [&](const YAML::Node& x) {
    keys(x, "balance.qp", {"mu", "w_qdd", "w_qdd_base", "torque_limit_Nm"});
    optional(x, "w_qdd_base", [&](const YAML::Node& y) { b.qp.w_qdd_base = rd.number_in(y, "balance.qp.w_qdd_base", 1e-9, 1e12, ""); });
    optional(x, "mu", [&](const YAML::Node& y) { b.qp.mu = rd.number_in(y, "balance.qp.mu", 0.0, 10.0, ""); });
    optional(x, "w_qdd", [&](const YAML::Node& y) { b.qp.w_qdd = rd.number_in(y, "balance.qp.w_qdd", 1e-9, 1e12, ""); });
    optional(x, "torque_limit_Nm", [&](const YAML::Node& y) { b.qp.torque_limit_Nm = rd.number_in(y, "balance.qp.torque_limit_Nm", 0.0, 1e6, "N m"); });
  });
  v.balance = b;
}

void Reader::balance_phases(const YAML::Node& x, wholebody::PhaseMachineParams& p) const {
  keys(x, "balance.phases", {"joint_move_s", "body_lift_s", "weight_shift_s", "double_support_s", "lift_s", "swing_s", "landing_s",
                             "first_swing", "body_lift_start_force_N", "body_lift_end_force_N"});
  auto dur = [&](const char* k, double& d) {
    optional(x, k, [&](const YAML::Node& y) { d = rd.number_in(y, std::string("balance.phases.") + k, 1e-4, 1e6, "s"); });
  };
  dur("joint_move_s", p.joint_move_s);
  dur("body_lift_s", p.body_lift_s);
  optional(x, "weight_shift_s", [&](const YAML::Node& y) { p.weight_shift_s = rd.number_in(y, "balance.phases.weight_shift_s", 0.0, 1e6, "s"); });
  dur("double_support_s", p.double_support_s);
  dur("lift_s", p.lift_s);
  dur("swing_s", p.swing_s);
  dur("landing_s", p.landing_s);
  optional(x, "body_lift_start_force_N", [&](const YAML::Node& y) { p.body_lift_start_force_N = rd.number_in(y, "balance.phases.body_lift_start_force_N", 0.0, 1e5, "N"); });
  optional(x, "body_lift_end_force_N", [&](const YAML::Node& y) { p.body_lift_end_force_N = rd.number_in(y, "balance.phases.body_lift_end_force_N", 0.0, 1e5, "N"); });
  optional(x, "first_swing", [&](const YAML::Node& y) {
    const std::string s = text(y, "balance.phases.first_swing");
    if (s == "left") p.first_swing_side = wholebody::Side::Left;
    else if (s == "right") p.first_swing_side = wholebody::Side::Right;
    else fail(y, "balance.phases.first_swing: expected left or right, got '" + s + "'");
  });
}

}  // namespace dmbd::sim::detail
