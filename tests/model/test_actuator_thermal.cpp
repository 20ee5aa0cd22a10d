// ThermalModel: the exact step against an independent RK4 of derivative(), steady
// state, energy balance, the 2.5x liquid-cooling calibration and the knee scenario of
// the paper (Sec. IV-B: without cooling the knee windings passed 130 C while balancing,
// with cooling they stayed below 60 C).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

#include "robot_files.hpp"
#include "dmbd/model/actuator.hpp"
#include "dmbd/model/error.hpp"
#include "dmbd/model/thermal.hpp"

namespace dm = dmbd::model;

namespace {

dm::ThermalParams knee_thermal() {
  for (const auto& a : dmbd::test::draco_actuators())
    if (a.joint == "l_knee") return a.thermal;
  ADD_FAILURE() << "no l_knee";
  return {};
}

// Classical RK4 on derivative(), the reference for step().
dm::ThermalState rk4(const dm::ThermalModel& m, dm::ThermalState s, double i, bool cool, double t, double h) {
  const int n = static_cast<int>(std::ceil(t / h));
  h = t / n;
  auto add = [](const dm::ThermalState& a, const dm::ThermalState& d, double k) {
    return dm::ThermalState{a.T_winding_C + k * d.T_winding_C, a.T_housing_C + k * d.T_housing_C};
  };
  for (int k = 0; k < n; ++k) {
    const auto k1 = m.derivative(s, i, cool), k2 = m.derivative(add(s, k1, h / 2), i, cool),
               k3 = m.derivative(add(s, k2, h / 2), i, cool), k4 = m.derivative(add(s, k3, h), i, cool);
    s.T_winding_C += h / 6 * (k1.T_winding_C + 2 * k2.T_winding_C + 2 * k3.T_winding_C + k4.T_winding_C);
    s.T_housing_C += h / 6 * (k1.T_housing_C + 2 * k2.T_housing_C + 2 * k3.T_housing_C + k4.T_housing_C);
  }
  return s;
}

// Balancing current of the knee scenario: 4 A RMS = 1188 N of actuator force
// (k_tau N_m = 297.1 N/A), ~60 N m at the knee's mid-range moment arm (5.1 cm): the
// stance knee carrying the ~30 kg upper body ~0.2 m behind it, plus force-loop ripple.
// Chosen; the paper does not print the current.
constexpr double kBalancingCurrentA = 4.0;
constexpr double kBalancingDurationS = 900.0;  // 15 min

}  // namespace

// step() is exact for a constant current (affine ODE, matrix exponential): it must agree
// with a fine RK4 of derivative() from any state, for small and large dt, both cooling
// modes, at and above the continuous rating. RK4 at h = 0.05 s (fastest time constant
// ~12 s) has global error ~(h/tau)^4 ~ 1e-10 relative: 1e-8 K bound.
TEST(Thermal, ExactStepMatchesRk4OfTheDerivative) {
  const dm::ThermalModel ref(knee_thermal());
  for (bool cool : {false, true}) {
    for (double i : {0.0, 3.0, 8.0}) {
      for (double dt : {0.01, 1.0, 60.0, 600.0}) {
        dm::ThermalModel m(knee_thermal());
        const dm::ThermalState s0{70.0, 40.0};
        m.reset(s0);
        m.step(i, dt, cool);
        const dm::ThermalState r = rk4(ref, s0, i, cool, dt, 0.05);
        EXPECT_NEAR(m.state().T_winding_C, r.T_winding_C, 1e-8) << "i " << i << " dt " << dt << " cool " << cool;
        EXPECT_NEAR(m.state().T_housing_C, r.T_housing_C, 1e-8) << "i " << i << " dt " << dt << " cool " << cool;
      }
    }
  }
}

// derivative() is the slope of step(): (step(dt) - x) / dt -> derivative as dt -> 0, with
// an O(dt) remainder x'' dt / 2 ~ (|x'|/tau) dt ~ 1e-7 K/s at dt = 1e-4 s.
TEST(Thermal, DerivativeIsTheSlopeOfStep) {
  dm::ThermalModel m(knee_thermal());
  const dm::ThermalState s0{90.0, 50.0};
  for (bool cool : {false, true}) {
    const double dt = 1e-4;
    m.reset(s0);
    m.step(5.0, dt, cool);
    const dm::ThermalState d = m.derivative(s0, 5.0, cool);
    EXPECT_NEAR((m.state().T_winding_C - s0.T_winding_C) / dt, d.T_winding_C, 1e-5) << cool;
    EXPECT_NEAR((m.state().T_housing_C - s0.T_housing_C) / dt, d.T_housing_C, 1e-5) << cool;
    // and it vanishes at the steady state
    const dm::ThermalState ss = m.steady_state(5.0, cool);
    const dm::ThermalState z = m.derivative(ss, 5.0, cool);
    EXPECT_NEAR(z.T_winding_C, 0.0, 1e-12);
    EXPECT_NEAR(z.T_housing_C, 0.0, 1e-12);
  }
}

// Long integration with many small steps settles on steady_state() (closed form). The
// slowest case, 2.9 A uncooled, has a slow mode of ~880 s (the copper's alpha stretches
// the 640 s of zero current by 1/(1 - i^2 R_20 alpha R_tot) = 1.37): after 8 h (33 of them)
// the transient is < 1e-12 K; 28800 steps of 1 s each add only rounding: 1e-7 K.
TEST(Thermal, LongIntegrationReachesSteadyState) {
  for (bool cool : {false, true}) {
    for (double i : {1.0, 2.9, 6.0}) {
      const dm::ThermalModel probe(knee_thermal());
      const dm::ThermalState ss = probe.steady_state(i, cool);
      if (!std::isfinite(ss.T_winding_C)) continue;  // uncooled 6 A runs away (tested below)
      dm::ThermalModel m(knee_thermal());
      for (int k = 0; k < 28800; ++k) m.step(i, 1.0, cool);
      EXPECT_NEAR(m.state().T_winding_C, ss.T_winding_C, 1e-7) << "i " << i << " cool " << cool;
      EXPECT_NEAR(m.state().T_housing_C, ss.T_housing_C, 1e-7) << "i " << i << " cool " << cool;
      // steady state: Joule heat = heat to ambient
      EXPECT_NEAR(probe.joule_power_W(i, ss.T_winding_C), probe.heat_to_ambient_W(ss, cool), 1e-9);
    }
  }
}

// With the copper's temperature coefficient the uncooled knee has no steady state above
// i^2 R_20 alpha (R_wh + R_ha) = 1, i.e. 5.6 A: the winding runs away (the model says
// so by returning infinity, and step() keeps heating).
TEST(Thermal, RunawayHasNoSteadyState) {
  dm::ThermalModel m(knee_thermal());
  const auto& p = m.params();
  const double i_runaway = 1.0 / std::sqrt(p.R_winding_ohm * p.alpha_per_K * (p.R_wh_K_per_W + p.R_ha_air_K_per_W));
  EXPECT_TRUE(std::isfinite(m.steady_state(0.999 * i_runaway, false).T_winding_C));
  EXPECT_EQ(m.steady_state(1.001 * i_runaway, false).T_winding_C, std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::isfinite(m.steady_state(1.001 * i_runaway, true).T_winding_C));  // cooled: fine
  m.step(6.0, 3600, false);
  EXPECT_GT(m.state().T_winding_C, 400.0);
}

// Energy: Joule heat in = heat stored in both nodes + heat out to the ambient, over 20
// min at 4 A from cold (uncooled, then cooled). Heat flows by the trapezoidal rule on 0.05
// s steps (exact states): the quadrature error ~ t h^2 |P''| / 12 ~ 1e-7 J of ~2e4 J:
// 1e-8 relative bound.
TEST(Thermal, EnergyBalance) {
  for (bool cool : {false, true}) {
    dm::ThermalModel m(knee_thermal());
    const auto& p = m.params();
    const double i = 4.0, h = 0.05;
    const int n = static_cast<int>(1200 / h);
    double e_in = 0, e_out = 0;
    dm::ThermalState s = m.state();
    for (int k = 0; k < n; ++k) {
      const double pin0 = m.joule_power_W(i, s.T_winding_C), pout0 = m.heat_to_ambient_W(s, cool);
      m.step(i, h, cool);
      s = m.state();
      e_in += h / 2 * (pin0 + m.joule_power_W(i, s.T_winding_C));
      e_out += h / 2 * (pout0 + m.heat_to_ambient_W(s, cool));
    }
    const double stored =
        p.C_winding_J_per_K * (s.T_winding_C - p.T_ambient_C) + p.C_housing_J_per_K * (s.T_housing_C - p.T_ambient_C);
    std::printf("[ measured ] energy, %s: in %.1f J = stored %.1f J + out %.1f J (residual %.2g J)\n",
                cool ? "cooled" : "uncooled", e_in, stored, e_out, e_in - stored - e_out);
    EXPECT_NEAR(e_in, stored + e_out, 1e-8 * e_in) << cool;
  }
}

// The calibration: liquid cooling raises the continuous current exactly 2.5x (paper,
// Sec. II-B). Both ratings hold the winding at T_max where R(T) is the same, so the ratio
// is sqrt((R_wh + R_ha_air) / (R_wh + R_ha_liquid)) with no approximation; every joint's
// R_ha_liquid is the one liquid_resistance_for_current_gain derives. 1e-9 relative.
TEST(Thermal, LiquidCoolingRaisesContinuousCurrentExactly2_5x) {
  for (const auto& a : dmbd::test::draco_actuators()) {
    const dm::ThermalModel m(a.thermal);
    const double ratio = m.continuous_current_A(true) / m.continuous_current_A(false);
    EXPECT_NEAR(ratio, 2.5, 2.5e-9) << a.joint;
    EXPECT_NEAR(a.thermal.R_ha_liquid_K_per_W,
                dm::liquid_resistance_for_current_gain(a.thermal.R_wh_K_per_W, a.thermal.R_ha_air_K_per_W, 2.5), 1e-12)
        << a.joint;
    // The rating really is the current whose steady winding temperature is T_max.
    for (bool cool : {false, true})
      EXPECT_NEAR(m.steady_state(m.continuous_current_A(cool), cool).T_winding_C, a.thermal.T_winding_max_C, 1e-9)
          << a.joint;
    if (a.joint[0] == 'l')
      std::printf("[ measured ] %-11s continuous current %.3f A uncooled, %.3f A cooled (ratio - 2.5 = %.1e), limit %.0f A\n",
                  a.joint.c_str(), m.continuous_current_A(false), m.continuous_current_A(true), ratio - 2.5,
                  a.current_limit_A);
  }
  // A made-up network: the derivation holds for any R_wh, R_ha_air (with R_ha_liquid > 0).
  dm::ThermalParams q;
  q.R_wh_K_per_W = 0.37;
  q.R_ha_air_K_per_W = 4.1;
  q.alpha_per_K = 0.0039;
  q.R_ha_liquid_K_per_W = dm::liquid_resistance_for_current_gain(0.37, 4.1, 2.5);
  const dm::ThermalModel mq(q);
  EXPECT_NEAR(mq.continuous_current_A(true) / mq.continuous_current_A(false), 2.5, 2.5e-9);
}

// Winding time constant tens of seconds, housing several minutes (uncooled); cooling
// shortens the housing's to under a minute.
TEST(Thermal, TimeConstantsArePlausible) {
  for (const auto& a : dmbd::test::draco_actuators()) {
    const dm::ThermalModel m(a.thermal);
    const dm::ThermalTimeConstants air = m.time_constants_s(false), liq = m.time_constants_s(true);
    if (a.joint[0] == 'l')
      std::printf("[ measured ] %-11s time constants: uncooled %.1f s / %.0f s, cooled %.1f s / %.1f s\n",
                  a.joint.c_str(), air.winding_s, air.housing_s, liq.winding_s, liq.housing_s);
    EXPECT_GE(air.winding_s, 10.0) << a.joint;
    EXPECT_LE(air.winding_s, 60.0) << a.joint;
    EXPECT_GE(air.housing_s, 180.0) << a.joint;
    EXPECT_LE(air.housing_s, 1200.0) << a.joint;
    EXPECT_LT(liq.housing_s, 60.0) << a.joint;
    // cross-check: the uncooled winding cools from 100 C to ambient along these modes
    dm::ThermalModel c(a.thermal);
    c.reset({100.0, 100.0});
    c.step(0.0, air.housing_s, false);  // both nodes equal: mostly the slow mode
    const double left = (c.state().T_housing_C - a.thermal.T_ambient_C) / (100.0 - a.thermal.T_ambient_C);
    EXPECT_GT(left, 0.30) << a.joint;  // exp(-1) = 0.37, minus a little of the fast mode
    EXPECT_LT(left, 0.40) << a.joint;
  }
}

// The knee during balancing (paper Sec. IV-B): at kBalancingCurrentA for 15 minutes from
// 25 C, the uncooled winding passes 130 C; the cooled one never reaches 60 C. The current
// is above the uncooled continuous rating (2.98 A) and well below the cooled one (7.46 A).
TEST(Thermal, KneeBalancingScenario) {
  const dm::ThermalParams p = knee_thermal();
  double peak[2] = {0, 0}, t130 = -1;
  for (int cool = 0; cool < 2; ++cool) {
    dm::ThermalModel m(p);
    for (int k = 1; k <= static_cast<int>(kBalancingDurationS); ++k) {
      m.step(kBalancingCurrentA, 1.0, cool == 1);
      peak[cool] = std::max(peak[cool], m.state().T_winding_C);
      if (cool == 0 && t130 < 0 && m.state().T_winding_C > 130) t130 = k;
    }
  }
  const dm::ThermalModel m(p);
  std::printf(
      "[ measured ] knee at %.1f A for %.0f s: uncooled %.1f C (passes 130 C at %.0f s; steady %.1f C), cooled %.1f C "
      "(steady %.1f C)\n",
      kBalancingCurrentA, kBalancingDurationS, peak[0], t130, m.steady_state(kBalancingCurrentA, false).T_winding_C,
      peak[1], m.steady_state(kBalancingCurrentA, true).T_winding_C);
  EXPECT_GT(peak[0], 130.0);
  EXPECT_LT(peak[1], 60.0);
  EXPECT_GT(kBalancingCurrentA, m.continuous_current_A(false));
  EXPECT_LT(kBalancingCurrentA, m.continuous_current_A(true));
  // cooled: even indefinitely it stays below 60 C
  EXPECT_LT(m.steady_state(kBalancingCurrentA, true).T_winding_C, 60.0);
}

TEST(Thermal, RejectsNonPhysicalParameters) {
  dm::ThermalParams p;
  p.C_winding_J_per_K = 0;
  EXPECT_THROW(dm::ThermalModel{p}, dm::ModelError);
  p = {};
  p.R_ha_liquid_K_per_W = -0.1;
  EXPECT_THROW(dm::ThermalModel{p}, dm::ModelError);
  dm::ThermalModel m;
  EXPECT_THROW(m.step(1.0, -1.0, false), std::invalid_argument);
  EXPECT_EQ(m.state().T_winding_C, m.params().T_ambient_C);  // starts at ambient
}

// ThermalParams' defaults are the knee motor of the table (a default-built model is DRACO's knee).
TEST(Thermal, DefaultsAreTheKneeMotor) {
  const dm::ThermalParams d, k = knee_thermal();
  EXPECT_EQ(d.R_winding_ohm, k.R_winding_ohm);
  EXPECT_EQ(d.alpha_per_K, k.alpha_per_K);
  EXPECT_EQ(d.C_winding_J_per_K, k.C_winding_J_per_K);
  EXPECT_EQ(d.C_housing_J_per_K, k.C_housing_J_per_K);
  EXPECT_EQ(d.R_wh_K_per_W, k.R_wh_K_per_W);
  EXPECT_EQ(d.R_ha_air_K_per_W, k.R_ha_air_K_per_W);
  EXPECT_EQ(d.R_ha_liquid_K_per_W, k.R_ha_liquid_K_per_W);
  EXPECT_EQ(d.T_ambient_C, k.T_ambient_C);
  EXPECT_EQ(d.T_winding_max_C, k.T_winding_max_C);
}
