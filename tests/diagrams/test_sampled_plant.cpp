// Sampled-data loops: a continuous subsystem inside a discrete diagram is a sampled
// plant (zero-order hold, sampler, its boundary delays exact). The loop's margins are
// checked against the loop discretised by hand from the modified z-transform (the
// margins by another formulation too: polynomial roots on the rational function, not
// the certified isolation on the diagram's zeros and poles).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "dmbd/blocks/frequency.hpp"
#include "dmbd/blocks/siso.hpp"
#include "dmbd/blocks/transfer_function.hpp"
#include "dmbd/blocks/zpk.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "dmbd/diagrams/linearize.hpp"

namespace dmbd::diagrams {
namespace {

namespace b = dmbd::blocks;

const std::string kData = std::string(DMBD_TEST_DATA) + "/sampled/";

// motor_loop.yaml's loop at C.out written out by hand: the motor 1/(J s^2 + B s) =
// (1/B)(1/s - 1/(s + a)), a = B/J, behind a hold and an input delay theta < T has
//   1/s:      ((T - theta) z + theta) / (z (z - 1))
//   1/(s+a):  ((1 - e^{-a m T}) z + (e^{-a m T} - e^{-a T})) / (a z (z - e^{-a T})),  m = 1 - theta/T
// (Franklin, Powell, Workman, modified z-transforms); the PD by Tustin,
// s = (2/T)(z - 1)/(z + 1); the measurement z^-1.
b::TransferFunction hand_loop(double P, double D, double tau, double J, double B, double theta, double T) {
  const b::ParameterMap p{{"P", P}, {"D", D}, {"tau", tau}, {"J", J}, {"B", B}, {"th", theta}, {"T", T},
                          {"a", B / J}, {"m", 1.0 - theta / T}};
  const auto tf = [&](const char* e) { return b::TransferFunction::parse(e, p, T); };
  const b::TransferFunction h1 = tf("((T - th)*z + th)/(z*(z - 1))");
  const b::TransferFunction h2 = tf("((1 - exp(-a*m*T))*z + (exp(-a*m*T) - exp(-a*T)))/(a*z*(z - exp(-a*T)))");
  const b::TransferFunction plant = (h1 - h2) * tf("1/B");
  const b::TransferFunction pd = tf("P + D*(2/T)*(z - 1)/(tau*(2/T)*(z - 1) + (z + 1))");
  return pd * plant * tf("1/z");
}

b::Siso loop_at(const std::string& file, const std::string& at, const b::ParameterMap& params = {}) {
  return b::Siso::from_state_space(loop_transfer_sparse(*Diagram::load(kData + file, params), at));
}

void expect_same_margins(const b::Margins& got, const b::Margins& want, double rel) {
  ASSERT_TRUE(got.gain_margin_db && want.gain_margin_db && got.phase_margin_deg && want.phase_margin_deg);
  EXPECT_NEAR(*got.gain_margin_db, *want.gain_margin_db, rel * std::abs(*want.gain_margin_db));
  EXPECT_NEAR(*got.phase_margin_deg, *want.phase_margin_deg, rel * std::abs(*want.phase_margin_deg));
  EXPECT_NEAR(*got.phase_crossover_rad_s, *want.phase_crossover_rad_s, rel * *want.phase_crossover_rad_s);
  EXPECT_NEAR(*got.gain_crossover_rad_s, *want.gain_crossover_rad_s, rel * *want.gain_crossover_rad_s);
}

TEST(SampledPlant, LoopMarginsMatchTheHandDiscretisedLoop) {
  for (const double theta : {0.0004, 0.0, 0.00095}) {
    const b::Siso diagram = loop_at("motor_loop.yaml", "C.out", {{"T_in", theta}});
    const b::TransferFunction hand = hand_loop(40, 1.2, 0.002, 0.02, 0.1, theta, 0.001);
    // Two margin algorithms on two constructions of the same loop: 1e-7 relative (the
    // crossovers are refined by Newton steps on the response in both).
    expect_same_margins(b::margins(diagram.zpk()), b::margins(hand), 1e-7);
    for (const double w : {1.0, 30.0, 700.0, 3000.0}) {
      const b::Complex z = std::exp(b::Complex(0.0, w * 0.001));
      const b::Complex want = hand.evaluate(z), got = std::exp(diagram.zpk().log_response(w));
      EXPECT_NEAR(std::abs(got - want), 0.0, 1e-9 * std::abs(want)) << "theta " << theta << ", w " << w;
    }
  }
}

TEST(SampledPlant, TheDelayIsWhatMovesTheMargins) {
  // Without the 0.4 ms the hold alone lags the loop; with it, the phase margin drops by
  // about w_c * 0.4 ms (in degrees), and the gain margin too. A check that the delay is
  // not dropped on the way: the figures must differ by that much.
  const b::Margins with = b::margins(loop_at("motor_loop.yaml", "C.out").zpk());
  const b::Margins without = b::margins(loop_at("motor_loop.yaml", "C.out", {{"T_in", 0.0}}).zpk());
  const double expected_deg = *with.gain_crossover_rad_s * 0.0004 * 180.0 / M_PI;
  // The crossover itself moves a little: 10 % of the expected drop.
  EXPECT_NEAR(*without.phase_margin_deg - *with.phase_margin_deg, expected_deg, 0.1 * expected_deg);
  EXPECT_GT(*without.gain_margin_db, *with.gain_margin_db + 0.1);
}

TEST(SampledPlant, ASisoPlantsOutputDelayIsItsInputDelay) {
  // The same motor with the delay after it: delays commute in a SISO plant, so the
  // sampled model, and the loop, are the same (to rounding).
  const b::Siso in = loop_at("motor_loop.yaml", "C.out");
  const std::string text =
      "name: motor_loop_out\nsample_time: 0.001\ninputs:\n  q_d: {}\noutputs:\n  q: {}\nblocks:\n"
      "  err: {type: sum, signs: \"+-\"}\n  C: {type: pd, P: 40, D: 1.2, tau: 0.002}\n"
      "  plant: {type: subsystem, file: motor_plant_output_delay.yaml}\n  meas: {type: delay, samples: 1}\n"
      "connections:\n  - q_d -> err.in1\n  - err -> C\n  - C -> plant\n  - plant -> [q, meas]\n"
      "  - meas -> err.in2\n";
  const auto out_diagram = Diagram::parse(text, kData + "motor_loop_out.yaml");
  const b::Siso out = b::Siso::from_state_space(loop_transfer_sparse(*out_diagram, "C.out"));
  expect_same_margins(b::margins(out.zpk()), b::margins(in.zpk()), 1e-9);
  const Block& plant = out_diagram->blocks()[static_cast<size_t>(out_diagram->find_block("plant"))];
  EXPECT_TRUE(plant.sampled);
  ASSERT_EQ(plant.input_delays_s.size(), 1u);
  EXPECT_DOUBLE_EQ(plant.input_delays_s[0], 0.0004);
  EXPECT_EQ(plant.model.num_states(), 3);  // the motor's two states and u[k-1] for the 0.4 of a period
  EXPECT_TRUE(plant.model.is_discrete());
}

TEST(SampledPlant, DelaysItCannotSampleExactlyAreErrorsAtTheDelayBlock) {
  const auto message = [](const std::string& file) {
    try {
      Diagram::load(kData + file);
    } catch (const DiagramError& e) {
      return std::string(e.what());
    }
    return std::string("loaded");
  };
  const std::string inner = message("loop_inner_delay_plant.yaml");
  EXPECT_NE(inner.find("inner_delay_plant.yaml:10:3: error: delay 'late' inside sampled plant 'plant' is not at one of "
                       "its inputs or outputs"),
            std::string::npos)
      << inner;
  const std::string mimo = message("loop_mimo_fraction_plant.yaml");
  EXPECT_NE(mimo.find("mimo_fraction_plant.yaml:10:3: error: delay 'late' of 0.0005 s at output 'y2' of sampled plant "
                      "'plant' is not a whole number of periods of 0.001 s"),
            std::string::npos)
      << mimo;
}

TEST(SampledPlant, LinearizeIoStacksEveryInputAndOutput) {
  // The paper's RFSEA (2 inputs, 6 outputs, continuous): linearize_io's columns and rows
  // are the single-signal models, input by input and output by output.
  const auto d = Diagram::load(std::string(DMBD_EXAMPLES) + "/diagrams/rfsea_plant.yaml");
  const b::StateSpace all = linearize_io(*d);
  ASSERT_EQ(all.num_inputs(), 2);
  ASSERT_EQ(all.num_outputs(), 6);
  for (int i = 0; i < 2; ++i)
    for (int o = 0; o < 6; ++o) {
      const b::StateSpace one = linearize(*d, d->inputs()[static_cast<size_t>(i)].name, d->outputs()[static_cast<size_t>(o)].name);
      for (const double w : {3.0, 300.0, 30000.0}) {
        const b::Complex s(0.0, w);
        const b::Complex want = one.evaluate(s)(0, 0), got = all.evaluate(s)(o, i);
        // Balanced realisations of a stiff model (9.5e6 N/m next to 2953 kg): 1e-9 relative.
        EXPECT_NEAR(std::abs(got - want), 0.0, 1e-9 * std::abs(want) + 1e-300) << i << " -> " << o << " at " << w;
      }
    }
}

}  // namespace
}  // namespace dmbd::diagrams
