// The swing foot's cubic B-spline and its minimum-jerk replan offsets (swing.hpp).
//
// The spline is evaluated by de Boor's algorithm; its velocity and acceleration are the
// B-splines of degree 2 and 1 whose control points are the differences
//   Q_i = d (P_{i+1} − P_i) / (u_{i+d+1} − u_{i+1})   (degree d, knots u),
// formed once per start(). The 7 × 7 conditions matrix is built by applying each
// condition to each basis spline (one control point 1, the others 0) and solved by a
// fixed-size LU: nothing is allocated.
#include "dmbd/wholebody/swing.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>

#include "dmbd/base/error.hpp"

namespace dmbd::wholebody {

namespace {

constexpr int kSegments = 4;
constexpr int kDegree = 3;
constexpr int kConditions = 7;  // p, v, a at 0; p at T/2; p, v, a at T
using Controls = std::array<Eigen::Vector3d, kSegments + kDegree>;

// The clamped uniform knot vector of a spline of `degree`: u_k = clamp((k − degree) h, 0, T).
double knot(int degree, int k, double h, double duration) { return std::clamp((k - degree) * h, 0.0, duration); }

// The spline of `degree` (control points c[0 .. kSegments + degree − 1]) at t ∈ [0, T].
Eigen::Vector3d de_boor(const Controls& c, int degree, double t, double duration) {
  const double h = duration / kSegments;
  const int span = degree + std::clamp(static_cast<int>(t / h), 0, kSegments - 1);  // u_span ≤ t < u_span+1
  std::array<Eigen::Vector3d, kDegree + 1> d;
  for (int j = 0; j <= degree; ++j) d[j] = c[j + span - degree];
  for (int r = 1; r <= degree; ++r) {
    for (int j = degree; j >= r; --j) {
      const int i = j + span - degree;
      const double lo = knot(degree, i, h, duration), hi = knot(degree, i + degree + 1 - r, h, duration);
      const double alpha = (t - lo) / (hi - lo);
      d[j] = (1.0 - alpha) * d[j - 1] + alpha * d[j];
    }
  }
  return d[degree];
}

// The control points of the derivative of the spline of `degree` with control points c.
Controls derivative(const Controls& c, int degree, double duration) {
  const double h = duration / kSegments;
  Controls q{};
  for (auto& point : q) point.setZero();  // the last one is unused
  for (int i = 0; i + 1 < kSegments + degree; ++i)
    q[i] = degree * (c[i + 1] - c[i]) / (knot(degree, i + degree + 1, h, duration) - knot(degree, i + 1, h, duration));
  return q;
}

// The conditions (rows, in the order of kConditions) applied to the spline of control points c.
Eigen::Matrix<double, kConditions, 3> conditions(const Controls& c, double duration) {
  const Controls v = derivative(c, kDegree, duration), a = derivative(v, kDegree - 1, duration);
  Eigen::Matrix<double, kConditions, 3> m;
  m.row(0) = de_boor(c, kDegree, 0.0, duration);
  m.row(1) = de_boor(v, kDegree - 1, 0.0, duration);
  m.row(2) = de_boor(a, kDegree - 2, 0.0, duration);
  m.row(3) = de_boor(c, kDegree, 0.5 * duration, duration);
  m.row(4) = de_boor(c, kDegree, duration, duration);
  m.row(5) = de_boor(v, kDegree - 1, duration, duration);
  m.row(6) = de_boor(a, kDegree - 2, duration, duration);
  return m;
}

// Minimum jerk from rest to rest: s(τ) = 10τ³ − 15τ⁴ + 6τ⁵ and its first two derivatives.
Eigen::Vector3d minimum_jerk(double tau) {
  const double u = 1.0 - tau;
  return {tau * tau * tau * (10.0 - 15.0 * tau + 6.0 * tau * tau), 30.0 * tau * tau * u * u,
          60.0 * tau * u * (1.0 - 2.0 * tau)};
}

}  // namespace

SwingTrajectory::SwingTrajectory(const SwingParams& params) : params_(params) {
  if (!std::isfinite(params_.mid_height_m) || !std::isfinite(params_.landing_vertical_velocity_m_s))
    throw InputError("swing trajectory: mid_height_m and landing_vertical_velocity_m_s must be finite");
  if (!(params_.horizontal_fraction > 0.0 && params_.horizontal_fraction <= 1.0))
    throw InputError("swing trajectory: horizontal_fraction must be in (0, 1]");
  start(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 1.0);
}

void SwingTrajectory::start(const Eigen::Vector3d& lift_off_m, const Eigen::Vector3d& target_m, double duration_s) {
  if (!(std::isfinite(duration_s) && duration_s > 0))
    throw InputError("swing trajectory: the swing duration must be positive");
  lift_off_m_ = lift_off_m;
  target_m_ = target_m;
  duration_s_ = duration_s;
  replans_ = 0;
  solve_control_points(target_m);
}

void SwingTrajectory::solve_control_points(const Eigen::Vector3d& target_m) {
  solve_axes(lift_off_m_, target_m, params_, duration_s_, position_, velocity_, acceleration_);
  solve_axes(lift_off_m_, target_m, params_, horizontal_s(), position_h_, velocity_h_, acceleration_h_);
}

void SwingTrajectory::solve_axes(const Eigen::Vector3d& lift_off_m, const Eigen::Vector3d& target_m, const SwingParams& params,
                                 double duration_s, Controls& position, Controls& velocity, Controls& acceleration) {
  Eigen::Matrix<double, kConditions, kControlPoints> m;
  for (int j = 0; j < kControlPoints; ++j) {
    Controls basis{};
    for (auto& c : basis) c.setZero();
    basis[j].setOnes();
    m.col(j) = conditions(basis, duration_s).col(0);
  }
  Eigen::Vector3d mid = 0.5 * (lift_off_m + target_m);
  mid.z() += params.mid_height_m;
  Eigen::Matrix<double, kConditions, 3> rhs = Eigen::Matrix<double, kConditions, 3>::Zero();
  rhs.row(0) = lift_off_m;
  rhs.row(3) = mid;
  rhs.row(4) = target_m;
  rhs(5, 2) = params.landing_vertical_velocity_m_s;
  const Eigen::Matrix<double, kControlPoints, 3> p = m.partialPivLu().solve(rhs);
  for (int j = 0; j < kControlPoints; ++j) position[j] = p.row(j);
  velocity = derivative(position, kDegree, duration_s);
  acceleration = derivative(velocity, kDegree - 1, duration_s);
}

SwingSample SwingTrajectory::at(double t_s) const {
  const double t = std::clamp(t_s, 0.0, duration_s_);
  SwingSample s;
  s.position_m = de_boor(position_, kDegree, t, duration_s_);
  s.velocity_m_s = de_boor(velocity_, kDegree - 1, t, duration_s_);
  s.acceleration_m_s2 = de_boor(acceleration_, kDegree - 2, t, duration_s_);
  if (params_.horizontal_fraction < 1.0) {
    const double th = horizontal_s(), t_h = std::min(t, th);  // at rest on the target after f T
    s.position_m.head<2>() = de_boor(position_h_, kDegree, t_h, th).head<2>();
    s.velocity_m_s.head<2>() = de_boor(velocity_h_, kDegree - 1, t_h, th).head<2>();
    s.acceleration_m_s2.head<2>() = de_boor(acceleration_h_, kDegree - 2, t_h, th).head<2>();
  }
  for (int k = 0; k < replans_; ++k) add_offset(offsets_[k], t, s);
  return s;
}

// The horizontal part of a change blends in by f T when the replan comes before it, the
// vertical part (and a later horizontal one) by T.
void SwingTrajectory::add_offset(const Offset& o, double t_s, SwingSample& s) const {
  if (t_s <= o.start_s) return;
  const double ends[2] = {o.start_s < horizontal_s() ? horizontal_s() : duration_s_, duration_s_};
  for (int part = 0; part < 2; ++part) {
    const double blend_s = ends[part] - o.start_s;
    const Eigen::Vector3d shape = minimum_jerk(std::min((t_s - o.start_s) / blend_s, 1.0));
    const Eigen::Vector3d change = part == 0 ? Eigen::Vector3d(o.change_m.x(), o.change_m.y(), 0.0)
                                             : Eigen::Vector3d(0.0, 0.0, o.change_m.z());
    s.position_m += shape[0] * change;
    s.velocity_m_s += shape[1] / blend_s * change;
    s.acceleration_m_s2 += shape[2] / (blend_s * blend_s) * change;
  }
}

bool SwingTrajectory::replan(double t_s, const Eigen::Vector3d& new_target_m) {
  if (replans_ == kMaxReplans || !(t_s < duration_s_)) return false;
  offsets_[replans_++] = {std::max(t_s, 0.0), new_target_m - target_m_};
  target_m_ = new_target_m;
  return true;
}

}  // namespace dmbd::wholebody
