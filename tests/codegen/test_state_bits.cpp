// Wider states in a 16-bit program (issue 28, row 12): a P position loop around a PI
// velocity loop (tests/codegen/data/pi_position_loop.yaml) in 16-bit words. With every
// word 16 bits the PI's integrator state gets a coarse format (Q3, 1/8 N m) from its
// simulated range: a small velocity error no longer moves it, and the predicted error
// bound exceeds the output's whole range. The range analysis widens the state update's
// words to 32 bits; the program then meets its own bound, far below the output range.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "dmbd/blocks/error.hpp"
#include "dmbd/codegen/emit.hpp"
#include "dmbd/codegen/emit_c.hpp"
#include "dmbd/codegen/fixed.hpp"
#include "dmbd/codegen/interpreter.hpp"
#include "dmbd/codegen/verify.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "test_support.hpp"

namespace {

using namespace dmbd;           // NOLINT
using namespace dmbd::codegen;  // NOLINT

struct PiLoop {
  LoopProgram p;
  std::vector<std::pair<double, double>> ranges{{-1.07, 1.07}, {-1.07, 1.07}, {-10.0, 10.0}};  // q_d, q, qd
  double output_range = 100.0;  // tau, N m
};

PiLoop pi_loop() {
  const auto d = diagrams::Diagram::load(test::kData + "/pi_position_loop.yaml");
  return {lower(*d, test::at(2000.0))};
}

int slot(const LoopProgram& p, const std::string& name) {
  for (size_t k = 0; k < p.slots.size(); ++k)
    if (p.slots[k].name == name) return static_cast<int>(k);
  ADD_FAILURE() << "no slot " << name;
  return 0;
}

// Max |fixed - exact| of the output over a run of constant inputs from reset.
double constant_input_error(const PiLoop& l, const FixedProgram& f, const std::vector<double>& u, int steps) {
  Interpreter<double> exact(l.p);
  FixedInterpreter fixed(l.p, f);
  double e = 0.0, ye = 0.0, yf = 0.0;
  for (int n = 0; n < steps; ++n) {
    exact.step(u.data(), &ye);
    fixed.step_real(u.data(), &yf);
    e = std::max(e, std::abs(yf - ye));
  }
  return e;
}

TEST(StateBits, PiInPLoopMeetsItsOwnBoundIn16Bits) {
  const PiLoop l = pi_loop();
  const FixedProgram narrow = make_fixed(l.p, l.ranges, 16, 16), wide = make_fixed(l.p, l.ranges, 16);
  const auto s1 = static_cast<size_t>(slot(l.p, "PI_s1")), out = static_cast<size_t>(l.p.outputs[0]);
  // Before: the integrator state in Q3 (its simulated range 1698 N m), the bound over
  // the 6000-step verification horizon (847 N m measured) beyond the output's range.
  EXPECT_EQ(narrow.bits[s1], 16);
  EXPECT_EQ(narrow.q[s1], 3);
  const ErrorBound before = predicted_error_bound(l.p, narrow, l.ranges, kVerifySamples);
  EXPECT_GT(before.over_horizon[0], l.output_range);
  // After: the state (and the signals the state update reads) in 32-bit words, Q19;
  // inputs and output keep their 16-bit words and formats.
  EXPECT_EQ(wide.word_bits, 16);
  EXPECT_EQ(wide.bits[s1], 32);
  EXPECT_EQ(wide.q[s1], 19);
  EXPECT_EQ(wide.bits[out], 16);
  EXPECT_EQ(wide.q[out], narrow.q[out]);
  for (int k : l.p.inputs) EXPECT_EQ(wide.bits[static_cast<size_t>(k)], 16);
  // The bound: 1.49 N m measured, below 2 % of the output range (margin 50).
  const ErrorBound after = predicted_error_bound(l.p, wide, l.ranges, kVerifySamples);
  EXPECT_LT(after.over_horizon[0], l.output_range / 50.0);
  EXPECT_GT(after.over_horizon[0], 0.0);
  // Met on the verification input where the bound's hypothesis holds (the largest
  // clamp-free scaled copy of the chirp and step): max error 0.048 N m measured.
  const auto u = verification_inputs(l.p, l.ranges);
  const double s = clamp_free_scale(l.p, wide, u, l.ranges);
  ASSERT_GT(s, 0.0);
  const BoundCheck c = check_bound(l.p, wide, scaled_inputs(u, l.ranges, s), kVerifySamples);
  ASSERT_TRUE(c.hypothesis_held());
  EXPECT_GT(c.max_error[0], 0.0);
  EXPECT_LE(c.max_error[0], after.over_horizon[0]);
  // The 16-bit program is no worse: its own (much larger) bound holds too.
  const BoundCheck cn = check_bound(l.p, narrow, scaled_inputs(u, l.ranges, clamp_free_scale(l.p, narrow, u, l.ranges)),
                                    kVerifySamples);
  ASSERT_TRUE(cn.hypothesis_held());
  EXPECT_LE(cn.max_error[0], before.over_horizon[0]);
  EXPECT_GT(cn.max_error[0], 10.0 * c.max_error[0]);
}

TEST(StateBits, TheIntegratorFollowsASmallVelocityError) {
  // A constant position error of 16/8192 rad (exact in the inputs' Q13; times K_q = 30,
  // exact in the velocity command's Q8) and qd = 0: the exact torque ramps as
  // K_v e + K_i e t, e = 0.05859375 rad/s, to 10.5 N m in 3 s, within the limits. With a
  // 16-bit state each step's increment K_i e T = 1.8e-3 N m is below half its LSB
  // (1/16 N m): the integrator stands still and the error grows with the ramp (10.5 N m
  // measured). With the widened state (Q19) the error stays at about the output's own
  // resolution, LSB 2^-7 = 7.8e-3 N m (8.3e-3 measured): half an LSB of the output's
  // rounding plus at most 2^-20 N m per step of the state's, over 6000 steps 5.7e-3.
  const PiLoop l = pi_loop();
  const FixedProgram narrow = make_fixed(l.p, l.ranges, 16, 16), wide = make_fixed(l.p, l.ranges, 16);
  const std::vector<double> u{0.5, 0.5 - 16.0 / 8192.0, 0.0};
  const double e16 = constant_input_error(l, narrow, u, kVerifySamples);
  const double e32 = constant_input_error(l, wide, u, kVerifySamples);
  EXPECT_GT(e16, 5.0);   // stuck: about the ramp's 10.5 N m
  EXPECT_LT(e32, 0.01);  // 3.9e-3 + 5.7e-3 at most
  const ErrorBound b = predicted_error_bound(l.p, wide, l.ranges, kVerifySamples);
  EXPECT_LE(e32, b.over_horizon[0]);
}

TEST(StateBits, StatesGetWiderWordsOnlyWhenTheAnalysisNeedsThem) {
  const PiLoop l = pi_loop();
  const auto s1 = static_cast<size_t>(slot(l.p, "PI_s1"));
  // Forced 32: every state and every signal the state update reads; never a port.
  const FixedProgram all = make_fixed(l.p, l.ranges, 16, 32);
  for (int s : l.p.states) EXPECT_EQ(all.bits[static_cast<size_t>(s)], 32);
  for (const Op& o : l.p.update_ops) {
    if (l.p.slots[static_cast<size_t>(o.a)].kind == SlotKind::Signal) {
      EXPECT_EQ(all.bits[static_cast<size_t>(o.a)], 32);
    }
  }
  for (int k : l.p.inputs) EXPECT_EQ(all.bits[static_cast<size_t>(k)], 16);
  for (int k : l.p.outputs) EXPECT_EQ(all.bits[static_cast<size_t>(k)], 16);
  // Auto picks the state here; a signal outside the state update stays 16-bit.
  const FixedProgram autow = make_fixed(l.p, l.ranges, 16);
  EXPECT_EQ(autow.bits[s1], 32);
  EXPECT_EQ(autow.bits[static_cast<size_t>(slot(l.p, "pos_err_out"))], 16);
  // A program without state has no recursion to widen: all 16 bits.
  const auto pd = diagrams::Diagram::load(test::kExamples + "/diagrams/joint_pd_torque.yaml");
  const LoopProgram q = lower(*pd, test::at(2000.0));
  std::vector<std::pair<double, double>> r;
  for (const auto& in : pd->inputs()) r.push_back(*in.range);
  const FixedProgram flat = make_fixed(q, r, 16);
  EXPECT_EQ(flat.bits, std::vector<int>(q.slots.size(), 16));
  // 32-bit programs keep 32-bit words (no 128-bit accumulator for 64-bit states).
  const FixedProgram w32 = make_fixed(l.p, l.ranges, 32);
  EXPECT_EQ(w32.bits, std::vector<int>(l.p.slots.size(), 32));
  EXPECT_THROW(make_fixed(l.p, l.ranges, 32, 64), InputError);
  EXPECT_THROW(make_fixed(l.p, l.ranges, 32, 16), InputError);
  EXPECT_THROW(make_fixed(l.p, l.ranges, 16, 24), InputError);
}

TEST(StateBits, MixedWordsCompileCleanAndMatchTheInterpreterBitForBit) {
  const PiLoop l = pi_loop();
  const FixedProgram f = make_fixed(l.p, l.ranges, 16);
  const std::string dir = test::fresh_dir("state_bits");
  const std::string hpp = dir + "/pi_position_loop.hpp";
  std::ofstream(hpp) << emit_fixed_header(l.p, f, {Scalar::Double, "pi_position_loop.yaml"});
  const VerifyResult v = verify(l.p, Scalar::Double, hpp, dir + "/cpp", l.ranges, &f);
  EXPECT_EQ(v.max_abs_error, 0.0);
  EXPECT_EQ(v.clamp_free.max_vs_interpreter, 0.0);
  const CFiles c = emit_fixed_c(l.p, f, {Scalar::Double, "pi_position_loop.yaml"});
  std::filesystem::create_directories(dir + "/c");
  std::ofstream(dir + "/c/pi_position_loop.h") << c.header;
  std::ofstream(dir + "/c/pi_position_loop.c") << c.source;
  const VerifyResult vc = verify(l.p, Scalar::Double, dir + "/c/pi_position_loop.h", dir + "/c/work", l.ranges, &f, Language::C);
  EXPECT_EQ(vc.max_abs_error, 0.0);
  // Readable: the state is a 32-bit member, its statements say which block they are.
  const std::string text = emit_fixed_header(l.p, f, {Scalar::Double, "x"});
  EXPECT_NE(text.find("fx::Word32 PI_s1_;  // PI, Q19"), std::string::npos);
  EXPECT_NE(text.find("16-bit fixed point, 32-bit states"), std::string::npos);
  EXPECT_NE(text.find("// PI (pid: P: K_v, I: K_i)"), std::string::npos);
  EXPECT_NE(text.find("fx::convert32_16(fx::clamp32(PI_out"), std::string::npos);
}

}  // namespace
