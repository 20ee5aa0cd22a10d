// The TVR footstep planner on the linear inverted pendulum (tvr.hpp).
#include "dmbd/wholebody/tvr.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "dmbd/base/error.hpp"

namespace dmbd::wholebody {

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw InputError("TVR planner: " + what);
}

void validate(const TvrParams& p) {
  require(std::isfinite(p.com_height_m) && p.com_height_m > 0, "com_height_m must be positive");
  require(std::isfinite(p.gravity_m_s2) && p.gravity_m_s2 > 0, "gravity_m_s2 must be positive");
  require(p.t_prime_s.allFinite() && (p.t_prime_s.array() > 0).all(), "t_prime_s must be positive (x and y)");
  require(p.kappa.allFinite(), "kappa must be finite (x and y)");
  require(p.step_x_min_m <= p.step_x_max_m, "step_x_min_m must not exceed step_x_max_m");
  require(p.step_lateral_min_m >= 0 && p.step_lateral_min_m <= p.step_lateral_max_m,
          "step_lateral_min_m must lie in [0, step_lateral_max_m]");
  require(p.switching_speed_min_m_s >= 0 && p.switching_speed_min_m_s <= p.switching_speed_max_m_s,
          "switching_speed_min_m_s must lie in [0, switching_speed_max_m_s]");
  require(p.slow_time_scale > 0 && p.fast_time_scale > 0, "the time scales must be positive");
  require(std::isfinite(p.lateral_width_m) && p.lateral_width_m >= 0, "lateral_width_m must be 0 or positive");
  require(std::isfinite(p.step_period_s) && p.step_period_s > 0, "step_period_s must be positive");
}

}  // namespace

LipmAxisState lipm_state_after(double x0_m, double v0_m_s, double foot_m, double omega_per_s, double t_s) {
  const double a = 0.5 * ((x0_m - foot_m) + v0_m_s / omega_per_s);
  const double b = 0.5 * ((x0_m - foot_m) - v0_m_s / omega_per_s);
  const double grow = std::exp(omega_per_s * t_s), decay = std::exp(-omega_per_s * t_s);
  return {a * grow + b * decay + foot_m, omega_per_s * (a * grow - b * decay)};
}

double reversal_foothold(double xs_m, double vs_m_s, double omega_per_s, double t_prime_s, double kappa,
                         double x_desired_m) {
  const double coth = 1.0 / std::tanh(omega_per_s * t_prime_s);
  return xs_m + vs_m_s / omega_per_s * coth + kappa * (x_desired_m - xs_m);
}

TvrPlanner::TvrPlanner(const TvrParams& params) : params_(params), omega_(0) {
  validate(params_);
  omega_ = std::sqrt(params_.gravity_m_s2 / params_.com_height_m);
}

TvrPlan TvrPlanner::plan(const TvrInput& in) const {
  TvrPlan out;
  const double t_s = std::max(in.time_to_switch_s, 0.0);
  switching_state(in, t_s, out);
  out.time_scale = speed_rule_scale(out.switching_com_velocity_m_s);
  out.time_to_switch_s = t_s * out.time_scale;
  if (out.time_scale != 1.0) switching_state(in, out.time_to_switch_s, out);  // once, not checked again
  for (int i = 0; i < 2; ++i)
    out.foothold_unclamped_m[i] = reversal_foothold(out.switching_com_m[i], out.switching_com_velocity_m_s[i], omega_,
                                                    params_.t_prime_s[i], params_.kappa[i], in.com_desired_m[i]);
  out.foothold_unclamped_m.y() += (in.swing == Side::Left ? 1.0 : -1.0) * lateral_width_offset_m();
  apply_step_limits(in, out);
  return out;
}

double TvrPlanner::lateral_width_offset_m() const {
  if (params_.lateral_width_m == 0.0) return 0.0;
  const double coth = 1.0 / std::tanh(omega_ * params_.t_prime_s.y());
  return 0.5 * params_.lateral_width_m * (1.0 - coth * std::tanh(0.5 * omega_ * params_.step_period_s));
}

void TvrPlanner::switching_state(const TvrInput& in, double t_s, TvrPlan& out) const {
  for (int i = 0; i < 2; ++i) {
    const LipmAxisState s = lipm_state_after(in.com_m[i], in.com_velocity_m_s[i], in.stance_foot_m[i], omega_, t_s);
    out.switching_com_m[i] = s.position_m;
    out.switching_com_velocity_m_s[i] = s.velocity_m_s;
  }
}

double TvrPlanner::speed_rule_scale(const Eigen::Vector2d& switching_velocity_m_s) const {
  const double fastest = switching_velocity_m_s.cwiseAbs().maxCoeff();
  const double slowest = switching_velocity_m_s.cwiseAbs().minCoeff();
  if (fastest > params_.switching_speed_max_m_s) return params_.fast_time_scale;
  if (slowest < params_.switching_speed_min_m_s) return params_.slow_time_scale;
  return 1.0;
}

void TvrPlanner::apply_step_limits(const TvrInput& in, TvrPlan& out) const {
  out.foothold_m = out.foothold_unclamped_m;
  const double dx = out.foothold_unclamped_m.x() - in.stance_foot_m.x();
  out.clamped_x = dx < params_.step_x_min_m || dx > params_.step_x_max_m;
  if (out.clamped_x)
    out.foothold_m.x() = in.stance_foot_m.x() + std::clamp(dx, params_.step_x_min_m, params_.step_x_max_m);
  // Lateral distance measured towards the swing side: +y for a left foot, −y for a right.
  const double side = in.swing == Side::Left ? 1.0 : -1.0;
  const double dy = side * (out.foothold_unclamped_m.y() - in.stance_foot_m.y());
  out.clamped_y = dy < params_.step_lateral_min_m || dy > params_.step_lateral_max_m;
  if (out.clamped_y)
    out.foothold_m.y() =
        in.stance_foot_m.y() + side * std::clamp(dy, params_.step_lateral_min_m, params_.step_lateral_max_m);
}

}  // namespace dmbd::wholebody
