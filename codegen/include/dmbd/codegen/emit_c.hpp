#pragma once
// The C emitter: a C99 header and source per program (docs/codegen.md, "C output").
// The statements are the C++ emitter's, in the same order with the same literals, and
// the fixed-point runtime (codegen/runtime/fixed_point_c.inc) does the C++ runtime's
// integer arithmetic, so generated C, generated C++ and the interpreters agree bit for bit.
#include <string>

#include "dmbd/codegen/emit.hpp"

namespace dmbd::codegen {

// The language of generated code: Cpp, one C++11 header <name>.hpp (emit_header,
// emit_fixed_header); C, a C99 header <name>.h and source <name>.c (emit_c, emit_fixed_c).
enum class Language { Cpp, C };
const char* to_string(Language l);  // "cpp", "c"

// The prefix of a program's C macros: its name in capitals (FORCE_DOB for force_dob).
std::string c_macro_prefix(const std::string& name);

// C output as text, to be written as <name>.h and <name>.c in one folder (the source
// includes "<name>.h").
struct CFiles {
  std::string header;  // <name>.h: the state struct, the functions' declarations, the sizes
  std::string source;  // <name>.c: their definitions (and the fixed-point runtime, private to it)
};

// Every symbol starts with the program's name (C has no namespaces): a struct
// <name>_state, <name>_reset(), <name>_step(), <name>_step_real(), macros
// <NAME>_SAMPLE_TIME, <NAME>_NUM_INPUTS, <NAME>_NUM_OUTPUTS. C99; the source needs only
// <math.h> (HUGE_VAL); no heap, no library call; every statement commented with its
// block. InputError for a program name that is not a C identifier, a signal named
// as a C keyword or as a name the generated code uses (self, u, y, acc), or a program
// without an input or without an output.
CFiles emit_c(const LoopProgram& p, const EmitOptions& o);

// Fixed point: words of `f.word_bits` bits in the formats of f, as emit_fixed_header;
// needs only <stdint.h>; also <name>_saturations(), the formats <name>_input_q and
// <name>_output_q, and the host conversions <name>_quantize_input() and
// <name>_dequantize_output() that <name>_step_real() uses. f must be make_fixed's
// result for this program p; the InputErrors of emit_c.
CFiles emit_fixed_c(const LoopProgram& p, const FixedProgram& f, const EmitOptions& o);

}  // namespace dmbd::codegen
