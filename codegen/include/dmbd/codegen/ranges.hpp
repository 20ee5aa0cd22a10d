#pragma once
// Guaranteed ranges of every slot of a loop program, for choosing fixed-point formats.
#include <utility>
#include <vector>

#include "dmbd/codegen/loop_program.hpp"

namespace dmbd::codegen {

// Bounds |slot| <= bound for every slot, for inputs within their ranges: the L1 norm
// of the impulse response from each source to the slot times the source's largest
// magnitude, summed over the sources. The sources are the program inputs and the
// outputs of the saturation blocks (a clamp bounds its output whatever its input, so
// it is cut out of the linear analysis and treated as a source of its own). When a
// source's response (all slots together) has not stayed below 1e-12 of its peak for 16
// samples within `max_samples` (an integrator, an unstable loop), every slot it reaches
// gets +infinity. input_ranges: [lo, hi] per program input, in the inputs' order (an
// input without one: [-1, 1]); an input's own bound is max(|lo|, |hi|), a saturation's
// output max(|lo|, |hi|) of its limits. Indexed like LoopProgram::slots.
std::vector<double> slot_bounds(const LoopProgram& p, const std::vector<std::pair<double, double>>& input_ranges,
                                int max_samples = 200000);

// The Q format (fractional bits) of a signed `word_bits`-bit word that holds +-bound
// with one bit of headroom: F = word_bits - 2 - ceil(log2(bound)). May be negative
// (large values) or above word_bits - 1 (small ones). A bound <= 0 (a slot that stays
// 0) gets word_bits - 1; InputError for an infinite bound.
int q_format(double bound, int word_bits);

}  // namespace dmbd::codegen
