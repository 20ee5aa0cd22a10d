// The contact-phase state machine of the balancing controller (phase_machine.hpp).
#include "dmbd/wholebody/phase_machine.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "dmbd/base/error.hpp"

namespace dmbd::wholebody {

namespace {

// A phase ends on the tick whose time in the phase reaches its duration to within this
// (the clock is a sum of dt: 2000 additions of 0.001 s are off by ~1e-13 s).
constexpr double kTimeTolerance_s = 1e-9;
constexpr double kPi = 3.14159265358979323846;

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", x);
  return text;
}

void require(bool ok, const char* name, const char* expected, double value) {
  if (ok) return;
  throw InputError(std::string("phase machine: ") + name + " must be " + expected + " (got " + number(value) + ")");
}

void require_duration(const char* name, double value_s) {
  require(std::isfinite(value_s) && value_s > 0.0, name, "a positive number of seconds", value_s);
}

void require_values(const char* which, const ContactValues& v) {
  const std::string prefix = std::string(which) + ".";
  require(std::isfinite(v.max_normal_force_N) && v.max_normal_force_N >= 0.0,
          (prefix + "max_normal_force_N").c_str(), "a force of 0 N or more", v.max_normal_force_N);
  const std::pair<const char*, double> weights[] = {{"tangential_force_weight", v.tangential_force_weight},
                                                    {"normal_force_weight", v.normal_force_weight},
                                                    {"slack_weight", v.slack_weight}};
  for (const auto& [name, w] : weights)
    require(std::isfinite(w) && w > 0.0, (prefix + name).c_str(), "a positive weight", w);
}

void validate(const PhaseMachineParams& p) {
  require_duration("joint_move_s", p.joint_move_s);
  require_duration("body_lift_s", p.body_lift_s);
  require_duration("double_support_s", p.double_support_s);
  require_duration("lift_s", p.lift_s);
  require_duration("swing_s", p.swing_s);
  require_duration("landing_s", p.landing_s);
  require(std::isfinite(p.body_lift_start_force_N) && p.body_lift_start_force_N >= 0.0, "body_lift_start_force_N",
          "a force of 0 N or more", p.body_lift_start_force_N);
  require(std::isfinite(p.body_lift_end_force_N) && p.body_lift_end_force_N >= 0.0, "body_lift_end_force_N",
          "a force of 0 N or more", p.body_lift_end_force_N);
  require(std::isfinite(p.weight_shift_s) && p.weight_shift_s >= 0.0, "weight_shift_s", "0 s or more",
          p.weight_shift_s);
  require(std::isfinite(p.touch_down_ankle_velocity_rad_s), "touch_down_ankle_velocity_rad_s", "finite",
          p.touch_down_ankle_velocity_rad_s);
  require(p.touch_down_height_max_m > 0.0, "touch_down_height_max_m", "a positive height (infinite: no gate)",
          p.touch_down_height_max_m);
  require_values("stance", p.stance);
  require_values("swing", p.swing);
}

// Overlay names per phase (rows) and swing side (columns).
constexpr const char* kNames[7][2] = {{"JS", "JS"},     {"BL", "BL"},     {"DS", "DS"},    {"LF-L", "LF-R"},
                                      {"SW-L", "SW-R"}, {"LN-L", "LN-R"}, {"WS", "WS"}};

}  // namespace

Side other(Side s) { return s == Side::Left ? Side::Right : Side::Left; }

const char* to_string(Side s) { return s == Side::Left ? "L" : "R"; }

const char* to_string(Phase p) {
  switch (p) {
    case Phase::JointMove: return "joint move";
    case Phase::BodyLift: return "body lift";
    case Phase::DoubleSupport: return "double support";
    case Phase::Lift: return "lift";
    case Phase::Swing: return "swing";
    case Phase::Landing: return "landing";
    case Phase::WeightShift: return "weight shift";
  }
  return "?";
}

ContactValues blend(const ContactValues& a, const ContactValues& b, double alpha) {
  const double beta = 1.0 - alpha;
  return {beta * a.max_normal_force_N + alpha * b.max_normal_force_N,
          beta * a.tangential_force_weight + alpha * b.tangential_force_weight,
          beta * a.normal_force_weight + alpha * b.normal_force_weight, beta * a.slack_weight + alpha * b.slack_weight};
}

double contact_blend(double t_s, double duration_s) {
  const double s = std::clamp(t_s / duration_s, 0.0, 1.0);
  return 0.5 * (1.0 - std::cos(kPi * s));
}

PhaseMachine::PhaseMachine(const PhaseMachineParams& params) : params_(params) {
  validate(params_);
  reset();
}

void PhaseMachine::reset() {
  info_ = PhaseInfo();
  info_.swing_side = params_.first_swing_side;
  started_ = false;
  mid_swing_reached_ = false;
  enter(Phase::JointMove);
  info_.events = PhaseEvents();
  refresh();
}

const PhaseInfo& PhaseMachine::update(double dt_s, double left_ankle_velocity_rad_s,
                                      double right_ankle_velocity_rad_s, double swing_foot_height_m) {
  if (!(std::isfinite(dt_s) && dt_s >= 0.0))
    throw InputError("phase machine: the tick's dt_s must be 0 s or more (got " + number(dt_s) + ")");
  info_.events = PhaseEvents();
  if (!started_) {
    started_ = true;
    info_.events.phase_started = true;
    return info_;
  }
  info_.time_s += dt_s;
  info_.time_in_phase_s += dt_s;
  if (touch_down_triggered(left_ankle_velocity_rad_s, right_ankle_velocity_rad_s, swing_foot_height_m)) {
    end_swing(true);
  } else if (info_.time_in_phase_s >= info_.phase_duration_s - kTimeTolerance_s) {
    next_phase();
  } else if (info_.phase == Phase::Swing && !mid_swing_reached_ &&
             info_.time_in_phase_s >= 0.5 * info_.phase_duration_s - kTimeTolerance_s) {
    mid_swing_reached_ = true;
    info_.events.mid_swing = true;
  }
  refresh();
  return info_;
}

bool PhaseMachine::touch_down_triggered(double left_ankle_velocity_rad_s, double right_ankle_velocity_rad_s,
                                        double swing_foot_height_m) const {
  if (info_.phase != Phase::Swing || !mid_swing_reached_) return false;  // armed after the mid-swing tick
  if (!(swing_foot_height_m <= params_.touch_down_height_max_m)) return false;  // still in the air (NaN: unknown, not down)
  const double v = info_.swing_side == Side::Left ? left_ankle_velocity_rad_s : right_ankle_velocity_rad_s;
  return v < params_.touch_down_ankle_velocity_rad_s;
}

void PhaseMachine::next_phase() {
  switch (info_.phase) {
    case Phase::JointMove: enter(Phase::BodyLift); break;
    case Phase::BodyLift:
      if (params_.weight_shift_s > 0.0) {
        enter(Phase::WeightShift);
        break;
      }
      info_.step = 1;
      enter(Phase::DoubleSupport);
      break;
    case Phase::WeightShift:
      info_.step = 1;
      enter(Phase::DoubleSupport);
      break;
    case Phase::DoubleSupport: enter(Phase::Lift); break;
    case Phase::Lift:
      mid_swing_reached_ = false;
      enter(Phase::Swing);
      info_.events.swing_started = true;
      break;
    case Phase::Swing: end_swing(false); break;
    case Phase::Landing:
      ++info_.step;
      info_.swing_side = other(info_.swing_side);
      enter(Phase::DoubleSupport);
      break;
  }
}

void PhaseMachine::end_swing(bool early) {
  ++info_.touch_downs;
  enter(Phase::Landing);
  info_.events.touch_down = true;
  info_.events.touch_down_early = early;
}

void PhaseMachine::enter(Phase p) {
  info_.phase = p;
  info_.time_in_phase_s = 0.0;
  info_.phase_duration_s = duration_s(p);
  info_.events.phase_started = true;
}

double PhaseMachine::duration_s(Phase p) const {
  switch (p) {
    case Phase::JointMove: return params_.joint_move_s;
    case Phase::BodyLift: return params_.body_lift_s;
    case Phase::DoubleSupport: return params_.double_support_s;
    case Phase::Lift: return params_.lift_s;
    case Phase::Swing: return params_.swing_s;
    case Phase::Landing: return params_.landing_s;
    case Phase::WeightShift: return params_.weight_shift_s;
  }
  return 0.0;
}

void PhaseMachine::refresh() {
  const double t = info_.time_in_phase_s, T = info_.phase_duration_s;
  const bool blending = info_.phase == Phase::Lift || info_.phase == Phase::Landing;
  info_.alpha = blending ? contact_blend(t, T) : 0.0;
  info_.name = kNames[static_cast<int>(info_.phase)][static_cast<int>(info_.swing_side)];
  ContactValues start_up = params_.stance;
  switch (info_.phase) {
    case Phase::JointMove:
      start_up.max_normal_force_N = params_.body_lift_start_force_N;
      set_feet(start_up, true, start_up);
      break;
    case Phase::BodyLift: {
      const double s = std::clamp(t / T, 0.0, 1.0);
      start_up.max_normal_force_N =
          params_.body_lift_start_force_N + s * (params_.body_lift_end_force_N - params_.body_lift_start_force_N);
      set_feet(start_up, true, start_up);
      break;
    }
    case Phase::DoubleSupport:
    case Phase::WeightShift: set_feet(params_.stance, true, params_.stance); break;
    case Phase::Lift: set_feet(blend(params_.stance, params_.swing, info_.alpha), true, params_.stance); break;
    case Phase::Swing: set_feet(params_.swing, false, params_.stance); break;
    case Phase::Landing: set_feet(blend(params_.swing, params_.stance, info_.alpha), true, params_.stance); break;
  }
}

void PhaseMachine::set_feet(const ContactValues& swing_foot, bool swing_foot_in_contact,
                            const ContactValues& stance_foot) {
  FootContact& moving = info_.feet[static_cast<int>(info_.swing_side)];
  FootContact& standing = info_.feet[static_cast<int>(other(info_.swing_side))];
  moving = {swing_foot_in_contact, swing_foot};
  standing = {true, stance_foot};
}

}  // namespace dmbd::wholebody
