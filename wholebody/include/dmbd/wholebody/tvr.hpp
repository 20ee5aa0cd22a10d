#pragma once
// The time-to-velocity-reversal (TVR) footstep planner on the linear inverted pendulum
// (the paper's planner; Kim et al., "Dynamic locomotion for passive-ankle biped robots
// and humanoids using whole-body locomotion control", IJRR 2020). Per horizontal axis
// the CoM obeys ẍ = ω² (x − p), ω = √(g/h), over the stance foot at p:
//
//   switching state after T:  A = ½[(x₀−p) + ẋ₀/ω],  B = ½[(x₀−p) − ẋ₀/ω],
//                             x_s = A e^{ωT} + B e^{−ωT} + p,  ẋ_s = ω (A e^{ωT} − B e^{−ωT})
//   next foothold:            p′ = x_s + (ẋ_s/ω) coth(ω t′) + κ (x_des − x_s)
//
// With κ = 0 the CoM, switched onto p′ with (x_s, ẋ_s), stops t′ after touch-down
// (ẋ(t) = ẋ_s [cosh ωt − coth(ωt′) sinh ωt]); κ < 0 moves the foot away from x_des so
// that the CoM, when it turns, is moving toward x_des.
//
// Step limits, relative to the stance foot in world axes: forward x ∈ [−0.4, 0.4] m;
// lateral 0.20–0.55 m towards the swing foot's side (a left foot lands at
// y_stance + [0.20, 0.55], a right foot at y_stance − [0.55, 0.20]).
//
// The switching-speed rule (the authors' code, draco-facts.md "TVR"): if |ẋ_s| of
// either axis is above switching_speed_max_m_s (1.3 m/s) the time to switching is
// scaled by fast_time_scale (0.9); otherwise, if |ẋ_s| of either axis is below
// switching_speed_min_m_s (0 m/s, so never by default) it is scaled by
// slow_time_scale (1.1). The switching state is then recomputed with the scaled time,
// once, without checking again. "Too fast" wins when the axes disagree. The scaled
// time is returned (TvrPlan::time_to_switch_s); the authors moved the swing phase's end
// by the difference, which is the caller's to do. Set switching_speed_max_m_s to
// infinity to turn the rule off.
//
// The caller chooses the CoM state (the authors used the torso position + (0.06, 0) m
// with its measured velocity) and calls plan() at lift-off and once more at mid-swing,
// with the time left until touch-down. The planner holds no state; plan() allocates
// nothing.
#include <Eigen/Core>

#include "dmbd/wholebody/phase_machine.hpp"

namespace dmbd::wholebody {

struct TvrParams {
  double com_height_m = 1.0;
  double gravity_m_s2 = 9.81;
  Eigen::Vector2d t_prime_s{0.21, 0.20};  // time to velocity reversal after touch-down (x, y)
  Eigen::Vector2d kappa{-0.08, -0.13};    // gain on x_des − x_s (x, y), dimensionless
  double step_x_min_m = -0.4, step_x_max_m = 0.4;              // p′x − stance x
  double step_lateral_min_m = 0.20, step_lateral_max_m = 0.55;  // |p′y − stance y|, swing side
  double switching_speed_min_m_s = 0.0, switching_speed_max_m_s = 1.3;
  double slow_time_scale = 1.1, fast_time_scale = 0.9;
  // Stepping in place with a lateral width w (0: none, the authors' planner). The TVR
  // rule alone holds no width: with t′_y = T/2 (T the step's period) every width is a
  // fixed point (a neutral mode that wanders), with t′_y > T/2 the width shrinks to the
  // step limit's minimum, which then carries the robot sideways. The pendulum's
  // period-2 orbit of width w (feet at ±w/2, the CoM crossing the middle at
  // (w/2) ω tanh(ωT/2) at each switch) is a fixed point of the rule when the foothold
  // gains an offset towards the swing side of
  //   d = (w/2) [1 − coth(ω t′_y) tanh(ωT/2)];
  // with t′_y = T the step-to-step map of (x_s − p, ẋ_s) is deadbeat (both eigenvalues
  // 0: H-LIP's deadbeat gain, Xiong and Ames 2021) and κ_y pulls the orbit's middle to
  // x_des.
  double lateral_width_m = 0.0;
  double step_period_s = 0.38;  // T, touch-down to touch-down (only with lateral_width_m)
};

// The foot that swings (and lands at the planned foothold) is a Side of the phase
// machine (phase_machine.hpp).

struct TvrInput {
  Eigen::Vector2d com_m = Eigen::Vector2d::Zero();          // world xy
  Eigen::Vector2d com_velocity_m_s = Eigen::Vector2d::Zero();
  Eigen::Vector2d stance_foot_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d com_desired_m = Eigen::Vector2d::Zero();  // x_des
  Side swing = Side::Left;
  double time_to_switch_s = 0.0;                             // T, from now to touch-down
};

struct TvrPlan {
  Eigen::Vector2d foothold_m = Eigen::Vector2d::Zero();            // p′ after the step limits
  Eigen::Vector2d foothold_unclamped_m = Eigen::Vector2d::Zero();  // p′ before them
  Eigen::Vector2d switching_com_m = Eigen::Vector2d::Zero();       // x_s at the time below
  Eigen::Vector2d switching_com_velocity_m_s = Eigen::Vector2d::Zero();
  double time_to_switch_s = 0.0;  // T after the switching-speed rule
  double time_scale = 1.0;        // 1, slow_time_scale or fast_time_scale
  bool clamped_x = false, clamped_y = false;
};

// The CoM of the LIPM, per axis.
struct LipmAxisState {
  double position_m = 0.0;
  double velocity_m_s = 0.0;
};

// The closed form: the state t_s after (x0, v0) over a foot at foot_m.
LipmAxisState lipm_state_after(double x0_m, double v0_m_s, double foot_m, double omega_per_s, double t_s);

// p′ = x_s + (ẋ_s/ω) coth(ω t′) + κ (x_des − x_s), no limits.
double reversal_foothold(double xs_m, double vs_m_s, double omega_per_s, double t_prime_s, double kappa,
                         double x_desired_m);

class TvrPlanner {
 public:
  // Throws InputError naming the first parameter out of its range.
  explicit TvrPlanner(const TvrParams& params = {});

  // Once per replan (a negative time to switching counts as 0).
  TvrPlan plan(const TvrInput& in) const;

  double omega_per_s() const { return omega_; }
  const TvrParams& params() const { return params_; }

 private:
  void switching_state(const TvrInput& in, double t_s, TvrPlan& out) const;
  double speed_rule_scale(const Eigen::Vector2d& switching_velocity_m_s) const;
  void apply_step_limits(const TvrInput& in, TvrPlan& out) const;
  double lateral_width_offset_m() const;  // d above, towards the swing side

  TvrParams params_;
  double omega_;
};

}  // namespace dmbd::wholebody
