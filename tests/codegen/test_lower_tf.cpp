// Lowering one transfer function: the interpreter's response equals an independent
// simulation of the discretised TF, the direct form I difference equation of the
// coefficients that dmbd::blocks::c2d gives, run in long double. The lowering builds
// its sections from the exactly mapped continuous poles and zeros, so the two share
// nothing but the continuous TF.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "dmbd/blocks/discretize.hpp"
#include "dmbd/blocks/elements.hpp"
#include "dmbd/codegen/interpreter.hpp"
#include "dmbd/codegen/loop_program.hpp"
#include "test_support.hpp"

namespace dmbd::codegen {
namespace {

using namespace test;

LowerOptions at(double rate_hz, C2dMethod m = C2dMethod::Tustin) {
  LowerOptions o;
  o.rate_hz = rate_hz;
  o.method = m;
  return o;
}

// The paper's Q filter (eq. frc_ctrl): a second-order Butterworth at 60 Hz, written as
// in examples/diagrams/force_dob.yaml (Q_A).
TransferFunction q_filter() {
  return TransferFunction::parse("wc^2/(s^2 + sqrt(2)*wc*s + wc^2)", {{"wc", 2 * M_PI * 60.0}});
}

// Issue 4, done-when: the Q filter generated at 1 kHz with Tustin matches an
// independent simulation of the Tustin-discretised filter to 1e-9 in double (step
// response of unit amplitude, so 1e-9 absolute = 1e-9 of full scale).
TEST(LowerTf, PaperQFilterTustinStepMatchesDirectForm1To1e9) {
  const TransferFunction g = q_filter();
  const LoopProgram p = lower(g, "q_filter", at(1000.0));
  ASSERT_EQ(p.inputs.size(), 1u);
  ASSERT_EQ(p.outputs.size(), 1u);
  ASSERT_EQ(p.blocks.size(), 1u);
  EXPECT_NE(p.blocks[0].realisation.find("1 second-order section"), std::string::npos) << p.blocks[0].realisation;
  EXPECT_NE(p.blocks[0].realisation.find("tustin"), std::string::npos) << p.blocks[0].realisation;
  EXPECT_EQ(p.states.size(), 2u);
  const auto u = step_input(1000);
  const auto want = direct_form_1(blocks::c2d(g, 1e-3, C2dMethod::Tustin), u);
  const auto got = interpret_siso(p, u);
  EXPECT_TRUE(sequences_near(got, want, 1e-9, 1.0));
  // And the step settles at the DC gain 1 (Tustin keeps it exactly).
  EXPECT_NEAR(got.back(), 1.0, 1e-9);
}

TEST(LowerTf, PaperQFilterChirpAllMethods) {
  const TransferFunction g = q_filter();
  const auto u = chirp(3000, 1000.0, 1.0, 450.0);
  for (C2dMethod m : {C2dMethod::Tustin, C2dMethod::Zoh, C2dMethod::BackwardEuler}) {
    SCOPED_TRACE(blocks::to_string(m));
    const LoopProgram p = lower(g, "q", at(1000.0, m));
    EXPECT_NE(p.blocks[0].realisation.find(blocks::to_string(m)), std::string::npos) << p.blocks[0].realisation;
    const auto want = direct_form_1(blocks::c2d(g, 1e-3, m), u);
    // 1e-9 of full scale (unit input amplitude): rounding of a stable second-order
    // recursion, amplified by its noise gain (< 1e2 here), is ~1e-14.
    EXPECT_TRUE(sequences_near(interpret_siso(p, u), want, 1e-9, 1.0));
    EXPECT_TRUE(sequences_near(interpret_siso(p, step_input(500)), direct_form_1(blocks::c2d(g, 1e-3, m), step_input(500)), 1e-9, 1.0));
  }
}

// ZOH of a strictly proper filter has no direct feedthrough: the first output sample of
// a step is exactly 0 (b0 == 0 is kept exact), as the force DOB's Q_A relies on.
TEST(LowerTf, ZohStrictlyProperHasNoFeedthrough) {
  const LoopProgram p = lower(q_filter(), "q", at(1000.0, C2dMethod::Zoh));
  const auto y = interpret_siso(p, step_input(3));
  EXPECT_EQ(y[0], 0.0);
  EXPECT_GT(y[1], 0.0);
  // Tustin has feedthrough: the first sample is already non-zero.
  EXPECT_GT(interpret_siso(lower(q_filter(), "q", at(1000.0)), step_input(1))[0], 0.0);
}

// Higher orders become cascades of sections: Butterworth 3..8 at 60 Hz, 1 kHz.
// Reference: the 8th-order direct form of c2d's coefficients, in long double. Its own
// accuracy is limited by the rounding of those double coefficients (relative 1e-16
// on coefficients of size up to ~1e2, poles of radius 0.65..0.93 and moderate
// clustering): 1e-9 of full scale leaves a margin of > 1e2 on what we see.
TEST(LowerTf, ButterworthCascadesMatchDirectForm) {
  const auto u = chirp(2000, 1000.0, 0.5, 400.0);
  for (int n = 3; n <= 8; ++n) {
    SCOPED_TRACE("order " + std::to_string(n));
    const TransferFunction g = blocks::butterworth_lowpass(n, 2 * M_PI * 60.0);
    for (C2dMethod m : {C2dMethod::Tustin, C2dMethod::Zoh, C2dMethod::BackwardEuler}) {
      SCOPED_TRACE(blocks::to_string(m));
      const LoopProgram p = lower(g, "bw", at(1000.0, m));
      EXPECT_EQ(p.states.size(), static_cast<size_t>(n));
      EXPECT_TRUE(sequences_near(interpret_siso(p, u), direct_form_1(blocks::c2d(g, 1e-3, m), u), 1e-9, 1.0));
    }
  }
}

// TFs with finite zeros and direct feedthrough: the force PD of force_dob.yaml with
// its 1 kHz derivative filter (at 2 kHz), a lead-lag, and a PID.
TEST(LowerTf, ZerosAndFeedthrough) {
  struct Case {
    std::string name;
    TransferFunction g;
    double rate_hz;
  };
  const std::vector<Case> cases{
      {"pd", blocks::pd(0.0056, 9.1e-5, 1.0 / (2 * M_PI * 1000.0)), 2000.0},
      {"lead_lag", TransferFunction::parse("3*(s/20 + 1)*(s/300 + 1)/((s/2 + 1)*(s/1500 + 1))"), 1000.0},
      {"pid", blocks::pid(2.0, 15.0, 0.05, 1.0 / (2 * M_PI * 150.0)), 1000.0},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const auto u = chirp(1500, c.rate_hz, 0.5, 0.45 * c.rate_hz);
    for (C2dMethod m : {C2dMethod::Tustin, C2dMethod::Zoh, C2dMethod::BackwardEuler}) {
      SCOPED_TRACE(blocks::to_string(m));
      const LoopProgram p = lower(c.g, "g", at(c.rate_hz, m));
      const auto want = direct_form_1(blocks::c2d(c.g, 1.0 / c.rate_hz, m), u);
      // Relative to the largest output (the PID's integrator grows): 1e-9.
      EXPECT_TRUE(sequences_near(interpret_siso(p, u), want, 1e-9, 1e-3));
    }
  }
}

// Regression (fixed): a biproper 5th-order TF (a real zero at 5 rad/s next to a lightly
// damped 2 Hz pole pair, complex zeros at 100 and 300 Hz, poles at 150 Hz and
// 3000 rad/s) at 1 kHz, Tustin. The 2 Hz pole pair takes the real zero (nearest), the
// 150 Hz pair one complex zero pair, and the other complex zero pair does not fit the
// first-order section of the real pole: it is dropped. Max error 0.34 against an
// output of 1.3 on this chirp (should be ~1e-12).
TEST(LowerTf, BiproperFifthOrderKeepsEveryZero) {
  const TransferFunction g = TransferFunction::parse(
      "(s/5 + 1)*(s^2/w2^2 + 2*0.3*s/w2 + 1)*(s^2/w4^2 + 2*0.4*s/w4 + 1)/"
      "((s^2/w1^2 + 2*0.05*s/w1 + 1)*(s^2/w3^2 + 2*0.2*s/w3 + 1)*(s/3000 + 1))",
      {{"w1", 2 * M_PI * 2.0}, {"w2", 2 * M_PI * 100.0}, {"w3", 2 * M_PI * 150.0}, {"w4", 2 * M_PI * 300.0}});
  const auto u = chirp(3000, 1000.0, 0.5, 450.0);
  const LoopProgram p = lower(g, "g5", at(1000.0));
  EXPECT_TRUE(sequences_near(interpret_siso(p, u), direct_form_1(blocks::c2d(g, 1e-3, C2dMethod::Tustin), u), 1e-9, 1.0));
}

// A TF already in z is realised as given (no second discretisation).
TEST(LowerTf, DiscreteTfAtItsOwnRate) {
  const TransferFunction g = TransferFunction::parse("0.02*(z + 1)*(z - 0.4)/((z^2 - 1.5*z + 0.7)*(z - 0.8))", {}, 0.005);
  const LoopProgram p = lower(g, "dz", at(200.0));
  const auto u = chirp(800, 200.0, 0.2, 90.0);
  EXPECT_TRUE(sequences_near(interpret_siso(p, u), direct_form_1(g, u), 1e-12, 1.0));
  EXPECT_EQ(p.blocks[0].realisation.find("tustin"), std::string::npos) << p.blocks[0].realisation;
}

// A static gain lowers to a single multiply, no state.
TEST(LowerTf, StaticGain) {
  const LoopProgram p = lower(TransferFunction(-2.5), "k", at(100.0));
  EXPECT_TRUE(p.states.empty());
  const auto y = interpret_siso(p, {1.0, -3.0, 0.25});
  EXPECT_EQ(y, (std::vector<double>{-2.5, 7.5, -0.625}));
}

// Float arithmetic of the same program stays within float accuracy of the long-double
// reference: the sections keep the pole accuracy that a direct form would lose.
// Tolerance 2e-5 of full scale: ~100 float ulps (6e-8) of noise gain for an 8th-order
// cascade with poles up to radius 0.93.
TEST(LowerTf, FloatInterpreterWithinFloatAccuracy) {
  const TransferFunction g = blocks::butterworth_lowpass(6, 2 * M_PI * 60.0);
  const LoopProgram p = lower(g, "bw", at(1000.0));
  const auto u = chirp(2000, 1000.0, 0.5, 400.0);
  Sequence in;
  for (double v : u) in.push_back({v});
  std::vector<double> got;
  for (const auto& r : interpret<float>(p, in)) got.push_back(r[0]);
  EXPECT_TRUE(sequences_near(got, direct_form_1(blocks::c2d(g, 1e-3, C2dMethod::Tustin), u), 2e-5, 1.0));
}

// reset() returns the interpreter to the initial state: the same input gives the same
// output bit for bit.
TEST(LowerTf, InterpreterResetRepeats) {
  const LoopProgram p = lower(q_filter(), "q", at(1000.0));
  Interpreter<double> it(p);
  const auto u = chirp(300, 1000.0, 1.0, 200.0);
  std::vector<double> a, b;
  for (double v : u) {
    double y;
    it.step(&v, &y);
    a.push_back(y);
  }
  it.reset();
  for (double v : u) {
    double y;
    it.step(&v, &y);
    b.push_back(y);
  }
  EXPECT_EQ(a, b);
}

}  // namespace
}  // namespace dmbd::codegen
