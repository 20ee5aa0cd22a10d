// Issue 28, row 10: controller 1 with D_q = 0 (a P-only position loop) was refused by
// lowering ("an improper transfer function has no second-order sections"): the
// derivative block D_q s/(tau s + 1) at D_q = 0 has a zero numerator, whose "zeros at
// infinity" were counted from its degree, -1. It is proper; it lowers now, keeping the
// filter's state (the program's shape does not depend on a parameter's value).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "dmbd/codegen/interpreter.hpp"
#include "dmbd/codegen/loop_program.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "test_support.hpp"

namespace dmbd::codegen {
namespace {

using namespace test;

const std::string kController = kExamples + "/diagrams/position_encoder_controller.yaml";

// i = clamp(k_ff (P_q (q_d - q_m) - 0), -22, 22) with the diagram's values, computed in
// the interpreter's order (each block one rounded product): exact, tolerance 0.
TEST(ZeroParameter, PositionControllerWithoutDerivativeIsItsProportionalLaw) {
  for (C2dMethod m : {C2dMethod::Tustin, C2dMethod::Zoh, C2dMethod::BackwardEuler}) {
    SCOPED_TRACE(blocks::to_string(m));
    const auto d = diagrams::Diagram::load(kController, {{"D_q", 0.0}});
    LowerOptions o = at(1000.0);
    o.method = m;
    const LoopProgram p = lower(*d, o);
    const LoopProgram full = lower(*diagrams::Diagram::load(kController), o);
    EXPECT_EQ(p.states.size(), full.states.size());  // the filter keeps its state
    const double P_q = d->parameters().at("P_q"), k_ff = d->parameters().at("k_ff");
    Sequence in;
    std::vector<double> want;
    for (int k = 0; k < 400; ++k) {
      const double qd = 0.3 * std::sin(0.05 * k), qm = 0.2 * std::cos(0.031 * k) + 1e-4 * k;
      in.push_back({qd, qm});
      want.push_back(std::clamp(k_ff * (P_q * (qd - qm)), -22.0, 22.0));
    }
    const Sequence y = interpret<double>(p, in);
    for (std::size_t k = 0; k < want.size(); ++k) ASSERT_EQ(y[k][0], want[k]) << "sample " << k;
  }
}

// The transfer-function realisation of a zero numerator, continuous and discrete: one
// section per pole, every numerator coefficient 0.
TEST(ZeroParameter, AZeroNumeratorKeepsItsPolesSections) {
  const auto secs = second_order_sections(blocks::c2d(TransferFunction::parse("0*s/(0.01*s + 1)"), 0.001, C2dMethod::Tustin));
  ASSERT_EQ(secs.size(), 1u);
  EXPECT_EQ(secs[0].order, 1);
  EXPECT_EQ(secs[0].b0, 0.0);
  EXPECT_EQ(secs[0].b1, 0.0);
  const LoopProgram p = lower(TransferFunction::parse("0/((s + 1)*(s + 2))"), "zero", at(1000.0));
  EXPECT_EQ(p.states.size(), 2u);
  for (double v : interpret_siso(p, step_input(50))) EXPECT_EQ(v, 0.0);
}

// The command line: `dmbd codegen ... --param D_q=0 --verify` generates and verifies
// (exit 0, max error 0) where it printed the error and exited 2.
TEST(ZeroParameter, CodegenCommandWithTheDerivativeGainAtZero) {
  const std::string dir = fresh_dir("zero_dq");
  const CliResult r = run_cli("codegen '" + kController + "' --rate 1000 --param D_q=0 --out '" + dir + "' --verify", dir);
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.find("improper"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("max |generated - interpreter|"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace dmbd::codegen
