#pragma once
// What quantising a loop program's coefficients does to the loop: its poles and its
// frequency response against the exact program's (the linear parts, saturations taken
// as identity: program_state_space).
#include <vector>

#include "dmbd/blocks/polynomial.hpp"
#include "dmbd/codegen/loop_program.hpp"

namespace dmbd::codegen {

struct QuantisationEffect {
  std::vector<blocks::Complex> poles_exact, poles_quantised;  // z-plane
  // Largest |20 log10 |Hq / H|| (dB) and |arg(Hq / H)| (degrees) over every input-output
  // pair, on 400 log-spaced frequencies from 0.01 Hz to 0.999 x Nyquist; points where
  // either response is exactly zero are left out.
  double max_db = 0.0, max_deg = 0.0;
};

QuantisationEffect quantisation_effect(const LoopProgram& exact, const LoopProgram& quantised);

}  // namespace dmbd::codegen
