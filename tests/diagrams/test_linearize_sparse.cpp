// Sparse linearisation of diagrams and their structural analysis (issue 13, items 1
// and 11): loops broken at a plant with integrators give poles exactly at s = 0 or
// z = 1; chains of thousands of blocks give the closed-form poles and DC gain; the
// sparse model equals the dense one.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <filesystem>
#include <string>

#include "dmbd/blocks/siso.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "dmbd/diagrams/linearize.hpp"
#include "chain_diagram.hpp"

namespace dmbd::diagrams {
namespace {

using blocks::Complex;
using blocks::Siso;
using blocks::Stability;

std::shared_ptr<const Diagram> parse(const std::string& yaml) { return Diagram::parse(yaml, "inline.yaml"); }

using dmbd::test::chain_diagram;

// PD on a double integrator built from integrator blocks (issue 13, item 1).
const char* kPdOnMass = R"yaml(
name: pd_mass
parameters: {M: 2.0}
inputs: {r: {}}
outputs: {y: {}}
blocks:
  err: {type: sum, signs: "+-"}
  C:   {type: pd, P: 100, D: 20, tau: 0.001}
  m:   {type: gain, k: 1/M}
  i1:  {type: integrator}
  i2:  {type: integrator}
connections:
  - r -> err.in1
  - err -> C
  - C -> m
  - m -> i1
  - i1 -> i2
  - i2 -> [y, err.in2]
)yaml";

TEST(LinearizeSparse, LoopWithIntegratorsHasExactPolesAtTheOrigin) {
  // Wherever the loop is broken, L = (100 + 20 s/(0.001 s + 1)) / (2 s^2): m = -2
  // exactly (was: poles at 1e-13, a DC gain of -2.8e14 and a 2e-14 Hz bandwidth),
  // k = 50, the filter pole -1000, and the verdict "unstable" (a double integrator).
  const auto d = parse(kPdOnMass);
  for (const char* at : {"C.out", "err.in2", "i1.out", "m.in"}) {
    const Siso s = Siso::from_state_space(loop_transfer_sparse(*d, at));
    EXPECT_EQ(s.zpk().m(), -2) << at;
    EXPECT_NEAR(s.zpk().k(), 50.0, 1e-12 * 50.0) << at;
    ASSERT_EQ(s.zpk().poles().size(), 1u) << at;
    EXPECT_NEAR(s.zpk().poles()[0].real(), -1000.0, 1e-9) << at;
    EXPECT_FALSE(s.zpk().dc_gain().has_value()) << at;
    EXPECT_FALSE(blocks::bandwidth(s.zpk()).has_value()) << at;
    EXPECT_EQ(blocks::stability(s.zpk()), Stability::Unstable) << at;
  }
  // The closed loop r -> y: s^2 (0.001 s + 1) 2 + 20.1 s + 100 = 0 has no pole at the
  // origin; DC gain exactly 1 to rounding; stable.
  const Siso t = Siso::from_state_space(linearize_sparse(*d, "r", "y"));
  EXPECT_EQ(t.zpk().m(), 0);
  EXPECT_NEAR(*t.zpk().dc_gain(), 1.0, 1e-12);
  EXPECT_EQ(blocks::stability(t.zpk()), Stability::Stable);
}

TEST(LinearizeSparse, DiscreteLoopHasItsPoleExactlyAtOne) {
  // The discrete loop of issue 13: an accumulator T/(z - 1) and 0.1 (z - 0.9)/(z - 0.6)
  // / T: L has m = -1 exactly and k = 0.1 (0.1)/(0.4) = 0.025; no phase crossover at
  // DC; the closed loop is stable with DC gain 1.
  const auto d = parse(R"yaml(
name: dloop
sample_time: 0.001
inputs: {r: {}}
outputs: {y: {}}
blocks:
  err: {type: sum, signs: "+-"}
  I:   {type: integrator}
  F:   {type: tf, expr: "100*(z-0.9)/(z-0.6)"}
connections:
  - r -> err.in1
  - err -> I
  - I -> F
  - F -> [y, err.in2]
)yaml");
  const Siso l = Siso::from_state_space(loop_transfer_sparse(*d, "err.out"));
  EXPECT_EQ(l.zpk().m(), -1);
  EXPECT_NEAR(l.zpk().k(), 0.025, 1e-15);
  for (const blocks::Crossing& c : blocks::margins(l.zpk()).phase_crossovers) EXPECT_GT(c.w_rad_s, 0.0);
  const Siso t = Siso::from_state_space(linearize_sparse(*d, "r", "y"));
  EXPECT_EQ(blocks::stability(t.zpk()), Stability::Stable);
  EXPECT_NEAR(*t.zpk().dc_gain(), 1.0, 1e-12);
}

TEST(LinearizeSparse, ChainOfThousandFirstOrderFilters) {
  // 1000 blocks 10/(s + 10): poles exactly -10 (x 1000), no zeros, DC gain 1 (each
  // block's to rounding: 1e-12), 1000 series factors; the sparse model has 1000 states
  // and 1999 non-zeros in A.
  const auto d = parse(chain_diagram(1000, "{type: tf, expr: \"10/(s+10)\"}"));
  const blocks::SparseStateSpace ss = linearize_sparse(*d, "u", "y");
  EXPECT_EQ(ss.num_states(), 1000);
  EXPECT_EQ(ss.a().nonZeros(), 1999);
  const Siso s = Siso::from_state_space(ss);
  EXPECT_EQ(s.factors(), 1000);
  const std::vector<Complex> poles = s.zpk().all_poles();
  ASSERT_EQ(poles.size(), 1000u);
  for (const Complex& p : poles) EXPECT_EQ(p, Complex(-10.0, 0.0));
  EXPECT_TRUE(s.zpk().zeros().empty());
  EXPECT_NEAR(*s.zpk().dc_gain(), 1.0, 1e-12);
}

TEST(LinearizeSparse, ChainOfTenThousandGainsIsOneNumber) {
  // 10000 gains of 1.0001: a static transfer 1.0001^10000 (1e-11 relative: 10^4
  // roundings), no states.
  const auto d = parse(chain_diagram(10000, "{type: gain, k: 1.0001}"));
  const blocks::SparseStateSpace ss = linearize_sparse(*d, "u", "y");
  EXPECT_EQ(ss.num_states(), 0);
  const Siso s = Siso::from_state_space(ss);
  EXPECT_NEAR(*s.zpk().dc_gain(), std::pow(1.0001, 10000), 1e-11 * std::pow(1.0001, 10000));
}

TEST(LinearizeSparse, EqualsTheDenseModel) {
  // linearize() is the sparse model made dense and balanced: the same transfer. The
  // two formulations (structural factors, and the dense TF's roots) agree on poles and
  // DC gain to 1e-9.
  const auto d = parse(kPdOnMass);
  const Siso a = Siso::from_state_space(linearize_sparse(*d, "r", "y"));
  const Siso b = Siso::from_tf(linearize(*d, "r", "y").to_tf());
  ASSERT_EQ(a.zpk().all_poles().size(), b.zpk().all_poles().size());
  for (size_t k = 0; k < a.zpk().all_poles().size(); ++k)
    EXPECT_NEAR(std::abs(a.zpk().all_poles()[k] - b.zpk().all_poles()[k]), 0.0,
                1e-9 * std::abs(b.zpk().all_poles()[k]));
  EXPECT_NEAR(*a.zpk().dc_gain(), *b.zpk().dc_gain(), 1e-9);
}

// G(x) of a dense model by one complex solve: the reference formulation.
Complex dense_response(const blocks::StateSpace& s, Complex x) {
  const auto n = s.num_states();
  const Eigen::MatrixXcd m = x * Eigen::MatrixXcd::Identity(n, n) - s.a().cast<Complex>();
  const Eigen::VectorXcd v = Eigen::PartialPivLU<Eigen::MatrixXcd>(m).solve(s.b().cast<Complex>());
  return (s.c().cast<Complex>() * v)(0, 0) + s.d()(0, 0);
}

TEST(LinearizeSparse, EveryExampleTransferEqualsTheDenseResponse) {
  // Two formulations on every input -> output transfer of the shipped examples: the
  // factored form of Siso (zeros, poles, k; hidden modes dropped) against the dense
  // model's c (xI - A)^-1 b + d, at 0.01 .. 3000 rad/s (below Nyquist when discrete).
  // 1e-8 relative, plus 1e-10 of the largest |G| seen: the dense solve loses digits on
  // these stiff actuators (a 9.5e6 N/m spring beside 1/J_m), most where |G| is far
  // below its peak (c v then cancels terms of the peak's size: 1e-11 absolute at 3000
  // rad/s on a transfer of DC gain -1). Before the linearisation zeroed sums that cancel
  // to rounding, the DOB's F_m -> i lost its integrator (1 - Q_A) to a 1e-14 entry.
  int checked = 0;
  for (const auto& entry : std::filesystem::directory_iterator(DMBD_EXAMPLES "/diagrams")) {
    const auto d = Diagram::load(entry.path().string());
    for (const auto& in : d->inputs())
      for (const auto& out : d->outputs()) {
        if (in.size != 1 || out.size != 1) continue;
        const blocks::StateSpace dense = linearize(*d, in.name, out.name);
        const Siso s = Siso::from_state_space(linearize_sparse(*d, in.name, out.name));
        std::vector<std::pair<double, Complex>> want;
        double peak = 0.0;
        for (double w : {0.01, 0.3, 3.0, 30.0, 300.0, 3000.0}) {
          if (d->is_discrete() && w * d->ts() > 3.0) continue;
          const Complex x = d->is_discrete() ? std::exp(Complex(0.0, w * d->ts())) : Complex(0.0, w);
          want.emplace_back(w, dense_response(dense, x));
          peak = std::max(peak, std::abs(want.back().second));
        }
        for (const auto& [w, g] : want) {
          const Complex got = std::exp(s.zpk().log_response(w));
          EXPECT_LE(std::abs(got - g), 1e-8 * std::abs(g) + 1e-10 * peak)
              << entry.path().filename() << " " << in.name << " -> " << out.name << " at " << w << ": " << got << " vs "
              << g;
        }
        ++checked;
      }
  }
  EXPECT_GE(checked, 25);
}

TEST(LinearizeSparse, DisturbanceObserverHasItsIntegrator) {
  // dob_controller: u (1 - Q_A) = u_r - Q_B Pbar^-1 F_m, and 1 - Q_A = s (s + sqrt2 wc)
  // / (s^2 + sqrt2 wc s + wc^2): F_m -> i has one pole exactly at s = 0 (Q_A's second
  // state is its own group once A_Q + B_Q C_Q cancels exactly), DC gain infinite.
  const auto d = Diagram::load(DMBD_EXAMPLES "/diagrams/dob_controller.yaml");
  const Siso s = Siso::from_state_space(linearize_sparse(*d, "F_m", "i"));
  EXPECT_EQ(s.zpk().m(), -1);
  EXPECT_FALSE(s.zpk().dc_gain().has_value());
  EXPECT_EQ(blocks::stability(s.zpk()), Stability::Marginal);
}

}  // namespace
}  // namespace dmbd::diagrams
