// examples/diagrams/joint_impedance_controller.yaml (issue 15): controller 1 with rate
// and feedforward-force inputs. With qd_d = 0 and F_ff = 0 it must be controller 1
// (position_encoder_controller.yaml) from either of the inputs they share: the two
// diagrams' responses agree at every frequency (1e-12 relative, two linearisations of
// different block structures); the new inputs act as D_q/(k_τ N_m) and 1/(k_τ N_m)
// (static gains, exactly as the parameters give them).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "dmbd/blocks/state_space.hpp"
#include "dmbd/diagrams/linearize.hpp"

namespace {

using namespace dmbd::diagrams;  // NOLINT

const std::string kDir = DMBD_EXAMPLES "/diagrams/";

std::complex<double> response(const dmbd::blocks::StateSpace& g, double f_hz) {
  return g.evaluate(std::complex<double>(0.0, 2.0 * M_PI * f_hz))(0, 0);
}

TEST(JointImpedanceDiagram, IsController1WithoutRateAndFeedforward) {
  const auto ext = Diagram::load(kDir + "joint_impedance_controller.yaml");
  const auto c1 = Diagram::load(kDir + "position_encoder_controller.yaml");
  for (const char* from : {"q_d", "q_m"}) {
    const auto a = linearize(*ext, from, "i"), b = linearize(*c1, from, "i");
    for (double f : {0.0, 0.1, 1.0, 10.0, 100.0, 1000.0}) {
      const std::complex<double> ra = response(a, f), rb = response(b, f);
      EXPECT_LT(std::abs(ra - rb), 1e-12 * std::abs(rb)) << from << " at " << f << " Hz";
    }
  }
}

TEST(JointImpedanceDiagram, RateAndFeedforwardInputsAreTheirStaticGains) {
  const auto ext = Diagram::load(kDir + "joint_impedance_controller.yaml", {{"P_q", 1000.0}, {"D_q", 250.0}});
  const double k_ff = 1.0 / (0.0448 * 6632);
  for (double f : {0.0, 5.0, 500.0}) {
    EXPECT_NEAR(std::abs(response(linearize(*ext, "qd_d", "i"), f) - 250.0 * k_ff), 0.0, 1e-12 * 250.0 * k_ff);
    EXPECT_NEAR(std::abs(response(linearize(*ext, "F_ff", "i"), f) - k_ff), 0.0, 1e-12 * k_ff);
  }
}

}  // namespace
