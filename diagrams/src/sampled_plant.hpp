#pragma once
// A continuous diagram inside a discrete one: a sampled plant, one block whose model is
// the exact sampled-data model at the discrete diagram's period (zero-order hold at
// its inputs, outputs read at k ts; blocks::c2d_zoh_delayed). Internal to diagrams/.
#include <memory>
#include <vector>

#include "dmbd/blocks/state_space.hpp"
#include "dmbd/diagrams/diagram.hpp"

namespace dmbd::diagrams {

// The sampled-data model of a continuous diagram and the dead times it kept exact.
struct SampledPlant {
  blocks::StateSpace model;                // discrete at ts: the plant's inputs stacked -> outputs stacked
  std::vector<double> input_delays_s;      // per input port
  std::vector<int> output_delay_samples;   // per output port
};

// The model of `plant` (continuous) at ts > 0, `name` the subsystem block's name for
// messages. A delay block that is the only reader of a plant input is that input's dead
// time (any length: a fraction of a period is exact); one that only drives plant outputs
// is their dead time, in whole periods (a SISO plant moves it to its input, where any
// length is exact). Every other delay would make the model inexact: DiagramError at the
// delay block, saying where to move it.
SampledPlant sample_plant(const Diagram& plant, double ts, const std::string& name);

// A copy of d with the given delay blocks (indices into d.blocks()) made wires.
std::shared_ptr<const Diagram> with_wires(const Diagram& d, const std::vector<int>& delay_blocks);

}  // namespace dmbd::diagrams
