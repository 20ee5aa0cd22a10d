#pragma once
// Internal to codegen/: the names generated code cannot give a signal. Each signal of a
// loop program becomes a local of the generated step(), so it may be neither a keyword of
// the output language nor a name step() itself uses; both emitters apply the same rule.
#include "dmbd/codegen/loop_program.hpp"

namespace dmbd::codegen::detail {

// Throws InputError "program name '2lag': expected a C identifier", or "signal 'u' (its
// block): a C keyword | a name the generated C code uses (self, u, y, acc) cannot name a
// signal of C output; rename it in the diagram".
void check_c_names(const LoopProgram& p);

// The same for C++: C++17's keywords and alternative tokens, and u, y, acc, fx, status_
// and every state's member name (the state's name and "_"), which a local would hide;
// the program name is a namespace, so no keyword either.
void check_cpp_names(const LoopProgram& p);

}  // namespace dmbd::codegen::detail
