// The fixed-point error bound (issue 4): truncated L1 norms of impulse responses against
// closed forms, the probed state-space model of a program against its interpreter, the
// bound over a horizon against the bound over any number of steps, and the step-by-step
// check of the bound's hypothesis (no saturation block engaged, no word saturated).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "dmbd/blocks/state_space.hpp"
#include "dmbd/codegen/fixed.hpp"
#include "dmbd/codegen/interpreter.hpp"
#include "dmbd/codegen/verify.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "test_support.hpp"

namespace {

using namespace dmbd;           // NOLINT
using namespace dmbd::codegen;  // NOLINT
using blocks::Matrix;
using blocks::StateSpace;

Matrix scalar(double v) { return Matrix::Constant(1, 1, v); }

TEST(ImpulseL1, IntegratorTruncatedNormIsNTimesB) {
  // y[k] = y[k-1] + b u[k]: h_k = b for every k >= 0, so sum_{k<N} |h_k| = N |b|, and the
  // whole sum is infinite. b = -0.375 and N |b| are exact in double: equality, not a tolerance.
  const double b = -0.375;
  const StateSpace integrator(scalar(1.0), scalar(1.0), scalar(b), scalar(b), 1e-3);
  for (int n : {1, 2, 17, 6000, 20000}) {
    SCOPED_TRACE(n);
    const ImpulseL1 r = impulse_l1(integrator, n);
    EXPECT_EQ(r.truncated(0, 0), n * std::abs(b));
    EXPECT_TRUE(std::isinf(r.infinite(0, 0)));
  }
  EXPECT_EQ(impulse_l1(integrator, 0).truncated(0, 0), 0.0);  // no samples, no sum
}

TEST(ImpulseL1, FirstOrderSectionMatchesTheClosedForm) {
  // x[k+1] = a x[k] + u[k], y = b a x + b u: h_k = b a^k, so
  // sum_{k<N} |h_k| = |b| (1 - |a|^N) / (1 - |a|), and |b| / (1 - |a|) over all k.
  for (double a : {0.9, -0.95, 0.999, 0.0}) {
    for (int n : {1, 5, 100, 6000}) {
      SCOPED_TRACE(::testing::Message() << "a = " << a << ", N = " << n);
      const double b = 2.5;
      const StateSpace s(scalar(a), scalar(1.0), scalar(b * a), scalar(b), 1e-3);
      const ImpulseL1 r = impulse_l1(s, n);
      const double want = std::abs(b) * (1.0 - std::pow(std::abs(a), n)) / (1.0 - std::abs(a));
      // Summing up to 6000 positive terms in double: relative error below 6000 x 2^-53 < 1e-12.
      EXPECT_NEAR(r.truncated(0, 0), want, 1e-12 * want);
      // The whole sum, cut once the state |a|^k is below 1e-13 of its peak: the tail left
      // out is below 1e-13 of the sum; the summation of up to 30000 terms (|a| = 0.999)
      // adds below 30000 x 2^-53 < 4e-12.
      const double all = std::abs(b) / (1.0 - std::abs(a));
      EXPECT_NEAR(r.infinite(0, 0), all, 1e-11 * all);
      EXPECT_LE(r.truncated(0, 0), r.infinite(0, 0));
    }
  }
}

TEST(ImpulseL1, SeveralInputsAndOutputsAreIndependentColumns) {
  // Two decoupled systems side by side (a stable lag and an integrator): each column is
  // its own system's norm, the integrator's column alone infinite, the other finite.
  Matrix a(2, 2), b(2, 2), c(2, 2), d(2, 2);
  a << 0.5, 0.0, 0.0, 1.0;
  b << 1.0, 0.0, 0.0, 1.0;
  c << 1.0, 0.0, 0.0, 1.0;
  d.setZero();
  const ImpulseL1 r = impulse_l1(StateSpace(a, b, c, d, 1e-3), 1000);
  EXPECT_NEAR(r.truncated(0, 0), 2.0, 1e-12);  // sum_{k>=1} 0.5^(k-1)
  EXPECT_EQ(r.truncated(1, 1), 999.0);         // h_0 = 0, then 1 for k = 1..999
  EXPECT_EQ(r.truncated(0, 1), 0.0);
  EXPECT_EQ(r.truncated(1, 0), 0.0);
  EXPECT_NEAR(r.infinite(0, 0), 2.0, 1e-12);
  EXPECT_TRUE(std::isinf(r.infinite(1, 1)));
  EXPECT_EQ(r.infinite(0, 1), 0.0);  // the integrator is not seen by output 0
  EXPECT_EQ(r.infinite(1, 0), 0.0);
}

// The model probed from a program (saturations as identity) reproduces the interpreter's
// impulse responses, for every example: all the memory of a program is in its states.
TEST(ProgramStateSpace, ImpulseResponsesMatchTheInterpreterForEveryExample) {
  for (const std::string& name : {std::string("dob_controller"), std::string("force_dob"), std::string("rfsea_plant"),
                                  std::string("position_potentiometer")}) {
    SCOPED_TRACE(name);
    const auto d = diagrams::Diagram::load(codegen::test::kExamples + "/diagrams/" + name + ".yaml");
    LoopProgram p = lower(*d, codegen::test::at(2000.0));
    for (auto* ops : {&p.output_ops, &p.update_ops})
      for (Op& o : *ops)
        if (o.kind == OpKind::Clamp) o.kind = OpKind::Copy;
    const StateSpace ss = program_state_space(p);
    const size_t ni = p.inputs.size(), no = p.outputs.size();
    for (size_t i = 0; i < ni; ++i) {
      Interpreter<double> it(p);
      blocks::Vector x = blocks::Vector::Zero(ss.num_states());
      std::vector<double> u(ni, 0.0), y(no);
      for (int k = 0; k < 300; ++k) {
        u[i] = k == 0 ? 1.0 : 0.0;
        it.step(u.data(), y.data());
        const blocks::Vector want = ss.c() * x + ss.d().col(static_cast<long>(i)) * u[i];
        x = ss.a() * x + ss.b().col(static_cast<long>(i)) * u[i];
        for (size_t j = 0; j < no; ++j) {
          // Different operation orders: agreement to rounding, relative to the response's size.
          const double scale = 1.0 + std::abs(want(static_cast<long>(j)));
          ASSERT_NEAR(y[j], want(static_cast<long>(j)), 1e-9 * scale) << "input " << i << ", output " << j << ", k " << k;
        }
      }
    }
  }
}

// Injections: one at a program input is that input's own column; one at a state after
// its last writer is a unit change of that state for the next step (B = e_s, D = 0).
TEST(ProgramStateSpace, InjectionsEnterWhereTheSlotIsWritten) {
  const auto d = diagrams::Diagram::load(codegen::test::kExamples + "/diagrams/dob_controller.yaml");
  const LoopProgram p = lower(*d, codegen::test::at(2000.0));
  std::vector<int> at{p.inputs[1]};
  at.insert(at.end(), p.states.begin(), p.states.end());
  const StateSpace plain = program_state_space(p), ss = program_state_space(p, at);
  const long ni = static_cast<long>(p.inputs.size()), nx = ss.num_states();
  ASSERT_EQ(ss.num_inputs(), ni + static_cast<long>(at.size()));
  EXPECT_EQ(ss.a(), plain.a());
  EXPECT_EQ(Matrix(ss.b().leftCols(ni)), plain.b());
  EXPECT_EQ(Matrix(ss.b().col(ni)), Matrix(plain.b().col(1)));
  EXPECT_EQ(Matrix(ss.d().col(ni)), Matrix(plain.d().col(1)));
  for (long s = 0; s < nx; ++s) {
    SCOPED_TRACE(s);
    EXPECT_EQ(Matrix(ss.b().col(ni + 1 + s)), Matrix(Matrix::Identity(nx, nx).col(s)));
    EXPECT_EQ(Matrix(ss.d().col(ni + 1 + s)), Matrix::Zero(ss.num_outputs(), 1));
  }
}

LoopProgram q_filter_program() {
  LowerOptions o;
  o.rate_hz = 1000.0;
  return lower(blocks::TransferFunction::parse("1/((s/wc)^2 + sqrt(2)*s/wc + 1)", {{"wc", 2 * M_PI * 60}}), "q_filter", o);
}

TEST(ErrorBound, OverAHorizonConvergesToTheInfiniteHorizonBoundForAStableFilter) {
  const LoopProgram p = q_filter_program();
  const FixedProgram f = make_fixed(p, {{-1.0, 1.0}}, 32);
  const double all = predicted_error_bound(p, f, {{-1.0, 1.0}}, 1).infinite[0];
  ASSERT_TRUE(std::isfinite(all));
  double last = 0.0;
  for (int n : {1, 2, 5, 10, 20, 50, 100, 1000, 6000, 100000}) {
    SCOPED_TRACE(n);
    const ErrorBound b = predicted_error_bound(p, f, {{-1.0, 1.0}}, n);
    EXPECT_EQ(b.horizon, n);
    // Beyond the decay the tail below 1e-13 of the peak is summed only up to the horizon.
    EXPECT_NEAR(b.infinite[0], all, 1e-12 * all);
    EXPECT_GE(b.over_horizon[0], last);      // more steps, more accumulated error
    EXPECT_LE(b.over_horizon[0], all * (1 + 1e-12));
    EXPECT_NEAR(b.over_horizon[0], b.rounding[0] + b.coefficients[0], 1e-15 * all);
    last = b.over_horizon[0];
    // The 60 Hz poles at 1 kHz decay by 1e-13 within about 150 samples.
    if (n >= 1000) {
      EXPECT_NEAR(b.over_horizon[0], all, 1e-12 * all);
    }
  }
  EXPECT_LT(predicted_error_bound(p, f, {{-1.0, 1.0}}, 5).over_horizon[0], 0.9 * all);
}

TEST(ErrorBound, AnIntegratorsBoundGrowsLinearlyWithTheHorizonAndHolds) {
  // 1/s by Tustin at 100 Hz: rounding errors accumulate, no bound over any number of
  // steps; over N steps the bound grows as N (each step's error can add up).
  LowerOptions o;
  o.rate_hz = 100.0;
  const LoopProgram p = lower(blocks::TransferFunction::parse("1/s"), "integ", o);
  const FixedProgram f = make_fixed(p, {{-1.0, 1.0}}, 32);
  const ErrorBound b1 = predicted_error_bound(p, f, {{-1.0, 1.0}}, 1000), b2 = predicted_error_bound(p, f, {{-1.0, 1.0}}, 2000);
  EXPECT_TRUE(std::isinf(b1.infinite[0]));
  EXPECT_TRUE(std::isfinite(b1.over_horizon[0]));
  EXPECT_NEAR(b2.over_horizon[0] / b1.over_horizon[0], 2.0, 0.01);
  // And it holds on the verification run (its formats from simulated ranges).
  const auto u = verification_inputs(p, {{-1.0, 1.0}});
  const ErrorBound b = predicted_error_bound(p, f, {{-1.0, 1.0}}, static_cast<int>(u.size()));
  const BoundCheck c = check_bound(p, f, u, b.horizon);
  ASSERT_TRUE(c.hypothesis_held());
  EXPECT_GT(c.max_error[0], 0.0);
  EXPECT_LE(c.max_error[0], b.over_horizon[0]);
}

// The hypothesis is checked at every step. dob_controller's inputs span +-8000 N: its
// Q_B Pbar^-1 path alone turns a force step of more than about 620 N into more than the
// 22 A limit at the first sample, so the full-range verification input engages the
// saturation at once; a small enough copy of it does not.
TEST(ErrorBound, TheHypothesisIsCheckedStepByStep) {
  const auto d = diagrams::Diagram::load(codegen::test::kExamples + "/diagrams/dob_controller.yaml");
  const LoopProgram p = lower(*d, codegen::test::at(2000.0));
  const std::vector<std::pair<double, double>> ranges{{-8000.0, 8000.0}, {-8000.0, 8000.0}};
  const FixedProgram f = make_fixed(p, ranges, 32);
  const auto u = verification_inputs(p, ranges);
  const BoundCheck full = check_bound(p, f, u, kVerifySamples);
  EXPECT_FALSE(full.hypothesis_held());
  EXPECT_EQ(full.first_violation, 0);
  EXPECT_EQ(full.covered_steps, 0);
  EXPECT_GT(full.clamp_steps_exact, 1000);
  EXPECT_GT(full.clamp_steps_fixed, 1000);
  EXPECT_EQ(full.saturation_steps, 0);
  EXPECT_GE(full.violation_steps, std::max(full.clamp_steps_exact, full.clamp_steps_fixed));
  // The largest clamp-free scale 2^-k: held there, not at twice it.
  const double s = clamp_free_scale(p, f, u, ranges);
  ASSERT_GT(s, 0.0);
  EXPECT_LT(s, 1.0);
  EXPECT_TRUE(check_bound(p, f, scaled_inputs(u, ranges, s), kVerifySamples).hypothesis_held());
  EXPECT_FALSE(check_bound(p, f, scaled_inputs(u, ranges, 2 * s), kVerifySamples).hypothesis_held());
  // A prefix of the run is covered when the hypothesis breaks later: zero for 100
  // samples, then F_d = 8000 N (its feed-forward alone is 26.9 A).
  std::vector<std::vector<double>> late(200, std::vector<double>{0.0, 0.0});
  for (size_t n = 100; n < late.size(); ++n) late[n] = {8000.0, 0.0};
  const BoundCheck c = check_bound(p, f, late, kVerifySamples);
  EXPECT_EQ(c.first_violation, 100);
  EXPECT_EQ(c.covered_steps, 100);
  // The covered horizon is also cut at the bound's own horizon.
  EXPECT_EQ(check_bound(p, f, scaled_inputs(u, ranges, s), 1000).covered_steps, 1000);
}

TEST(ErrorBound, ScaledInputsStayInTheirRanges) {
  const std::vector<std::vector<double>> u{{-3.0, 5.0, 1.0}, {2.0, 4.0, -1.0}};
  const std::vector<std::pair<double, double>> r{{-3.0, 2.0}, {3.0, 5.0}, {-1.0, 1.0}};
  const auto v = scaled_inputs(u, r, 0.25);
  // Towards 0 for ranges containing it, towards the range's end nearest 0 otherwise.
  EXPECT_EQ(v[0], (std::vector<double>{-0.75, 3.5, 0.25}));
  EXPECT_EQ(v[1], (std::vector<double>{0.5, 3.25, -0.25}));
}

}  // namespace
