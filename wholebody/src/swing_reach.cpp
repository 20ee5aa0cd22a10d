// Where a swinging foot can still land (swing_reach.hpp).
#include "dmbd/wholebody/swing_reach.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "dmbd/base/error.hpp"

namespace dmbd::wholebody {

namespace {

// The farthest displacement in the +x direction, arriving at rest (|v0| <= a t).
double farthest(double v0, double t, double v_max, double a_max) {
  const double vp = std::min(v_max, 0.5 * (a_max * t + v0));
  const double t_up = (vp - v0) / a_max, t_down = vp / a_max;
  return 0.5 * (v0 + vp) * t_up + vp * (t - t_up - t_down) + 0.5 * vp * t_down;
}

}  // namespace

Reach swing_reach(double x0_m, double v0_m_s, double t_s, double v_max_m_s, double a_max_m_s2) {
  if (!(v_max_m_s > 0.0) || !(a_max_m_s2 > 0.0))
    throw InputError("swing reach: the swing foot's speed and acceleration limits must be positive");
  if (!(t_s >= 0.0)) throw InputError("swing reach: the time left must not be negative");
  if (!(std::abs(v0_m_s) <= v_max_m_s)) throw InputError("swing reach: the swing foot's speed is beyond its limit");
  if (std::abs(v0_m_s) > a_max_m_s2 * t_s) {  // it cannot stop in time: full braking
    const double x = x0_m + v0_m_s * t_s - std::copysign(0.5 * a_max_m_s2 * t_s * t_s, v0_m_s);
    return {x, x};
  }
  return {x0_m - farthest(-v0_m_s, t_s, v_max_m_s, a_max_m_s2), x0_m + farthest(v0_m_s, t_s, v_max_m_s, a_max_m_s2)};
}

}  // namespace dmbd::wholebody
