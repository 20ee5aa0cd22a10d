#pragma once
// Where a swinging foot can still land, per horizontal axis: from its position x0 and
// velocity v0 (|v0| <= v_max), in the time t left before touch-down, with its speed
// within v_max and its acceleration within a_max, arriving at rest (the swing's
// horizontal motion ends still, as the balancing controller's swing spline does). A push
// that moves the capture point where only a foothold out of this reach would catch it is
// not captured whatever the planner asks.
//
// The farthest forward landing (time-optimal control of a double integrator): accelerate
// at a_max to the peak speed v_p = min(v_max, (a_max t + v0) / 2), hold it, brake at a_max
// to rest at t:
//   D(v0) = (v0 + v_p)/2 (v_p − v0)/a_max + v_p (t − (2 v_p − v0)/a_max) + v_p²/(2 a_max),
// and the farthest backward is −D(−v0). Stopping at all needs |v0| <= a_max t; a foot
// moving faster than that lands where full braking takes it, x0 + v0 t − sgn(v0) a_max t²/2
// (the reach is that one point).
namespace dmbd::wholebody {

struct Reach {
  double lo_m = 0.0, hi_m = 0.0;  // the landing positions the foot can reach, same frame as x0
};

// Throws InputError for v_max or a_max not positive, t negative, or |v0| > v_max.
Reach swing_reach(double x0_m, double v0_m_s, double t_s, double v_max_m_s, double a_max_m_s2);

}  // namespace dmbd::wholebody
