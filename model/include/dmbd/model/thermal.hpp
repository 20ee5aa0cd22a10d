#pragma once
// Two-node thermal model of one motor: winding and housing.
//   C_w dT_w/dt = i^2 R(T_w) - (T_w - T_h) / R_wh
//   C_h dT_h/dt = (T_w - T_h) / R_wh - (T_h - T_amb) / R_ha(cooling)
// with R(T) = R_20 (1 + alpha (T - 20 C)) (copper) and R_ha switched between the
// air-cooled and the liquid-cooled housing-to-ambient resistance.

namespace dmbd::model {

struct ThermalParams {
  double R_winding_ohm = 1.03;           // at 20 C
  double alpha_per_K = 0.00393;          // copper
  double C_winding_J_per_K = 60;
  double C_housing_J_per_K = 600;
  double R_wh_K_per_W = 0.5;             // winding to housing
  double R_ha_air_K_per_W = 3.0;         // housing to ambient, cooling off
  double R_ha_liquid_K_per_W = 0.2;      // housing to coolant/ambient, cooling on
  double T_ambient_C = 25;
  double T_winding_max_C = 130;          // rating limit
};

struct ThermalState {
  double T_winding_C = 25;
  double T_housing_C = 25;
};

class ThermalModel {
 public:
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
  // Steady-state temperatures at a constant current.
  ThermalState steady_state(double current_A, bool cooling) const;

 private:
  ThermalParams p_;
  ThermalState s_;
};

}  // namespace dmbd::model
