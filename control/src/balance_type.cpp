// The balance bus controller type: its options read from YAML (key by key over a base:
// the robot folder's, the scenario's, a variant's) and its controller built for a
// floating-base variant with contact (registry.hpp, balance_controller.hpp).
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "builtin_types.hpp"
#include "dmbd/base/error.hpp"
#include "dmbd/control/balance_controller.hpp"
#include "dmbd/wholebody/phase_machine.hpp"

namespace dmbd::control::detail {

namespace {

constexpr long long kMaxExactInteger = 1LL << 53;  // doubles hold every integer up to here

Eigen::Vector2d vec2(const yaml::Fields& f, const YAML::Node& n, const std::string& what) {
  if (!n.IsSequence() || n.size() != 2) f.fail(n, what + ": expected a list of 2 numbers [x, y]");
  return {f.number(n[0], what), f.number(n[1], what)};
}

// Two gains [kp, kd] of 0 or more.
JointFeedback gains(const yaml::Fields& f, const YAML::Node& n, const std::string& what, const char* expected) {
  const Eigen::Vector2d g = vec2(f, n, what);
  if ((g.array() < 0).any()) f.fail(n, what + ": " + expected);
  return {g[0], g[1]};
}

// [left, right] names.
std::array<std::string, 2> pair_of_names(const yaml::Fields& f, const YAML::Node& n, const std::string& what) {
  if (!n.IsSequence() || n.size() != 2) f.fail(n, what + ": expected [left, right] names");
  return {f.text(n[0], what), f.text(n[1], what)};
}

// A joint's gains replace that joint's (a joint not given keeps the base's).
void read_joint_feedback(const yaml::Fields& f, const YAML::Node& x, BalanceSetup& b) {
  if (!x.IsMap()) f.fail(x, "balance.joint_feedback: expected a map of joint: [kp, kd]");
  for (const auto& kv : x)
    f.reader().guard([&] {
      const std::string j = f.key(kv.first, "balance.joint_feedback");
      const JointFeedback g = gains(f, kv.second, "balance.joint_feedback." + j, "expected gains of 0 or more");
      for (auto& e : b.joint_feedback)
        if (e.first == j) return void(e.second = g);
      b.joint_feedback.push_back({j, g});
    });
}

void read_tvr_point(const yaml::Fields& f, const YAML::Node& x, BalanceSetup& b) {
  const char* expected = "balance.tvr_point: expected com, angular_momentum or {torso_offset_m: [x, y]}";
  if (x.IsScalar()) {
    const std::string point = x.as<std::string>();
    if (point != "com" && point != "angular_momentum") f.fail(x, expected);
    b.tvr_point = point == "com" ? TvrPoint::Com : TvrPoint::AngularMomentum;
    return;
  }
  if (!x.IsMap() || !x["torso_offset_m"]) f.fail(x, expected);
  f.keys(x, "balance.tvr_point", {"torso_offset_m"});
  b.tvr_point = TvrPoint::Torso;
  b.tvr_torso_offset_m = vec2(f, x["torso_offset_m"], "balance.tvr_point.torso_offset_m");
}

void read_task_gains(const yaml::Fields& f, const YAML::Node& x, BalanceTaskGains& g) {
  f.keys(x, "balance.task_gains", {"torso", "swing_foot", "joints", "com"});
  const std::pair<const char*, JointFeedback*> rows[] = {{"torso", &g.torso}, {"swing_foot", &g.swing_foot}, {"joints", &g.joints}, {"com", &g.com}};
  for (const auto& row : rows) {  // not a structured binding: C++17 lambdas cannot capture one
    const std::string what = std::string("balance.task_gains.") + row.first;
    JointFeedback* out = row.second;
    f.optional(x, row.first, [&, out](const YAML::Node& y) { *out = gains(f, y, what, "expected gains [kp, kd] of 0 or more"); });
  }
}

void read_phases(const yaml::Fields& f, const YAML::Node& x, wholebody::PhaseMachineParams& p) {
  f.keys(x, "balance.phases", {"joint_move_s", "body_lift_s", "weight_shift_s", "double_support_s", "lift_s", "swing_s", "landing_s",
                               "first_swing", "body_lift_start_force_N", "body_lift_end_force_N", "touch_down_height_max_m"});
  auto dur = [&](const char* k, double& d) {
    f.optional(x, k, [&](const YAML::Node& y) { d = f.number_in(y, std::string("balance.phases.") + k, 1e-4, 1e6, "s"); });
  };
  dur("joint_move_s", p.joint_move_s);
  dur("body_lift_s", p.body_lift_s);
  f.optional(x, "weight_shift_s", [&](const YAML::Node& y) { p.weight_shift_s = f.number_in(y, "balance.phases.weight_shift_s", 0.0, 1e6, "s"); });
  dur("double_support_s", p.double_support_s);
  dur("lift_s", p.lift_s);
  dur("swing_s", p.swing_s);
  dur("landing_s", p.landing_s);
  f.optional(x, "body_lift_start_force_N", [&](const YAML::Node& y) { p.body_lift_start_force_N = f.number_in(y, "balance.phases.body_lift_start_force_N", 0.0, 1e5, "N"); });
  f.optional(x, "body_lift_end_force_N", [&](const YAML::Node& y) { p.body_lift_end_force_N = f.number_in(y, "balance.phases.body_lift_end_force_N", 0.0, 1e5, "N"); });
  f.optional(x, "touch_down_height_max_m", [&](const YAML::Node& y) {
    p.touch_down_height_max_m = f.number_in(y, "balance.phases.touch_down_height_max_m", 1e-4, 1.0, "m");
  });
  f.optional(x, "first_swing", [&](const YAML::Node& y) {
    const std::string s = f.text(y, "balance.phases.first_swing");
    if (s == "left") p.first_swing_side = wholebody::Side::Left;
    else if (s == "right") p.first_swing_side = wholebody::Side::Right;
    else f.fail(y, "balance.phases.first_swing: expected left or right, got '" + s + "'");
  });
}

void read_planner(const yaml::Fields& f, const YAML::Node& n, BalanceSetup& b) {
  f.optional(n, "tvr", [&](const YAML::Node& x) {
    f.keys(x, "balance.tvr", {"t_prime_s", "kappa", "com_height_m", "lateral_width_m", "integral_gain", "integral_limit_m"});
    f.optional(x, "integral_gain", [&](const YAML::Node& y) {
      b.tvr_integral_gain = vec2(f, y, "balance.tvr.integral_gain");
      if (!(b.tvr_integral_gain.array() >= 0.0).all() || !(b.tvr_integral_gain.array() <= 1.0).all())
        f.fail(y, "balance.tvr.integral_gain: expected two gains from 0 to 1 (per step)");
    });
    f.optional(x, "integral_limit_m", [&](const YAML::Node& y) { b.tvr_integral_limit_m = f.number_in(y, "balance.tvr.integral_limit_m", 0.0, 10.0, "m"); });
    f.optional(x, "lateral_width_m", [&](const YAML::Node& y) { b.tvr.lateral_width_m = f.number_in(y, "balance.tvr.lateral_width_m", 0.0, 2.0, "m"); });
    f.optional(x, "t_prime_s", [&](const YAML::Node& y) { b.tvr.t_prime_s = vec2(f, y, "balance.tvr.t_prime_s"); });
    f.optional(x, "kappa", [&](const YAML::Node& y) { b.tvr.kappa = vec2(f, y, "balance.tvr.kappa"); });
    f.optional(x, "com_height_m", [&](const YAML::Node& y) { b.tvr.com_height_m = f.number_in(y, "balance.tvr.com_height_m", 0.1, 10.0, "m"); });
  });
  f.optional(n, "heading", [&](const YAML::Node& x) {
    f.keys(x, "balance.heading", {"gain", "step_max_rad"});
    f.optional(x, "gain", [&](const YAML::Node& y) { b.heading_gain = f.number_in(y, "balance.heading.gain", 0.0, 1.0, ""); });
    f.optional(x, "step_max_rad", [&](const YAML::Node& y) { b.heading_step_max_rad = f.number_in(y, "balance.heading.step_max_rad", 0.0, 0.5, "rad"); });
  });
  f.optional(n, "swing", [&](const YAML::Node& x) {
    f.keys(x, "balance.swing", {"mid_height_m", "landing_vertical_velocity_m_s", "horizontal_fraction"});
    f.optional(x, "horizontal_fraction", [&](const YAML::Node& y) { b.swing.horizontal_fraction = f.number_in(y, "balance.swing.horizontal_fraction", 0.05, 1.0, ""); });
    f.optional(x, "mid_height_m", [&](const YAML::Node& y) { b.swing.mid_height_m = f.number_in(y, "balance.swing.mid_height_m", 0.0, 1.0, "m"); });
    f.optional(x, "landing_vertical_velocity_m_s", [&](const YAML::Node& y) {
      b.swing.landing_vertical_velocity_m_s = f.number_in(y, "balance.swing.landing_vertical_velocity_m_s", -10.0, 0.0, "m/s");
    });
  });
  f.optional(n, "qp", [&](const YAML::Node& x) {
    f.keys(x, "balance.qp", {"mu", "w_qdd", "w_qdd_base", "torque_limit_Nm"});
    f.optional(x, "w_qdd_base", [&](const YAML::Node& y) { b.qp.w_qdd_base = f.number_in(y, "balance.qp.w_qdd_base", 1e-9, 1e12, ""); });
    f.optional(x, "mu", [&](const YAML::Node& y) { b.qp.mu = f.number_in(y, "balance.qp.mu", 0.0, 10.0, ""); });
    f.optional(x, "w_qdd", [&](const YAML::Node& y) { b.qp.w_qdd = f.number_in(y, "balance.qp.w_qdd", 1e-9, 1e12, ""); });
    f.optional(x, "torque_limit_Nm", [&](const YAML::Node& y) { b.qp.torque_limit_Nm = f.number_in(y, "balance.qp.torque_limit_Nm", 0.0, 1e6, "N m"); });
  });
}

// The robot's names the tasks use, and the joints' gains.
void read_names(const yaml::Fields& f, const YAML::Node& n, BalanceSetup& b) {
  f.optional(n, "torso_link", [&](const YAML::Node& x) { b.torso_link = f.text(x, "balance.torso_link"); });
  f.optional(n, "foot_links", [&](const YAML::Node& x) { b.foot_link = pair_of_names(f, x, "balance.foot_links"); });
  f.optional(n, "hip_yaw_joints", [&](const YAML::Node& x) { b.hip_yaw = pair_of_names(f, x, "balance.hip_yaw_joints"); });
  f.optional(n, "ankle_joints", [&](const YAML::Node& x) { b.ankle = pair_of_names(f, x, "balance.ankle_joints"); });
  f.optional(n, "joint_feedback", [&](const YAML::Node& x) { read_joint_feedback(f, x, b); });
  f.optional(n, "stance_posture", [&](const YAML::Node& x) { b.stance_posture = f.named_numbers(x, "balance.stance_posture"); });
}

void read_sensing(const yaml::Fields& f, const YAML::Node& n, BalanceSetup& b) {
  f.optional(n, "sensors", [&](const YAML::Node& x) {
    f.keys(x, "balance.sensors", {"q", "qd"});
    f.optional(x, "q", [&](const YAML::Node& y) { b.q_signal = f.text(y, "balance.sensors.q"); });
    f.optional(x, "qd", [&](const YAML::Node& y) { b.qd_signal = f.text(y, "balance.sensors.qd"); });
  });
  f.optional(n, "estimator", [&](const YAML::Node& x) {
    const std::string e = f.text(x, "balance.estimator");
    if (e == "kinematic") b.estimator = BalanceEstimator::Kinematic;
    else if (e == "motion_capture") b.estimator = BalanceEstimator::MotionCapture;
    else f.fail(x, "balance.estimator: expected kinematic or motion_capture, got '" + e + "'");
  });
  f.optional(n, "motion_capture_noise", [&](const YAML::Node& x) {
    f.keys(x, "balance.motion_capture_noise", {"position_m", "velocity_m_s"});
    f.optional(x, "position_m", [&](const YAML::Node& y) { b.mocap_position_noise_m = f.number_in(y, "balance.motion_capture_noise.position_m", 0.0, 1.0, "m"); });
    f.optional(x, "velocity_m_s", [&](const YAML::Node& y) { b.mocap_velocity_noise_m_s = f.number_in(y, "balance.motion_capture_noise.velocity_m_s", 0.0, 10.0, "m/s"); });
  });
  f.optional(n, "seed", [&](const YAML::Node& x) { b.seed = static_cast<unsigned long long>(f.integer(x, "balance.seed", 0, kMaxExactInteger)); });
}

void read_behaviour(const yaml::Fields& f, const YAML::Node& n, BalanceSetup& b) {
  f.optional(n, "torso_height_m", [&](const YAML::Node& x) { b.torso_height_m = f.number_in(x, "balance.torso_height_m", 0.1, 10.0, "m"); });
  f.optional(n, "swing_ankle_rad", [&](const YAML::Node& x) { b.swing_ankle_rad = f.number_in(x, "balance.swing_ankle_rad", -M_PI, M_PI, "rad"); });
  f.optional(n, "fall_tilt_rad", [&](const YAML::Node& x) { b.fall_tilt_rad = f.number_in(x, "balance.fall_tilt_rad", 0.0, M_PI, "rad"); });
  f.optional(n, "tvr_point", [&](const YAML::Node& x) { read_tvr_point(f, x, b); });
  f.optional(n, "task_gains", [&](const YAML::Node& x) { read_task_gains(f, x, b.task_gains); });
  f.optional(n, "swing_foot_level", [&](const YAML::Node& x) { b.swing_foot_level = f.boolean(x, "balance.swing_foot_level"); });
  f.optional(n, "actuator_feedforward", [&](const YAML::Node& x) { b.actuator_feedforward = f.boolean(x, "balance.actuator_feedforward"); });
  f.optional(n, "swing_relative_to_torso", [&](const YAML::Node& x) { b.swing_relative_to_torso = f.boolean(x, "balance.swing_relative_to_torso"); });
  f.optional(n, "ik_base_weight", [&](const YAML::Node& x) { b.ik_base_weight = f.number_in(x, "balance.ik_base_weight", 1e-6, 1e9, ""); });
  f.optional(n, "weight_shift", [&](const YAML::Node& x) {
    f.keys(x, "balance.weight_shift", {"offset_m", "speed_scale"});
    f.optional(x, "offset_m", [&](const YAML::Node& y) { b.weight_shift.offset_m = vec2(f, y, "balance.weight_shift.offset_m"); });
    f.optional(x, "speed_scale", [&](const YAML::Node& y) { b.weight_shift.speed_scale = f.number_in(y, "balance.weight_shift.speed_scale", 0.0, 10.0, ""); });
  });
  f.optional(n, "phases", [&](const YAML::Node& x) { read_phases(f, x, b.phases); });
}

class BalanceType : public BusControllerType {
 public:
  std::shared_ptr<BusControllerOptions> read(const yaml::Fields& f, const YAML::Node& n, const BusControllerOptions* base) const override {
    check_keys(f, n, "balance",
               {"stance_posture", "torso_height_m", "swing_ankle_rad", "tvr_point", "sensors", "estimator", "motion_capture_noise",
                "joint_feedback", "task_gains", "ik_base_weight", "swing_relative_to_torso", "actuator_feedforward", "swing_foot_level",
                "weight_shift", "phases", "tvr", "heading", "swing", "qp", "seed", "fall_tilt_rad", "torso_link", "foot_links", "hip_yaw_joints",
                "ankle_joints"});
    auto b = std::make_shared<BalanceSetup>();
    if (const auto* from = dynamic_cast<const BalanceSetup*>(base)) *b = *from;
    b->type = "balance";
    if (b->name.empty()) b->name = "balance";
    b->where = f.at(n);
    read_common_options(f, n, *b);
    read_names(f, n, *b);
    read_behaviour(f, n, *b);
    read_sensing(f, n, *b);
    read_planner(f, n, *b);
    return b;
  }

  std::shared_ptr<BusController> make(const BusControllerOptions& options, const BusControllerContext& c) const override {
    const auto& b = dynamic_cast<const BalanceSetup&>(options);
    if (c.base != model::BaseMode::Floating)
      throw InputError(b.where + ": " + b.name + ": balancing needs the robot's base floating (robot.base: floating)");
    if (!c.contact) throw InputError(b.where + ": " + b.name + ": balancing needs ground contact (robot.contact: true)");
    return std::make_shared<BalanceController>(c.robot, c.gravity_m_s2, c.actuators, c.q0, b, ticks_over(c.duration_s, b.rate_hz));
  }

  // The phase by its name in the frame's text, and the planned foothold on the ground.
  std::vector<sim::Overlay> overlays(const BusControllerOptions& o) const override {
    const std::string& n = o.name;
    sim::Overlay phase{"phase", {n + ".phase", "", ""}, {255, 255, 255}, false, 0.0, sim::Overlay::Kind::Text, {}};
    for (int k = 0; k <= static_cast<int>(wholebody::Phase::WeightShift); ++k) phase.value_names.emplace_back(wholebody::to_string(static_cast<wholebody::Phase>(k)));
    sim::Overlay foothold{"planned foothold", {n + ".foothold_x", n + ".foothold_y", ""}, {255, 140, 0}, false, 0.0, sim::Overlay::Kind::Marker, {}};
    return {phase, foothold};
  }
};

}  // namespace

std::shared_ptr<const BusControllerType> balance_type() { return std::make_shared<BalanceType>(); }

}  // namespace dmbd::control::detail
