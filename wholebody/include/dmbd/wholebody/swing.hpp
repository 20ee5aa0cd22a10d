#pragma once
// The swing foot's path: a clamped cubic B-spline per axis from the lift-off position to
// the landing target over the swing duration T, plus minimum-jerk offsets that move the
// target when the footstep is replanned during the swing (draco-facts.md "Swing").
//
// The spline: 4 uniform segments (knots 0, T/4, T/2, 3T/4, T; the ends repeated), 7
// control points per axis, solved from 7 conditions:
//   lift-off (t = 0):  p = lift-off, v = 0, a = 0
//   mid-swing (T/2):   horizontal p = half-way, vertical p = ½(z₀ + z_T) + mid_height_m
//   landing (t = T):   p = target, horizontal v = 0, vertical v = landing_vertical_velocity_m_s, a = 0
// Why cubic: the whole-body controller tracks the foot's position, velocity and
// acceleration, so the path must be C² (continuous acceleration, from rest at lift-off);
// a cubic B-spline is C² across its knots, which is all that is needed, with the fewest
// control points and a piecewise-linear acceleration. A quintic would add continuity
// of jerk and snap that nothing downstream uses. "Above the ground" is measured from the
// straight line between the lift-off and landing heights (both on the ground for
// stepping in place).
//
// Replan: at t_r the target moves by δ = new target − current target. The change is
// blended in as δ·s(τ), τ = (t − t_r)/(T − t_r), s = 10τ³ − 15τ⁴ + 6τ⁵ (minimum jerk
// from rest to rest), zero before t_r: its position, velocity and acceleration are 0 at
// t_r (p, v, a stay continuous there) and δ, 0, 0 at T (the foot lands on the new
// target with the planned landing velocity). Replans add up, so the path before every
// replan instant is kept; up to kMaxReplans per swing. T does not change with a replan.
//
// Horizontal ahead of vertical (horizontal_fraction f < 1; 1 by default, the authors'):
// the horizontal axes follow the same conditions over f T instead of T (mid-way at f T/2,
// on the target at rest from f T on), the height still over T; a replan's horizontal
// change then blends in by f T (by T when it comes later). The foot is then over its
// foothold before it comes down, wherever in the descent the ground is met.
//
// Times outside [0, T] are clamped to it (p, v, a are those at 0 or at T).
// start(), replan() and at() allocate nothing.
#include <array>

#include <Eigen/Core>

namespace dmbd::wholebody {

struct SwingParams {
  double mid_height_m = 0.11;                    // above the ground at T/2
  double landing_vertical_velocity_m_s = -0.5;  // ż at t = T (negative: downwards)
  double horizontal_fraction = 1.0;              // f in (0, 1]: x and y arrive at f T
};

struct SwingSample {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d acceleration_m_s2 = Eigen::Vector3d::Zero();
};

class SwingTrajectory {
 public:
  static constexpr int kMaxReplans = 4;

  // Throws InputError for a mid-height or landing velocity that is not finite or a
  // horizontal_fraction outside (0, 1]. Until
  // start(), the path is a 1 s swing from the origin back to it.
  explicit SwingTrajectory(const SwingParams& params = {});

  // A new swing (forgets earlier replans); throws InputError unless duration_s > 0.
  void start(const Eigen::Vector3d& lift_off_m, const Eigen::Vector3d& target_m, double duration_s);

  // p, v, a at t_s after lift-off (clamped to [0, T]).
  SwingSample at(double t_s) const;

  // Moves the landing point to new_target_m from t_s on (t_s < 0 counts as 0). False,
  // changing nothing, when t_s ≥ T (no time left to blend) or kMaxReplans were made.
  bool replan(double t_s, const Eigen::Vector3d& new_target_m);

  const Eigen::Vector3d& lift_off_m() const { return lift_off_m_; }
  const Eigen::Vector3d& target_m() const { return target_m_; }  // after the replans
  double duration_s() const { return duration_s_; }
  int replans() const { return replans_; }

 private:
  static constexpr int kControlPoints = 7;
  using Controls = std::array<Eigen::Vector3d, kControlPoints>;
  struct Offset {  // one replan's minimum-jerk blend
    double start_s = 0.0;
    Eigen::Vector3d change_m = Eigen::Vector3d::Zero();
  };

  void solve_control_points(const Eigen::Vector3d& target_m);
  static void solve_axes(const Eigen::Vector3d& lift_off_m, const Eigen::Vector3d& target_m, const SwingParams& params,
                         double duration_s, Controls& position, Controls& velocity, Controls& acceleration);
  void add_offset(const Offset& o, double t_s, SwingSample& s) const;
  double horizontal_s() const { return params_.horizontal_fraction * duration_s_; }

  SwingParams params_;
  Eigen::Vector3d lift_off_m_ = Eigen::Vector3d::Zero(), target_m_ = Eigen::Vector3d::Zero();
  double duration_s_ = 1.0;
  Controls position_{}, velocity_{}, acceleration_{};  // splines of degree 3, 2 and 1 (over T)
  Controls position_h_{}, velocity_h_{}, acceleration_h_{};  // the same over f T (x and y used)
  std::array<Offset, kMaxReplans> offsets_{};
  int replans_ = 0;
};

}  // namespace dmbd::wholebody
