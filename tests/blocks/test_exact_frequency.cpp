// Issue 28 row 3: margins, crossovers and bandwidth of repeated and clustered poles from
// the transfer's own response (exact_frequency.hpp), not from its scattered roots.
// Golden values in closed form: 1/(s + 1)^20 has its phase crossover at tan(pi/20)
// rad/s with gain margin 400 log10 sec(pi/20) dB, and its -3 dB bandwidth at
// sqrt(10^(3/200) - 1) rad/s.
#include <gtest/gtest.h>

#include <cmath>

#include "dmbd/blocks/exact_frequency.hpp"
#include "dmbd/blocks/siso.hpp"
#include "test_support.hpp"

namespace dmbd::blocks {
namespace {

TransferFunction tf(const std::string& e) { return TransferFunction::parse(e, {}, 0.0); }

ExactResponse of(const Siso& g) {
  return [&g](double w) { return g.response(w); };
}

TEST(ExactFrequency, TwentyFoldPoleHasTheClosedFormGainMarginAndBandwidth) {
  // Was 2.15907 dB at 0.0254066 Hz and a bandwidth of 0.030022 Hz (scattered roots).
  const Siso g = Siso::from_tf(tf("1/(s+1)^20"));
  const Margins m = margins(g.zpk(), of(g));
  ASSERT_TRUE(m.phase_crossover_rad_s && m.gain_margin_db);
  const double wpc = std::tan(M_PI / 20.0);
  EXPECT_NEAR(*m.phase_crossover_rad_s, wpc, 1e-12 * wpc);
  EXPECT_NEAR(*m.gain_margin_db, 400.0 * std::log10(1.0 / std::cos(M_PI / 20.0)), 1e-10);
  EXPECT_FALSE(m.gain_crossover_rad_s.has_value());  // |L| < 1 for every w > 0
  const auto bw = bandwidth(g.zpk(), of(g));
  ASSERT_TRUE(bw.has_value());
  const double wb = std::sqrt(std::pow(10.0, 3.0 / 200.0) - 1.0);
  EXPECT_NEAR(*bw, wb, 1e-12 * wb);
}

TEST(ExactFrequency, RepeatedPoleLoopGainCrossoverAndPhaseMargin) {
  // L = 4/(s + 1)^4: |L| = 1 at w = 1 (|1 + j|^4 = 4), phase -4 * 45 deg = -180 deg there:
  // a phase margin of 0 and a phase crossover at the same w = 1 with 0 dB.
  const Siso g = Siso::from_tf(tf("4/(s+1)^4"));
  const Margins m = margins(g.zpk(), of(g));
  ASSERT_TRUE(m.gain_crossover_rad_s && m.phase_margin_deg && m.phase_crossover_rad_s && m.gain_margin_db);
  EXPECT_NEAR(*m.gain_crossover_rad_s, 1.0, 1e-12);
  EXPECT_NEAR(*m.phase_margin_deg, 0.0, 1e-9);
  EXPECT_NEAR(*m.phase_crossover_rad_s, 1.0, 1e-12);
  EXPECT_NEAR(*m.gain_margin_db, 0.0, 1e-9);
}

TEST(ExactFrequency, BodeAtTheCrossoverIsMinusOneEighty) {
  const Siso g = Siso::from_tf(tf("1/(s+1)^20"));
  const double wpc = std::tan(M_PI / 20.0);
  const Bode b = bode(g.zpk(), {1e-3, wpc, 10.0}, of(g));
  EXPECT_NEAR(b.phase_deg[1], -180.0, 1e-9);                       // the branch from DC
  EXPECT_NEAR(b.phase_deg[0], -20.0 * std::atan(1e-3) * 180.0 / M_PI, 1e-9);
  EXPECT_NEAR(b.phase_deg[2], -20.0 * std::atan(10.0) * 180.0 / M_PI, 1e-7);  // -1685.6 deg
  EXPECT_NEAR(b.mag_db[2], -200.0 * std::log10(101.0), 1e-9);
}

TEST(ExactFrequency, DiagramRealisationIsTheExactResponse) {
  // The same 20-fold pole as a state-space chain (Siso::from_state_space): the response
  // from the realisation agrees with the closed form.
  const Siso g = Siso::from_state_space(SparseStateSpace(StateSpace::from_tf(tf("1/(s+1)^20"))));
  const double wpc = std::tan(M_PI / 20.0);
  const Margins m = margins(g.zpk(), of(g));
  ASSERT_TRUE(m.phase_crossover_rad_s && m.gain_margin_db);
  EXPECT_NEAR(*m.phase_crossover_rad_s, wpc, 1e-9 * wpc);
  EXPECT_NEAR(*m.gain_margin_db, 400.0 * std::log10(1.0 / std::cos(M_PI / 20.0)), 1e-8);
}

}  // namespace
}  // namespace dmbd::blocks

namespace dmbd::blocks {
namespace {

// A discrete loop with poles 1e-3..1e-2 from the unit circle: margins() listed every
// multiple of 2π inside a slope bound that reached ±inf there and never returned (issue
// 28's random-systems check: 47 of 200 runs). Each crossing it reports now is one.
TEST(ExactFrequency, PolesNearTheUnitCircleDoNotStallTheCrossingSearch) {
  const TransferFunction g = TransferFunction::parse(
      "1/(z^4 + (-2.557769160204915)*z^3 + (3.4293130399681955)*z^2 + (-2.334047322635506)*z + (0.8074531587703119))",
      {}, 0.001);
  const Siso s = Siso::from_tf(g);
  const Margins m = margins(s.zpk(), of(s));
  for (const Crossing& c : m.phase_crossovers) {
    const auto l = s.response(c.w_rad_s);
    ASSERT_TRUE(l.has_value());
    EXPECT_NEAR(std::abs(std::arg(*l)), M_PI, 1e-7) << "at " << c.w_rad_s << " rad/s";
  }
  for (const Crossing& c : m.gain_crossovers) {
    const auto l = s.response(c.w_rad_s);
    ASSERT_TRUE(l.has_value());
    EXPECT_NEAR(std::abs(*l), 1.0, 1e-7) << "at " << c.w_rad_s << " rad/s";
  }
}

}  // namespace
}  // namespace dmbd::blocks
