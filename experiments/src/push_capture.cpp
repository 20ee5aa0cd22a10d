// Whether a push left the robot capturable (push_capture.hpp).
#include "push_capture.hpp"

#include <algorithm>
#include <cmath>

#include "dmbd/wholebody/capture.hpp"
#include "dmbd/wholebody/swing_reach.hpp"
#include "experiment_support.hpp"

namespace dmbd::experiments::detail {

namespace {

using wholebody::CaptureInterval;
using wholebody::Phase;
using wholebody::StepRange;
using control::BalanceSetup;

// The step about to land at a log sample: its stance foot, side, the time to its
// touch-down and whether its foothold is fixed (past the mid-swing replan).
struct PendingStep {
  double stance_x, stance_y;
  bool left_swings;
  double time_to_touch_down_s;
  bool fixed;
};

// How long the sample's phase has lasted (from the log: the first sample of the phase).
double time_in_phase(const std::vector<double>& t, const std::vector<double>& phase, std::size_t k) {
  std::size_t j = k;
  while (j > 0 && phase[j - 1] == phase[k]) --j;
  return t[k] - t[j];
}

PendingStep pending_step(const VariantResult& r, const BalanceSetup& b, std::size_t k, Phase phase, const std::string& file) {
  const auto& ph = b.phases;
  const double in = time_in_phase(r.log.time(), signal(r, b.name + ".phase", file), k);
  const bool left = signal(r, b.name + ".swing_side", file)[k] == 0;
  if (phase == Phase::Landing)  // the moving foot is down: the next step stands on it
    return {signal(r, b.name + ".swing_x", file)[k], signal(r, b.name + ".swing_y", file)[k], !left,
            std::max(0.0, ph.landing_s - in) + ph.double_support_s + ph.lift_s + ph.swing_s, false};
  double rest = ph.swing_s;
  if (phase == Phase::DoubleSupport) rest += ph.double_support_s + ph.lift_s;
  if (phase == Phase::Lift) rest += ph.lift_s;
  return {signal(r, b.name + ".stance_x", file)[k], signal(r, b.name + ".stance_y", file)[k], left,
          std::max(0.0, rest - in), phase == Phase::Swing && in >= 0.5 * ph.swing_s};
}

nlohmann::json pair(const CaptureInterval& c) { return nlohmann::json::array({c.lo_m, c.hi_m}); }

}  // namespace

double pendulum_omega(const control::BalanceSetup& b, double gravity_m_s2) { return std::sqrt(gravity_m_s2 / b.tvr.com_height_m); }

// The footholds the swing foot can land on (relative to the stance foot), per axis, from
// its logged position and velocity (the difference to the sample before) at sample k;
// its measured speed is held within the limit.
std::pair<wholebody::Reach, wholebody::Reach> reach_at(const VariantResult& r, const BalanceSetup& b, std::size_t k, const PendingStep& p,
                                                       const SwingLimits& lim, const std::string& file) {
  const auto& t = r.log.time();
  std::pair<wholebody::Reach, wholebody::Reach> out;
  const char* axes[] = {".swing_x", ".swing_y"};
  for (int a = 0; a < 2; ++a) {
    const auto& x = signal(r, b.name + axes[a], file);
    const double v = k > 0 ? (x[k] - x[k - 1]) / (t[k] - t[k - 1]) : 0.0;
    const double x0 = x[k] - (a == 0 ? p.stance_x : p.stance_y);
    const auto reach = wholebody::swing_reach(x0, std::clamp(v, -lim.speed_m_s, lim.speed_m_s), p.time_to_touch_down_s, lim.speed_m_s, lim.accel_m_s2);
    (a == 0 ? out.first : out.second) = reach;
  }
  return out;
}

// The step's range within the foot's reach; false when they do not meet.
bool within_reach(StepRange& step, const wholebody::Reach& reach) {
  step.min_m = std::max(step.min_m, reach.lo_m);
  step.max_m = std::min(step.max_m, reach.hi_m);
  return step.min_m <= step.max_m;
}

nlohmann::json push_capture(const VariantResult& r, const control::BalanceSetup& b, double gravity_m_s2, double end_s,
                            const std::string& file, const std::optional<SwingLimits>& limits) {
  const auto& t = r.log.time();
  const auto k = static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), end_s - 1e-9) - t.begin());
  if (k >= t.size()) return nullptr;
  const auto phase = static_cast<Phase>(std::lround(signal(r, b.name + ".phase", file)[k]));
  if (phase != Phase::DoubleSupport && phase != Phase::Lift && phase != Phase::Swing && phase != Phase::Landing) return nullptr;
  const PendingStep p = pending_step(r, b, k, phase, file);
  const double w = pendulum_omega(b, gravity_m_s2), T = b.phases.step_period_s();
  const double ex = signal(r, b.name + ".com_x", file)[k] + signal(r, b.name + ".com_vx", file)[k] / w - p.stance_x;
  const double ey = signal(r, b.name + ".com_y", file)[k] + signal(r, b.name + ".com_vy", file)[k] / w - p.stance_y;
  // The TVR's limits: forward the same every step; sideways towards the swinging side.
  const StepRange sx{b.tvr.step_x_min_m, b.tvr.step_x_max_m};
  const StepRange left{b.tvr.step_lateral_min_m, b.tvr.step_lateral_max_m}, right{-left.max_m, -left.min_m};
  const CaptureInterval next_x = wholebody::capture_intervals(w, T, {sx})[0];
  const CaptureInterval next_y = wholebody::capture_intervals(w, T, {p.left_swings ? left : right, p.left_swings ? right : left})[1];
  StepRange step_x = sx, step_y = p.left_swings ? left : right;
  nlohmann::json reach_json = nlohmann::json::object();
  bool reachable = true;
  if (p.fixed) {
    const double fx = signal(r, b.name + ".foothold_x", file)[k] - p.stance_x, fy = signal(r, b.name + ".foothold_y", file)[k] - p.stance_y;
    step_x = {fx, fx};
    step_y = {fy, fy};
  } else if (limits && phase == Phase::Swing) {  // the foot is in the air: where it can still land
    const auto [rx, ry] = reach_at(r, b, k, p, *limits, file);
    reach_json = {{"reach_x_m", nlohmann::json::array({rx.lo_m, rx.hi_m})}, {"reach_y_m", nlohmann::json::array({ry.lo_m, ry.hi_m})}};
    reachable = within_reach(step_x, rx) && within_reach(step_y, ry);
  }
  nlohmann::json out = {{"foothold_fixed", p.fixed}, {"time_to_touch_down_s", p.time_to_touch_down_s}, {"cp_offset_m", nlohmann::json::array({ex, ey})}};
  if (limits) out["reachable"] = reachable;
  out.update(reach_json);
  if (!reachable) {  // no foothold within the step limits can be reached: no interval
    out.update({{"capturable", false}, {"margin_m", nullptr}, {"interval_x_m", nullptr}, {"interval_y_m", nullptr}});
    return out;
  }
  const CaptureInterval ix = wholebody::capture_interval_before(w, p.time_to_touch_down_s, step_x, next_x);
  const CaptureInterval iy = wholebody::capture_interval_before(w, p.time_to_touch_down_s, step_y, next_y);
  const double margin = std::min({ex - ix.lo_m, ix.hi_m - ex, ey - iy.lo_m, iy.hi_m - ey});
  out.update({{"capturable", ix.contains(ex) && iy.contains(ey)}, {"margin_m", margin}, {"interval_x_m", pair(ix)}, {"interval_y_m", pair(iy)}});
  return out;
}

}  // namespace dmbd::experiments::detail
