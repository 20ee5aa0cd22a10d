#pragma once
// What quantising a loop program's coefficients does to the loop: its poles and its
// frequency response against the exact program's (the linear parts, saturations taken
// as identity: program_state_space).
#include <vector>

#include "dmbd/blocks/polynomial.hpp"
#include "dmbd/codegen/loop_program.hpp"

namespace dmbd::codegen {

// The exact and the quantised program compared (quantisation_effect).
struct QuantisationEffect {
  // The exact program's poles: the eigenvalues of its linear part's A, z-plane.
  std::vector<blocks::Complex> poles_exact, poles_quantised;  // the quantised program's, likewise (z-plane)
  // Largest |20 log10 |Hq / H|| (dB) and |arg(Hq / H)| (degrees) over every input-output
  // pair, on 400 log-spaced frequencies from 0.01 Hz to 0.999 x Nyquist; points where
  // either response is exactly zero are left out.
  double max_db = 0.0, max_deg = 0.0;  // the phase deviation in degrees (see max_db)
};

// The effect of `quantised` (normally FixedProgram::quantised: the same program with
// quantised coefficients) against `exact`; both must have the same inputs and outputs.
// The frequency grid takes its Nyquist frequency from exact.rate_hz. The poles are not
// paired: each list sorted as blocks::StateSpace::poles() sorts it.
QuantisationEffect quantisation_effect(const LoopProgram& exact, const LoopProgram& quantised);

}  // namespace dmbd::codegen
