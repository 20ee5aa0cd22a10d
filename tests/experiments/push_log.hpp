#pragma once
// A synthetic balancing log whose phases follow the phase machine's default durations
// (double support 0–0.01 s, lift to 0.04 s, swing to 0.37 s, the left foot swinging from
// the right foot at the origin), with capture intervals worked out by hand (Koolen's d_∞
// for the sagittal steps, the alternating lateral steps solved in closed form),
// independently of wholebody/capture.cpp; shared by the push-capture and push-map tests.
#include <cmath>
#include <string>
#include <vector>

#include "dmbd/sim/run_result.hpp"

namespace push_log {

constexpr double kHeight = 0.78, kG = 9.81, kMass = 37.0;
const double kOmega = std::sqrt(kG / kHeight);
constexpr double kPeriod = 0.01 + 0.03 + 0.33 + 0.01;  // the phase machine's defaults
constexpr double kFootholdX = 0.12, kFootholdY = 0.25;  // the swing's plan (stance at 0)

struct Interval {
  double lo, hi;
};

// Before the left foot's touch-down, t from now, its step within `x`/`y` (ranges).
inline Interval sagittal(double t, double step_min, double step_max) {
  const double b = std::exp(-kOmega * kPeriod), d = 0.4 * b / (1 - b);
  return {(-d + step_min) * std::exp(-kOmega * t), (d + step_max) * std::exp(-kOmega * t)};
}
inline Interval lateral(double t, double step_min, double step_max) {
  const double b = std::exp(-kOmega * kPeriod);
  const double hi_l = (0.55 * b - 0.20 * b * b) / (1 - b * b), lo_l = (0.20 * b - 0.55 * b * b) / (1 - b * b);
  const double hi_r = (hi_l - 0.20) * b, lo_r = (lo_l - 0.55) * b;  // the right foot's step follows
  return {(lo_r + step_min) * std::exp(-kOmega * t), (hi_r + step_max) * std::exp(-kOmega * t)};
}

// Push ends: A at 5 ms (double support, foothold free, 0.365 s to touch-down), B at
// 0.30 s (0.26 s into the swing: past the mid-swing replan, foothold fixed, 0.07 s left).
constexpr double kEndA = 0.005, kEndB = 0.300;
const Interval kAx = sagittal(0.365, -0.4, 0.4), kAy = lateral(0.365, 0.20, 0.55);
const Interval kBx = sagittal(0.07, kFootholdX, kFootholdX), kBy = lateral(0.07, kFootholdY, kFootholdY);

// ξ − stance at A: 1 mm inside x's interval (outside when `outside_a`); at B 1 mm beyond
// its top. y mid-way in its interval at both.
inline dmbd::sim::VariantResult log(bool outside_a, double swing_y = 0.25) {
  dmbd::sim::VariantResult r;
  r.name = "v";
  r.truth["total_mass_kg"] = kMass;
  const std::vector<std::string> cols = {"base.z", "base.tilt", "balance.phase", "balance.swing_side", "balance.touch_downs",
                                         "balance.landings", "balance.qp_failures", "balance.com_x", "balance.com_y", "balance.com_vx",
                                         "balance.com_vy", "balance.stance_x", "balance.stance_y", "balance.swing_x", "balance.swing_y",
                                         "balance.foothold_x", "balance.foothold_y", "balance.landed_x", "balance.landed_y",
                                         "balance.planned_x", "balance.planned_y", "balance.step"};
  for (const auto& c : cols) r.log.add_column(c, "");
  auto set = [&](const std::string& c, double v) { r.log.set(r.log.find(c), v); };
  for (int k = 0; k <= 600; ++k) {
    const double t = k / 1000.0;
    r.log.begin_row(t);
    for (const auto& c : cols) set(c, 0.0);
    set("base.z", 0.9);
    set("balance.phase", t < 0.01 - 1e-9 ? 2 : t < 0.04 - 1e-9 ? 3 : t < 0.37 - 1e-9 ? 4 : 5);  // DS, lift, swing, landing
    set("balance.swing_x", -0.05);
    set("balance.swing_y", swing_y);
    set("balance.foothold_x", kFootholdX);
    set("balance.foothold_y", kFootholdY);
    // The capture point ξ = com + v/ω: the CoM at 0.02 m, its velocity making ξ the target.
    const bool at_b = t > 0.1;
    const double ex = at_b ? kBx.hi + 1e-3 : (outside_a ? kAx.hi + 1e-3 : kAx.hi - 1e-3);
    const double ey = at_b ? 0.5 * (kBy.lo + kBy.hi) : 0.5 * (kAy.lo + kAy.hi);
    set("balance.com_x", 0.02);
    set("balance.com_vx", (ex - 0.02) * kOmega);
    set("balance.com_y", 0.02);
    set("balance.com_vy", (ey - 0.02) * kOmega);
  }
  return r;
}

}  // namespace push_log
