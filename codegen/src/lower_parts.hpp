#pragma once
// The pieces of lowering that more than one block's lowering uses (codegen/src/lower.cpp,
// pid_lowering.cpp): slots, operations, sums and cascades of sections.
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "dmbd/blocks/transfer_function.hpp"
#include "dmbd/codegen/loop_program.hpp"

namespace dmbd::codegen {

// The program being built and the slot names taken.
struct Builder {
  LoopProgram p;
  // A new slot named after `name` (made a unique C identifier).
  int new_slot(const std::string& name, SlotKind kind, const std::string& origin, const std::string& unit = "");
  std::set<std::string> taken;  // the identifiers in use
};

// One block's operations and its direct feedthrough per input port.
struct BlockCode {
  std::vector<Op> out, upd;       // its output operations, its state updates
  std::vector<bool> feedthrough;  // per input port
};

// Appends one operation.
void op(std::vector<Op>& v, OpKind k, int dst, int a, double c, int block, const std::string& note = "");
// dst = sum_k c_k a_k, zero terms dropped (a single Mul by 0 if none is left).
void sum(std::vector<Op>& v, int dst, const std::vector<std::pair<int, double>>& terms, int block, const std::string& note);
// A cascade of sections from slot x to slot y (states and intermediate signals named
// after `base`); sets code.feedthrough.
void cascade(Builder& bld, BlockCode& code, const std::vector<Section>& secs, int x, int y, int block, const std::string& base);
// The sections of a transfer function discretised by `method` at ts (a discrete one's
// own sections).
std::vector<Section> discretised_sections(const blocks::TransferFunction& g, double ts, blocks::C2dMethod method);
// "2 second-order sections, direct form II transposed, tustin", or "static gain".
std::string describe(const std::vector<Section>& secs, blocks::C2dMethod m, bool discrete_source);

}  // namespace dmbd::codegen
