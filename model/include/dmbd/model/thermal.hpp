#pragma once
// Two-node thermal model of one motor: winding and housing.
//   C_w dT_w/dt = i^2 R(T_w) - (T_w - T_h) / R_wh
//   C_h dT_h/dt = (T_w - T_h) / R_wh - (T_h - T_amb) / R_ha(cooling)
// with R(T) = R_20 (1 + alpha (T - 20 C)) (copper) and R_ha switched between the
// air-cooled and the liquid-cooled housing-to-ambient resistance.
// For a constant current the system is affine in (T_w, T_h) (R(T) is linear in T), so
// step() advances it exactly (2x2 matrix exponential), for any dt. See docs/model.md.

namespace dmbd::model {

// Defaults: DRACO's knee motor (robots/draco/actuators.yaml, docs/model.md section 4).
struct ThermalParams {
  double R_winding_ohm = 1.03;           // at 20 C
  double alpha_per_K = 0.00393;          // copper
  double C_winding_J_per_K = 30;
  double C_housing_J_per_K = 60;
  double R_wh_K_per_W = 1.0;             // winding to housing
  double R_ha_air_K_per_W = 7.0;         // housing to ambient, cooling off
  double R_ha_liquid_K_per_W = 0.28;     // housing to coolant/ambient, cooling on (2.5x continuous current)
  double T_ambient_C = 25;
  double T_winding_max_C = 130;          // rating limit
};

// The liquid-cooled housing-to-ambient resistance that makes the continuous current
// rating `gain` times the air-cooled one: both ratings hold the winding at
// T_winding_max_C, where R(T) is the same, so i_liquid^2 / i_air^2 = (R_wh + R_ha_air) /
// (R_wh + R_ha_liquid) exactly (temperature-dependent resistance included), and
//   R_ha_liquid = (R_wh + R_ha_air) / gain^2 - R_wh   (K/W; must come out > 0).
double liquid_resistance_for_current_gain(double R_wh_K_per_W, double R_ha_air_K_per_W, double gain);

// The two time constants of the network at zero current (s): the fast one is dominated
// by the winding (C_w, R_wh), the slow one by the housing (C_h, R_ha).
struct ThermalTimeConstants {
  double winding_s = 0;
  double housing_s = 0;
};

struct ThermalState {
  double T_winding_C = 25;
  double T_housing_C = 25;
};

class ThermalModel {
 public:
  // Throws ModelError for non-positive capacities/resistances or a negative alpha.
  explicit ThermalModel(const ThermalParams& p = {});
  const ThermalParams& params() const { return p_; }
  void reset(ThermalState s) { s_ = s; }
  void reset() { s_ = {p_.T_ambient_C, p_.T_ambient_C}; }
  const ThermalState& state() const { return s_; }
  // Advances by dt seconds with constant current (A) and cooling switch.
  void step(double current_A, double dt_s, bool cooling);
  // Time derivatives at a state (for an outer integrator).
  ThermalState derivative(const ThermalState& s, double current_A, bool cooling) const;
  // Largest constant current whose steady state keeps the winding at T_winding_max_C.
  double continuous_current_A(bool cooling) const;
  // Steady-state temperatures at a constant current. Both +infinity when there is none
  // (thermal runaway: i^2 R_20 alpha (R_wh + R_ha) >= 1, the copper's resistance rises
  // faster than the network sheds heat).
  ThermalState steady_state(double current_A, bool cooling) const;
  ThermalTimeConstants time_constants_s(bool cooling) const;
  // Joule heat in the winding at a winding temperature (W), and the heat leaving the
  // housing to the ambient/coolant at a state (W).
  double joule_power_W(double current_A, double T_winding_C) const;
  double heat_to_ambient_W(const ThermalState& s, bool cooling) const;

 private:
  ThermalParams p_;
  ThermalState s_;
};

}  // namespace dmbd::model
