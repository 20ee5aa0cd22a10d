#pragma once
// The loop program: the small discrete-time IR that a diagram is lowered to once, and
// that both the C++ emitter and the in-process interpreter consume, so that the loop
// that is simulated is the loop that is shipped (docs/codegen.md).
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

// What a slot is in generated code. Input: a program input, read from u[k] at the start
// of a step. Output: a program output, written to y[k]. Signal: a value computed within a
// step (a local of step()). State: kept from one step to the next (a member, zero after
// reset()).
enum class SlotKind { Input, Output, Signal, State };

// One scalar of the program (an element of a vector signal is a slot of its own).
struct Slot {
  std::string name;    // a C identifier, unique in the program
  SlotKind kind = SlotKind::Signal;  // how the generated code holds it
  std::string origin;  // the block (path) or diagram port it belongs to
  std::string unit;    // the diagram port's unit for inputs and outputs (free text, may be empty); else empty
};

// One operation on slots (the comments give its effect; c, lo, hi are Op's).
enum class OpKind {
  Mul,    // dst = c * a
  Mac,    // dst = dst + c * a    (c == 1: dst + a, c == -1: dst - a)
  Copy,   // dst = a
  Clamp,  // dst = min(max(a, lo), hi)
};

// One operation: dst = f(dst, a) as its OpKind says, in double (or float: the
// Interpreter and the emitted literal round c, lo and hi to the scalar type once).
struct Op {
  OpKind kind = OpKind::Copy;  // what it computes
  // The slot written (index into LoopProgram::slots).
  int dst = 0, a = 0;      // the slot read (index into LoopProgram::slots)
  double c = 1.0;          // the coefficient of Mul and Mac (unused by Copy and Clamp)
  // Clamp: the lower limit, in the unit of the slots a and dst.
  double lo = 0.0, hi = 0.0;  // Clamp: the upper limit
  int block = -1;          // index into LoopProgram::blocks: the block it came from (-1: a diagram output's copy)
  std::string note;        // what the statement computes, e.g. "section 1: y = b0 x + s1"
};

// A block of the diagram as the program realises it (the header comment of generated
// code lists every one).
struct BlockInfo {
  std::string path;        // "plant.K"
  std::string type;        // "tf", "gain", ...
  std::string summary;     // the block's fields as written
  std::string realisation; // e.g. "2 second-order sections, direct form II transposed, tustin"
};

// A diagram (or a transfer function) lowered for one sample rate (lower): what the
// emitters print and the interpreters run. A step: inputs into their slots, output_ops,
// outputs read, update_ops.
struct LoopProgram {
  std::string name;  // the diagram's name (or lower's `name`): generated code's namespace or C prefix, file name
  // The loop rate in Hz.
  double rate_hz = 0.0, ts = 0.0;  // the sample time, s: 1 / rate_hz
  blocks::C2dMethod method = blocks::C2dMethod::Tustin;  // the default discretisation (LowerOptions::method)
  std::vector<Slot> slots;  // every scalar the step reads or writes; ops and the lists below index it
  // Slot indices of the program inputs: u[k] is inputs[k] (the diagram's inputs in file
  // order, a vector input taking consecutive entries).
  std::vector<int> inputs,
      outputs,  // slot indices of the program outputs: y[k] is outputs[k], as inputs
      states;   // slot indices of the states, block by block (a merged group's after the others)
  // The operations that compute every signal and output of a step from the inputs and
  // the states, in order: each block after the blocks feeding its direct-feedthrough inputs.
  std::vector<Op> output_ops, update_ops;  // then those that advance the states (after y is written)
  std::vector<BlockInfo> blocks;  // per atomic block of the diagram, in its order; Op::block indexes it
  std::vector<std::string> warnings;         // e.g. a delay rounded to whole samples
};

// How lower() discretises.
struct LowerOptions {
  double rate_hz = 1000.0;  // the loop rate, Hz (> 0; a discrete diagram's own rate)
  // For continuous blocks without a method of their own (the diagram's `discretization`
  // field of a block), and for every merged state-space group.
  blocks::C2dMethod method = blocks::C2dMethod::Tustin;
  // Per-block method overrides by block path (as FlatDiagram names atomic blocks,
  // e.g. "plant.Q_A"); they win over the block's own field, not over a group's method.
  std::vector<std::pair<std::string, blocks::C2dMethod>> block_methods;
};

// Lower a diagram (continuous blocks discretised at the rate; discrete diagrams must
// run at their own sample time). Transfer functions become cascades of second-order
// sections in direct form II transposed; delays exact sample delays (rounded to whole
// samples, with a warning in `warnings`, when they are not). Blocks whose loop would be
// algebraic once discretised are merged into one state-space group (discretised by
// options.method, with a warning). A block with a pole or zero above the Nyquist
// frequency gets a warning. InputError for such a loop through a saturation or delay
// (naming the blocks), a rate that is not a positive finite number or does not match a
// discrete diagram, a block method (LowerOptions::block_methods) for a path that names
// no block, or a non-zero delay shorter than half a sample; the discretisation's own
// InputErrors (blocks::c2d) pass through.
LoopProgram lower(const diagrams::Diagram& d, const LowerOptions& options);
// A single transfer function as a one-input one-output program called `name`: input
// slot in_u, output slot out_y, one block "G" (sections as above, by options.method;
// block_methods unused). InputError for an improper g, a rate that is not a positive
// finite number, or a discrete g whose sample time is not 1 / options.rate_hz.
LoopProgram lower(const blocks::TransferFunction& g, const std::string& name, const LowerOptions& options);

// The second-order sections of a discrete transfer function: each {b0, b1, b2, a1, a2}
// of (b0 + b1 z^-1 + b2 z^-2)/(1 + a1 z^-1 + a2 z^-2) (first-order sections have b2 =
// a2 = 0; a static gain is one section of order 0). Poles are paired with their
// nearest zeros, sections ordered by increasing pole radius |p| (for stable poles: from
// the farthest from the unit circle to the nearest); the gain goes into the first section.
struct Section {
  // Numerator b0 + b1 z^-1 + b2 z^-2: b0, its z^0 coefficient (0: no direct feedthrough).
  double b0 = 0.0,
      b1 = 0.0,  // numerator, z^-1
      b2 = 0.0,  // numerator, z^-2 (0 in a first-order section)
      a1 = 0.0,  // denominator 1 + a1 z^-1 + a2 z^-2, z^-1
      a2 = 0.0;  // denominator, z^-2 (0 in a first-order section)
  int order = 2;  // poles in the section: 2, 1, or 0 for a static gain b0
};
// The sections (above) of the discrete transfer function `discrete`, whose product is
// it. Roots at z = -1, 0 and 1 are divided out exactly before the others are found (as
// repeated roots they would scatter). InputError for a continuous or an improper one.
std::vector<Section> second_order_sections(const blocks::TransferFunction& discrete);

}  // namespace dmbd::codegen
