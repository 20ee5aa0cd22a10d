#pragma once
// Capturability of the linear inverted pendulum with stepping (Koolen, de Boer, Rebula,
// Goswami, Pratt, "Capturability-based analysis and control of legged locomotion, part
// 1", IJRR 2012), per horizontal axis, for a robot that steps at a fixed period: how far
// the capture point may be from the stance foot for some sequence of steps within the
// step limits to stop the robot from falling. It answers whether a push can be survived
// at all by any stepping within a planner's limits and timing, whatever the controller.
//
// Per axis, with the capture point ξ = x + ẋ/ω and the centre of pressure c,
//   ξ̇ = ω (ξ − c),
// and c within ±r of the stance foot p (r = 0: a point foot). The offset e = ξ − p
// grows as (|e| − r) e^{ωt} once the CoP sits at the edge nearest ξ (the best it can do).
// A step every T seconds puts the next foot at p′ = p + s with s in the step's range
// [s_min, s_max]; the offset becomes e′ = e(T) − s.
//
// The ∞-step capture interval of a step is the set of offsets at its start (a
// touch-down: the step about to be taken is free) from which some sequence of steps keeps
// ξ bounded for ever. With β = e^{−ωT} and the next step's interval [lo′, hi′]:
//   lo = −r + (lo′ + s_min + r) β,   hi = r + (hi′ + s_max − r) β
// (with r = 0 and one range for every step, hi = s_max β / (1 − β): Koolen's d_∞).
// For a cycle of step ranges (a biped's lateral steps alternate sides) the recursion
// runs around the cycle to its fixed point; it contracts by β per step.
//
// A constant horizontal force F on a mass m for τ seconds moves the capture point, at
// the force's end, by  F / (m ω²) · (e^{ωτ} − 1)  (ξ̇ = ω(ξ − c) + F/(mω)).
#include <vector>

namespace dmbd::wholebody {

struct StepRange {
  double min_m = 0.0, max_m = 0.0;  // next foot − stance foot along the axis
};

struct CaptureInterval {
  double lo_m = 0.0, hi_m = 0.0;  // capture point − stance foot along the axis
  bool contains(double offset_m) const { return offset_m >= lo_m && offset_m <= hi_m; }
};

// The ∞-step capture interval at the start of each step of the cycle (cycle[k] is the
// range of the step that starts there; after the last comes the first again), stepping
// every step_time_s. Throws InputError for ω or T not positive, r negative, an empty
// cycle or a range with min > max.
std::vector<CaptureInterval> capture_intervals(double omega_per_s, double step_time_s,
                                               const std::vector<StepRange>& cycle, double cop_range_m = 0.0);

// The interval of offsets from which a step that lands t_s from now, within `step`, and
// then the steps whose interval at that touch-down is `next`, capture the robot (the
// recursion above over t_s instead of T). With step = {s, s}, a foothold already fixed.
CaptureInterval capture_interval_before(double omega_per_s, double t_s, const StepRange& step,
                                        const CaptureInterval& next, double cop_range_m = 0.0);

// The capture point's displacement at the end of a constant force (N) held for
// duration_s on mass_kg, relative to the same motion without it (m).
double push_capture_point_shift(double force_N, double duration_s, double mass_kg, double omega_per_s);

}  // namespace dmbd::wholebody
