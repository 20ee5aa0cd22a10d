#pragma once
// The loop program: the small discrete-time IR that a diagram is lowered to once, and
// that both the C++ emitter and the in-process interpreter consume, so that the loop
// that is simulated is the loop that is shipped (design.md).
//
// A program is a list of scalar slots (inputs, outputs, signals, states) and two
// ordered lists of operations: `output_ops` compute every signal and output of a step
// from the inputs and the states; `update_ops` then advance the states. Every slot has
// exactly one writer sequence; an accumulation is a `Mul` followed by `Mac`s on the
// same slot.
#include <string>
#include <vector>

#include "dmbd/blocks/discretize.hpp"
#include "dmbd/diagrams/diagram.hpp"

namespace dmbd::codegen {

enum class SlotKind { Input, Output, Signal, State };

struct Slot {
  std::string name;    // a C identifier, unique in the program
  SlotKind kind = SlotKind::Signal;
  std::string origin;  // the block (path) or diagram port it belongs to
  std::string unit;
};

enum class OpKind {
  Mul,    // dst = c * a
  Mac,    // dst = dst + c * a    (c == 1: dst + a, c == -1: dst - a)
  Copy,   // dst = a
  Clamp,  // dst = min(max(a, lo), hi)
};

struct Op {
  OpKind kind = OpKind::Copy;
  int dst = 0, a = 0;
  double c = 1.0;
  double lo = 0.0, hi = 0.0;
  int block = -1;          // index into LoopProgram::blocks: the block it came from
  std::string note;        // what the statement computes, e.g. "section 1: y = b0 x + s1"
};

struct BlockInfo {
  std::string path;        // "plant.K"
  std::string type;        // "tf", "gain", ...
  std::string summary;     // the block's fields as written
  std::string realisation; // e.g. "2 second-order sections, direct form II transposed, tustin"
};

struct LoopProgram {
  std::string name;
  double rate_hz = 0.0, ts = 0.0;
  blocks::C2dMethod method = blocks::C2dMethod::Tustin;
  std::vector<Slot> slots;
  std::vector<int> inputs, outputs, states;  // slot indices, in the diagram's order
  std::vector<Op> output_ops, update_ops;
  std::vector<BlockInfo> blocks;
  std::vector<std::string> warnings;         // e.g. a delay rounded to whole samples
};

struct LowerOptions {
  double rate_hz = 1000.0;
  blocks::C2dMethod method = blocks::C2dMethod::Tustin;
  // Per-block method overrides by block path.
  std::vector<std::pair<std::string, blocks::C2dMethod>> block_methods;
};

// Lower a diagram (continuous blocks discretised at the rate; discrete diagrams must
// run at their own sample time). Transfer functions become cascades of second-order
// sections in direct form II transposed; delays exact sample delays (rounded to whole
// samples, with a warning in `warnings`, when they are not). Blocks whose loop would be
// algebraic once discretised are merged into one state-space group. InputError for such
// a loop through a saturation or delay (naming the blocks), a rate that does not match
// a discrete diagram, a block method (LowerOptions::block_methods) for a path that
// names no block, or a non-zero delay shorter than half a sample.
LoopProgram lower(const diagrams::Diagram& d, const LowerOptions& options);
// A single transfer function as a one-input one-output program.
LoopProgram lower(const blocks::TransferFunction& g, const std::string& name, const LowerOptions& options);

// The second-order sections of a discrete transfer function: each {b0, b1, b2, a1, a2}
// of (b0 + b1 z^-1 + b2 z^-2)/(1 + a1 z^-1 + a2 z^-2) (first-order sections have b2 =
// a2 = 0; a static gain is one section of order 0). Poles are paired with their nearest zeros, sections ordered from the pole
// farthest from the unit circle to the nearest; the gain goes into the first section.
struct Section {
  double b0 = 0.0, b1 = 0.0, b2 = 0.0, a1 = 0.0, a2 = 0.0;
  int order = 2;
};
std::vector<Section> second_order_sections(const blocks::TransferFunction& discrete);

}  // namespace dmbd::codegen
