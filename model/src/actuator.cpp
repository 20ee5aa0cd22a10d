// Actuators without a multibody engine: the VLCA's two-pivot linkage, its firmware-style
// lookup table (natural cubic spline of N_l(q)), and ActuatorParams' transmission (the
// linkage or a gear). The actuator file is read in actuator_file.cpp.
#include "dmbd/model/actuator.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "dmbd/model/error.hpp"

namespace dmbd::model {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

// ---- LinkageGeometry ------------------------------------------------------------------

double LinkageGeometry::length_m(double q) const { return at(q).length_m; }
double LinkageGeometry::moment_arm_m(double q) const { return at(q).moment_arm_m; }
double LinkageGeometry::dmoment_arm_dq_m(double q) const { return at(q).dmoment_arm_dq_m; }
double LinkageGeometry::N_l(double q) const { return 1.0 / at(q).moment_arm_m; }

// One sine and one cosine of gamma for all three (the plant and the controllers want
// them together, at every step, for every actuator).
LinkagePoint LinkageGeometry::at(double q) const {
  const double g = gamma0_rad + sign * q;
  const double sg = std::sin(g), cg = std::cos(g);
  const double x = std::sqrt(a_m * a_m + b_m * b_m - 2.0 * a_m * b_m * cg);
  const double s = a_m * b_m * sg;
  // d/dq (sign ab sin g / x) with dg/dq = sign, dx/dq = sign ab sin g / x; sign^2 = 1:
  //   ab cos g / x - (ab sin g)^2 / x^3.
  return {x, sign * s / x, a_m * b_m * cg / x - s * s / (x * x * x)};
}

// The law of cosines solved for gamma: cos gamma = (a^2 + b^2 - x^2) / (2 a b), on the
// branch (+-acos + 2 pi k) nearest the guess's gamma, the one Newton's method from the
// guess would reach while the moment arm keeps its sign. A length out of the linkage's
// reach gives the nearest end (gamma = 0 or pi).
double LinkageGeometry::angle_for_length_change(double dx, double guess) const {
  constexpr double kTwoPi = 2.0 * kPi;
  const double x = length_m(0.0) + dx;
  const double c = std::clamp((a_m * a_m + b_m * b_m - x * x) / (2.0 * a_m * b_m), -1.0, 1.0);
  const double g0 = std::acos(c), guess_g = gamma0_rad + sign * guess;
  const double g_plus = g0 + kTwoPi * std::round((guess_g - g0) / kTwoPi);
  const double g_minus = -g0 + kTwoPi * std::round((guess_g + g0) / kTwoPi);
  const double g = std::abs(g_plus - guess_g) <= std::abs(g_minus - guess_g) ? g_plus : g_minus;
  return sign * (g - gamma0_rad);
}

// ---- LinkageTable ---------------------------------------------------------------------

LinkageTable::LinkageTable(const LinkageGeometry& g, double q_lo, double q_hi, int samples) {
  if (samples < 2) throw ModelError("linkage table: needs at least 2 samples, got " + std::to_string(samples));
  if (!(q_hi > q_lo) || !std::isfinite(q_lo) || !std::isfinite(q_hi))
    throw ModelError("linkage table: needs q_hi > q_lo, got [" + std::to_string(q_lo) + ", " + std::to_string(q_hi) +
                     "]");
  if (!(g.a_m > 0) || !(g.b_m > 0) || !(g.sign == 1.0 || g.sign == -1.0))
    throw ModelError("linkage table: needs a_m > 0, b_m > 0 and sign +1 or -1");
  // The moment arm vanishes where gamma is a multiple of pi (the pivots and the joint axis
  // in line): the range must not reach one.
  const double g_a = g.gamma0_rad + g.sign * q_lo, g_b = g.gamma0_rad + g.sign * q_hi;
  const double g_min = std::min(g_a, g_b), g_max = std::max(g_a, g_b);
  const double k = std::floor(g_min / kPi);
  if (!(g_min > k * kPi) || !(g_max < (k + 1) * kPi))
    throw ModelError("linkage table: the linkage is singular over [" + std::to_string(q_lo) + ", " +
                     std::to_string(q_hi) + "] rad (gamma = gamma0 + sign q reaches a multiple of pi)");
  q_lo_ = q_lo;
  q_hi_ = q_hi;
  const int n = samples;
  h_ = (q_hi - q_lo) / (n - 1);
  n_.resize(n);
  for (int i = 0; i < n; ++i) n_[i] = g.N_l(i == n - 1 ? q_hi : q_lo + i * h_);
  // Natural spline: m_0 = m_{n-1} = 0 and, for the interior,
  //   m_{i-1} + 4 m_i + m_{i+1} = 6 (y_{i+1} - 2 y_i + y_{i-1}) / h^2   (Thomas algorithm).
  m_.assign(n, 0.0);
  if (n > 2) {
    std::vector<double> c(n, 0.0), d(n, 0.0);
    for (int i = 1; i < n - 1; ++i) {
      const double rhs = 6.0 * (n_[i + 1] - 2.0 * n_[i] + n_[i - 1]) / (h_ * h_);
      const double denom = 4.0 - (i > 1 ? c[i - 1] : 0.0);
      c[i] = 1.0 / denom;
      d[i] = (rhs - (i > 1 ? d[i - 1] : 0.0)) / denom;
    }
    for (int i = n - 2; i >= 1; --i) m_[i] = d[i] - c[i] * m_[i + 1];
  }
}

double LinkageTable::N_l(double q) const {
  const int n = static_cast<int>(n_.size());
  if (n == 0) return 0.0;
  if (n == 1) return n_[0];
  const double qc = std::clamp(q, q_lo_, q_hi_);
  int i = static_cast<int>(std::floor((qc - q_lo_) / h_));
  i = std::clamp(i, 0, n - 2);
  const double a = (q_lo_ + (i + 1) * h_ - qc) / h_, b = 1.0 - a;
  return a * n_[i] + b * n_[i + 1] + ((a * a * a - a) * m_[i] + (b * b * b - b) * m_[i + 1]) * h_ * h_ / 6.0;
}

// ---- ActuatorParams: the transmission ---------------------------------------------------

double ActuatorParams::moment_arm(double q) const { return is_rotary() ? 1.0 : linkage.moment_arm_m(q); }
LinkagePoint ActuatorParams::transmission(double q) const {
  return is_rotary() ? LinkagePoint{q, 1.0, 0.0} : linkage.at(q);
}
double ActuatorParams::dmoment_arm_dq(double q) const { return is_rotary() ? 0.0 : linkage.dmoment_arm_dq_m(q); }
double ActuatorParams::N_l(double q) const { return is_rotary() ? 1.0 : linkage.N_l(q); }
double ActuatorParams::travel(double q) const { return is_rotary() ? q : linkage.length_m(q) - linkage.length_m(0.0); }
double ActuatorParams::angle_for_travel(double dx, double guess) const {
  return is_rotary() ? dx : linkage.angle_for_length_change(dx, guess);
}

double ActuatorParams::applied_current_limit_A() const {
  if (!is_rotary()) return current_limit_A;
  return std::min(current_limit_A, torque_limit_Nm / (efficiency * force_per_amp_N_per_A()));
}

const char* kind_name(ActuatorKind kind) {
  switch (kind) {
    case ActuatorKind::RFSEA: return "rfsea";
    case ActuatorKind::FSEA: return "fsea";
    case ActuatorKind::ROTARY: return "rotary";
    case ActuatorKind::ROTARY_SEA: return "rotary_sea";
  }
  return "?";
}

}  // namespace dmbd::model
