#pragma once
// Whether a push left the balancing robot capturable at all (balance experiment): the
// linear inverted pendulum's capture analysis (wholebody/capture.hpp) at the end of the
// push, from the logged CoM state, stance foot and phase, with the controller's own step
// timing (the phase machine's nominal durations), step limits (the TVR's) and pendulum
// height, point feet, and the step in progress free until its mid-swing replan (then
// fixed at its planned foothold). False: no sequence of steps within those limits and
// timing could have kept this pendulum up, whatever the controller did next.
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "dmbd/control/balance_controller.hpp"
#include "dmbd/sim/run_result.hpp"

namespace dmbd::experiments::detail {

// The swing foot's limits (the balance experiment's swing_speed_max_m_s and
// swing_accel_max_m_s2): with them, a free foothold counts only where the swinging foot
// can still land in the time left (wholebody/swing_reach.hpp).
struct SwingLimits {
  double speed_m_s = 0, accel_m_s2 = 0;
};

// At the first log sample at or after end_s; null when there is none or the robot was
// not stepping then. Fields: capturable, margin_m (the offsets' least distance inside
// their intervals; negative outside), foothold_fixed, time_to_touch_down_s,
// cp_offset_m [x, y] (capture point − stance foot), interval_x_m and interval_y_m
// [lo, hi] (the capturable offsets); with `reach`, also reach_x_m and reach_y_m (the
// footholds the swing foot can still land on, relative to the stance foot, while the
// step is free) and reachable (some foothold within the step limits is; false: not
// capturable). Throws InputError (naming file) for a missing signal.
// The pendulum's ω uses gravity_m_s2, the scenario's (as the controller's planner does).
nlohmann::json push_capture(const sim::VariantResult& r, const control::BalanceSetup& b, double gravity_m_s2, double end_s,
                            const std::string& file, const std::optional<SwingLimits>& reach = std::nullopt);

// The pendulum's ω = √(g / h) of a balance setup under gravity g.
double pendulum_omega(const control::BalanceSetup& b, double gravity_m_s2);

}  // namespace dmbd::experiments::detail
