#pragma once
// What the C++ emitter (emit.cpp) and the C emitter (emit_c.cpp) write alike: the
// comment that opens a generated file, and the body of step(): the locals, every
// statement with the comment of its block, the outputs, the state update. The two
// languages differ only in how a state and the runtime are spelled (StepSyntax), so
// both print the same statements in the same order: the same arithmetic.
#include <ostream>
#include <string>
#include <vector>

#include "dmbd/codegen/emit.hpp"
#include "dmbd/codegen/fixed.hpp"
#include "dmbd/codegen/loop_program.hpp"

namespace dmbd::codegen::detail {

// How step() spells what differs between C++ and C.
struct StepSyntax {
  std::string indent;        // of a statement in step(): "    " (C++ member function) or "  " (C function)
  std::string state_prefix;  // before a state's member name: "" (C++: a member) or "self->" (C: the state struct)
  std::string fx;            // before a runtime name: "fx::" (C++ namespace) or "fx_" (C prefix)
  std::string status;        // the saturation counter argument: "status_" or "&self->saturations"
};

// The arithmetic, as the opening comment says it: "16-bit fixed point", and for a
// program with wider words "16-bit fixed point, 32-bit states (N words widened)".
std::string fixed_arithmetic(const FixedProgram& f);

// A state's member name (the slot's name and "_").
std::string state_member(const Slot& s);

// The opening comment: `file` generated from `source`, rate and method, `arithmetic`,
// the contract lines (each written after "// "), every signal (with its format and
// range when `fixed` is given), every block, every warning.
void write_preamble(std::ostream& h, const LoopProgram& p, const std::string& file, const std::string& source,
                    const std::string& arithmetic, const std::vector<std::string>& contract, const FixedProgram* fixed,
                    Scalar scalar);

// "; inputs u[0] = F, ...; outputs y[0] = ...": the sentence after "One sample" (with
// each port's Q format when `fixed` is given).
std::string port_list(const LoopProgram& p, const FixedProgram* fixed);

// The body of step(u, y): locals for the inputs (read from u) and for every signal and
// output, then the output statements, the writes of y, the state update, and a (void)
// for every input or signal no statement reads. Floating point (`fixed` null) in
// `scalar`, else the fixed program's integer statements.
void write_step_body(std::ostream& h, const LoopProgram& p, const FixedProgram* fixed, Scalar scalar,
                     const StepSyntax& syntax);

}  // namespace dmbd::codegen::detail
