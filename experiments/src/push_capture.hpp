#pragma once
// Whether a push left the balancing robot capturable at all (balance experiment): the
// linear inverted pendulum's capture analysis (wholebody/capture.hpp) at the end of the
// push, from the logged CoM state, stance foot and phase, with the controller's own step
// timing (the phase machine's nominal durations), step limits (the TVR's) and pendulum
// height, point feet, and the step in progress free until its mid-swing replan (then
// fixed at its planned foothold). False: no sequence of steps within those limits and
// timing could have kept this pendulum up, whatever the controller did next.
#include <string>

#include <nlohmann/json.hpp>

#include "dmbd/control/balance_controller.hpp"
#include "dmbd/sim/run_result.hpp"

namespace dmbd::experiments::detail {

// At the first log sample at or after end_s; null when there is none or the robot was
// not stepping then. Fields: capturable, margin_m (the offsets' least distance inside
// their intervals; negative outside), foothold_fixed, time_to_touch_down_s,
// cp_offset_m [x, y] (capture point − stance foot), interval_x_m and interval_y_m
// [lo, hi] (the capturable offsets). Throws InputError (naming file) for a missing signal.
nlohmann::json push_capture(const sim::VariantResult& r, const control::BalanceSetup& b, double end_s, const std::string& file);

// The pendulum's ω = √(g / h) and step period of a balance setup.
double pendulum_omega(const control::BalanceSetup& b);
double step_period_s(const control::BalanceSetup& b);

}  // namespace dmbd::experiments::detail
