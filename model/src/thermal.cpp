// Two-node motor thermal model (winding, housing). For a constant current the model is
// affine in the temperatures, x' = A x + c, because the copper resistance is linear in
// the winding temperature; step() applies the exact solution
//   x(t) = e^{At} x0 + (integral_0^t e^{As} ds) c
// with both matrix functions from Sylvester's formula (A is 2x2 with real, distinct
// eigenvalues: its off-diagonal entries are both positive).
#include "dmbd/model/thermal.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "dmbd/model/error.hpp"

namespace dmbd::model {

namespace {

struct Affine2 {
  double a11, a12, a21, a22;  // A
  double c1, c2;              // c
};

double r_ha(const ThermalParams& p, bool cooling) { return cooling ? p.R_ha_liquid_K_per_W : p.R_ha_air_K_per_W; }

Affine2 affine(const ThermalParams& p, double current_A, bool cooling) {
  const double i2r = current_A * current_A * p.R_winding_ohm;  // W at 20 C
  const double g_wh = 1.0 / p.R_wh_K_per_W, g_ha = 1.0 / r_ha(p, cooling);
  Affine2 m{};
  m.a11 = (i2r * p.alpha_per_K - g_wh) / p.C_winding_J_per_K;
  m.a12 = g_wh / p.C_winding_J_per_K;
  m.a21 = g_wh / p.C_housing_J_per_K;
  m.a22 = -(g_wh + g_ha) / p.C_housing_J_per_K;
  m.c1 = i2r * (1.0 - 20.0 * p.alpha_per_K) / p.C_winding_J_per_K;
  m.c2 = g_ha * p.T_ambient_C / p.C_housing_J_per_K;
  return m;
}

// Eigenvalues, l1 > l2 (real, distinct since a12 a21 > 0).
void eigen(const Affine2& m, double& l1, double& l2) {
  const double half_tr = 0.5 * (m.a11 + m.a22);
  const double half_diff = 0.5 * (m.a11 - m.a22);
  const double root = std::sqrt(half_diff * half_diff + m.a12 * m.a21);
  l1 = half_tr + root;
  l2 = half_tr - root;
}

void check_positive(double v, const char* name) {
  if (!(v > 0) || !std::isfinite(v))
    throw ModelError(std::string("thermal parameters: '") + name + "' must be a positive finite number, got " +
                     std::to_string(v));
}

}  // namespace

double liquid_resistance_for_current_gain(double R_wh_K_per_W, double R_ha_air_K_per_W, double gain) {
  return (R_wh_K_per_W + R_ha_air_K_per_W) / (gain * gain) - R_wh_K_per_W;
}

ThermalModel::ThermalModel(const ThermalParams& p) : p_(p), s_{p.T_ambient_C, p.T_ambient_C} {
  check_positive(p.R_winding_ohm, "R_winding_ohm");
  check_positive(p.C_winding_J_per_K, "C_winding_J_per_K");
  check_positive(p.C_housing_J_per_K, "C_housing_J_per_K");
  check_positive(p.R_wh_K_per_W, "R_wh_K_per_W");
  check_positive(p.R_ha_air_K_per_W, "R_ha_air_K_per_W");
  check_positive(p.R_ha_liquid_K_per_W, "R_ha_liquid_K_per_W");
  if (!(p.alpha_per_K >= 0) || !std::isfinite(p.alpha_per_K))
    throw ModelError("thermal parameters: 'alpha_per_K' must be >= 0, got " + std::to_string(p.alpha_per_K));
  if (!std::isfinite(p.T_ambient_C) || !std::isfinite(p.T_winding_max_C))
    throw ModelError("thermal parameters: temperatures must be finite");
}

double ThermalModel::joule_power_W(double current_A, double T_winding_C) const {
  return current_A * current_A * p_.R_winding_ohm * (1.0 + p_.alpha_per_K * (T_winding_C - 20.0));
}

double ThermalModel::heat_to_ambient_W(const ThermalState& s, bool cooling) const {
  return (s.T_housing_C - p_.T_ambient_C) / r_ha(p_, cooling);
}

ThermalState ThermalModel::derivative(const ThermalState& s, double current_A, bool cooling) const {
  const double q_wh = (s.T_winding_C - s.T_housing_C) / p_.R_wh_K_per_W;
  ThermalState d;
  d.T_winding_C = (joule_power_W(current_A, s.T_winding_C) - q_wh) / p_.C_winding_J_per_K;
  d.T_housing_C = (q_wh - heat_to_ambient_W(s, cooling)) / p_.C_housing_J_per_K;
  return d;
}

void ThermalModel::step(double current_A, double dt_s, bool cooling) {
  if (!(dt_s >= 0)) throw std::invalid_argument("ThermalModel::step: dt_s must be >= 0");
  if (dt_s == 0) return;
  const Affine2 m = affine(p_, current_A, cooling);
  double l1, l2;
  eigen(m, l1, l2);
  // f(A) = [f(l1) (A - l2 I) - f(l2) (A - l1 I)] / (l1 - l2)
  // e^{l dt} as 1 + expm1(l dt), and phi1(l, dt) = (e^{l dt} - 1) / l (dt at l = 0) from
  // the same expm1: two exponentials a step instead of four (the thermals run for every
  // actuator, cooled and not, at every event of a scenario).
  const double g1 = std::expm1(l1 * dt_s), g2 = std::expm1(l2 * dt_s);
  const double e1 = 1.0 + g1, e2 = 1.0 + g2;
  const double p1 = l1 == 0.0 ? dt_s : g1 / l1, p2 = l2 == 0.0 ? dt_s : g2 / l2;
  const double d = l1 - l2;
  auto apply = [&](double f1, double f2, double x, double y, double& ox, double& oy) {
    const double k_a = (f1 - f2) / d;            // coefficient of A
    const double k_i = (f2 * l1 - f1 * l2) / d;  // coefficient of I
    ox = k_a * (m.a11 * x + m.a12 * y) + k_i * x;
    oy = k_a * (m.a21 * x + m.a22 * y) + k_i * y;
  };
  double hx, hy, fx, fy;
  apply(e1, e2, s_.T_winding_C, s_.T_housing_C, hx, hy);  // e^{A dt} x0
  apply(p1, p2, m.c1, m.c2, fx, fy);                      // phi(A, dt) c
  s_.T_winding_C = hx + fx;
  s_.T_housing_C = hy + fy;
}

double ThermalModel::continuous_current_A(bool cooling) const {
  const double rise = p_.T_winding_max_C - p_.T_ambient_C;
  if (!(rise > 0)) return 0.0;
  const double r_hot = p_.R_winding_ohm * (1.0 + p_.alpha_per_K * (p_.T_winding_max_C - 20.0));
  return std::sqrt(rise / (r_hot * (p_.R_wh_K_per_W + r_ha(p_, cooling))));
}

ThermalState ThermalModel::steady_state(double current_A, bool cooling) const {
  // T_w - T_a = P (R_wh + R_ha), P = i^2 R_20 (1 + alpha (T_w - 20)), solved for T_w.
  const double r_tot = p_.R_wh_K_per_W + r_ha(p_, cooling);
  const double i2r = current_A * current_A * p_.R_winding_ohm;
  const double den = 1.0 - i2r * p_.alpha_per_K * r_tot;
  if (!(den > 0)) {
    const double inf = std::numeric_limits<double>::infinity();
    return {inf, inf};
  }
  ThermalState s;
  s.T_winding_C = (p_.T_ambient_C + i2r * (1.0 - 20.0 * p_.alpha_per_K) * r_tot) / den;
  s.T_housing_C = p_.T_ambient_C + joule_power_W(current_A, s.T_winding_C) * r_ha(p_, cooling);
  return s;
}

ThermalTimeConstants ThermalModel::time_constants_s(bool cooling) const {
  const Affine2 m = affine(p_, 0.0, cooling);
  double l1, l2;
  eigen(m, l1, l2);  // both negative at zero current: l2 < l1 < 0
  return {-1.0 / l2, -1.0 / l1};
}

}  // namespace dmbd::model
