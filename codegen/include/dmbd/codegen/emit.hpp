#pragma once
// The C++ emitter: one self-contained header per program (docs/codegen.md).
#include <string>

#include "dmbd/codegen/loop_program.hpp"

namespace dmbd::codegen {

enum class Scalar { Double, Float };
const char* to_string(Scalar s);

struct EmitOptions {
  Scalar scalar = Scalar::Double;
  std::string source;  // what it was generated from (diagram file or expression), for the header comment
};

// The text of `<program.name>.hpp`: namespace <name> { kSampleTime, kNumInputs,
// kNumOutputs, class Controller { reset(), step(), step_real() } }. C++11, needs only
// <cmath>; no heap, no STL, no virtual calls; every statement commented with the
// block it comes from; the statements in exactly the program's order (so a double
// program is bit-identical to the interpreter).
std::string emit_header(const LoopProgram& p, const EmitOptions& o);

struct FixedProgram;
// The fixed-point header: integer words of `f.word_bits` bits, the formats of f, the
// runtime fragment pasted into namespace <name>::fx; needs only <cstdint>; step() is
// integer arithmetic only; step_real() quantises and converts; saturations() counts.
std::string emit_fixed_header(const LoopProgram& p, const FixedProgram& f, const EmitOptions& o);

// A C++ literal that reads back as exactly v in the given scalar type.
std::string literal(double v, Scalar s);

}  // namespace dmbd::codegen
