#pragma once
// The C++ emitter: one self-contained header per program (docs/codegen.md).
#include <string>

#include "dmbd/codegen/loop_program.hpp"

namespace dmbd::codegen {

// The floating-point type of generated code (Double: double, Float: float; every
// literal then carries f and no operand is promoted) and of the Interpreter it matches.
// Fixed point is not a Scalar: it is a FixedProgram (make_fixed) and its own emitters.
enum class Scalar { Double, Float };
// The type's C and C++ name: "double" or "float".
const char* to_string(Scalar s);

// What the emitters (emit_header, emit_fixed_header, emit_c, emit_fixed_c) take besides
// the program.
struct EmitOptions {
  Scalar scalar = Scalar::Double;  // arithmetic of floating-point output; the fixed-point emitters ignore it
  std::string source;  // what it was generated from (diagram file or expression), for the header comment
};

// The text of <program.name>.hpp: namespace <name> { kSampleTime, kNumInputs,
// kNumOutputs, class Controller { reset(), step(), step_real() } }. C++11, needs only
// <cmath>; no heap, no STL, no virtual calls; every statement commented with the
// block it comes from; the statements in exactly the program's order (so a double
// program is bit-identical to the interpreter). kSampleTime is p.ts in seconds; step()
// takes one value per program input and writes one per output, in the order of
// p.inputs and p.outputs. The name is used as is (not checked as an identifier).
// InputError for a program without an input or without an output.
std::string emit_header(const LoopProgram& p, const EmitOptions& o);

struct FixedProgram;
// The fixed-point header: integer words of `f.word_bits` bits, the formats of f, the
// runtime fragment (codegen/runtime/fixed_point.inc) pasted into a namespace fx inside
// namespace <name>; needs only <cstdint>; step() is integer arithmetic only;
// step_real() quantises and converts; saturations() counts. Also kInputQ and kOutputQ,
// the fractional bits of u[k] and y[k]. f must be make_fixed's result for this program
// p. InputError for a program without an input or without an output.
std::string emit_fixed_header(const LoopProgram& p, const FixedProgram& f, const EmitOptions& o);

// A C++ literal that reads back as exactly v in the given scalar type (the C emitter
// prints the same): 17 significant digits for double; for float, v rounded to float
// first, 9 digits and an f suffix; a value beyond the type's range is HUGE_VAL or
// HUGE_VALF with its sign (the infinity the interpreter gets from the same conversion).
std::string literal(double v, Scalar s);

}  // namespace dmbd::codegen
