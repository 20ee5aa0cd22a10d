#include "sampled_plant.hpp"

#include <cmath>
#include <set>
#include <string>

#include "dmbd/base/number_text.hpp"
#include "dmbd/blocks/sampled.hpp"
#include "dmbd/diagrams/linearize.hpp"

namespace dmbd::diagrams {

namespace b = dmbd::blocks;

std::shared_ptr<const Diagram> with_wires(const Diagram& d, const std::vector<int>& delay_blocks) {
  auto copy = std::make_shared<Diagram>(d);
  for (int k : delay_blocks) {
    Block& bl = copy->blocks_[static_cast<size_t>(k)];
    bl.model = b::StateSpace::gain(b::Matrix::Identity(1, 1));
    bl.tf = b::TransferFunction(1.0);
    bl.delay_s = 0.0;
    bl.feedthrough = {true};
  }
  return copy;
}

namespace {

bool is_delay(const Block& bl) { return bl.type == BlockType::Delay && bl.delay_s > 0.0; }

Diagnostic inner_delay(const Block& bl, const std::string& plant) {
  return {bl.where, "delay '" + bl.name + "' inside sampled plant '" + plant +
                        "' is not at one of its inputs or outputs: its sampled-data model would not be exact; move it "
                        "to the plant's input or output (or into the controller, in whole samples)"};
}

// How many block inputs and how many diagram outputs read `src`, and the last block
// reading it.
struct Readers {
  int blocks = 0, outputs = 0, block = -1;
};
Readers readers_of(const Diagram& d, Source src) {
  Readers r;
  for (size_t bi = 0; bi < d.blocks().size(); ++bi)
    for (const Source& s : d.drivers(static_cast<int>(bi)))
      if (s == src) ++r.blocks, r.block = static_cast<int>(bi);
  for (size_t o = 0; o < d.outputs().size(); ++o)
    if (d.output_driver(static_cast<int>(o)) == src) ++r.outputs;
  return r;
}

// Delays below the top of the plant, in its subsystems: never at its boundary.
void refuse_inner_delays(const Diagram& d, const std::string& plant, std::vector<Diagnostic>& errors) {
  for (const Block& bl : d.blocks()) {
    if (bl.type == BlockType::Subsystem && bl.subsystem) refuse_inner_delays(*bl.subsystem, plant, errors);
    if (is_delay(bl))
      errors.push_back(inner_delay(bl, plant));
  }
}

}  // namespace

SampledPlant sample_plant(const Diagram& plant, double ts, const std::string& name) {
  const int ni = static_cast<int>(plant.inputs().size()), no = static_cast<int>(plant.outputs().size());
  std::vector<double> in_delay(static_cast<size_t>(ni), 0.0), out_delay(static_cast<size_t>(no), 0.0);
  std::vector<Diagnostic> errors;
  // A delay that alone reads a plant input is that input's dead time.
  std::set<int> at_boundary;
  for (int j = 0; j < ni; ++j) {
    const Readers r = readers_of(plant, {-1, j});
    if (r.blocks == 1 && r.outputs == 0 && is_delay(plant.blocks()[static_cast<size_t>(r.block)])) {
      in_delay[static_cast<size_t>(j)] = plant.blocks()[static_cast<size_t>(r.block)].delay_s;
      at_boundary.insert(r.block);
    }
  }
  // A delay read only by plant outputs is their dead time.
  for (size_t bi = 0; bi < plant.blocks().size(); ++bi) {
    const Block& bl = plant.blocks()[bi];
    if (!is_delay(bl) || at_boundary.count(static_cast<int>(bi))) continue;
    const Source src{static_cast<int>(bi), 0};
    const Readers r = readers_of(plant, src);
    if (r.blocks > 0 || r.outputs == 0) {
      errors.push_back(inner_delay(bl, name));
      continue;
    }
    for (int o = 0; o < no; ++o)
      if (plant.output_driver(o) == src) out_delay[static_cast<size_t>(o)] = bl.delay_s;
    at_boundary.insert(static_cast<int>(bi));
  }
  for (const Block& bl : plant.blocks())
    if (bl.type == BlockType::Subsystem && bl.subsystem) refuse_inner_delays(*bl.subsystem, name, errors);
  // A SISO plant's output delay commutes to its input, where any length is exact.
  const bool siso = ni == 1 && no == 1 && plant.inputs()[0].size == 1 && plant.outputs()[0].size == 1;
  if (siso) in_delay[0] += out_delay[0], out_delay[0] = 0.0;
  std::vector<int> out_samples, out_periods;  // per scalar output entry; per output
  for (int o = 0; o < no; ++o) {
    const auto n = b::whole_samples(out_delay[static_cast<size_t>(o)], ts);
    if (!n) {
      const Block& bl = plant.blocks()[static_cast<size_t>(plant.output_driver(o).block)];
      errors.push_back({bl.where, "delay '" + bl.name + "' of " + number_text(bl.delay_s) + " s at output '" +
                                      plant.outputs()[static_cast<size_t>(o)].name + "' of sampled plant '" + name +
                                      "' is not a whole number of periods of " + number_text(ts) +
                                      " s: with several inputs or outputs only an input delay may hold a fraction of "
                                      "a period"});
      continue;
    }
    out_periods.push_back(*n);
    for (int k = 0; k < plant.outputs()[static_cast<size_t>(o)].size; ++k) out_samples.push_back(*n);
  }
  if (!errors.empty()) throw DiagramError(errors);
  const std::vector<int> wired(at_boundary.begin(), at_boundary.end());
  std::vector<double> columns;
  for (int j = 0; j < ni; ++j)
    for (int k = 0; k < plant.inputs()[static_cast<size_t>(j)].size; ++k) columns.push_back(in_delay[static_cast<size_t>(j)]);
  SampledPlant s;
  s.model = b::c2d_zoh_delayed(linearize_io(*with_wires(plant, wired)), ts, columns, out_samples);
  s.input_delays_s = in_delay;
  s.output_delay_samples = out_periods;
  return s;
}

}  // namespace dmbd::diagrams
