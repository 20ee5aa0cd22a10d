// Compile test of codegen/runtime/fixed_point.inc, built by CTest with the flags a
// generated header must survive (C++11, -Wall -Wextra -Werror -pedantic, no exceptions,
// no RTTI).  It includes <cstdint> and nothing else, pastes the fragment into two
// namespaces the way the emitter does (several generated headers in one program), and
// uses every function so that nothing is left unchecked.
#include <cstdint>

namespace diagram_a {
namespace fx {
#include "fixed_point.inc"
}  // namespace fx
}  // namespace diagram_a

namespace diagram_b {
namespace fx {
#include "fixed_point.inc"
}  // namespace fx
}  // namespace diagram_b

// A fixed-point step in the style of generated code: a 16-bit and a 32-bit biquad-like
// accumulation, a saturation block and the host conversions.
int32_t compile_fixed_point_use(const int16_t* u16, const int32_t* u32, double* y);
int32_t compile_fixed_point_use(const int16_t* u16, const int32_t* u32, double* y) {
  diagram_a::fx::Status st = {0};
  diagram_b::fx::Status st_b = {0};
  diagram_a::fx::Acc16 acc16 = 0;
  acc16 = diagram_a::fx::mac16(acc16, u16[0], 12, 16384, 14, 24, st);
  acc16 = diagram_a::fx::acc16_add(acc16, u16[1], 13, 24, st);
  acc16 = diagram_a::fx::acc16_sub(acc16, u16[2], 13, 24, st);
  int16_t w = diagram_a::fx::narrow16(acc16, 24, 12, st);
  w = diagram_a::fx::add16(w, diagram_a::fx::mul16(u16[3], 15, -12000, 15, 12, st), st);
  w = diagram_a::fx::sub16(w, diagram_a::fx::convert16(u16[4], 14, 12, st), st);
  w = diagram_a::fx::clamp16(w, -2048, 2047);
  diagram_b::fx::Acc32 acc32 = 0;
  acc32 = diagram_b::fx::mac32(acc32, u32[0], 28, 1073741824, 30, 57, st_b);
  acc32 = diagram_b::fx::acc32_add(acc32, u32[1], 29, 57, st_b);
  acc32 = diagram_b::fx::acc32_sub(acc32, u32[2], 29, 57, st_b);
  int32_t v = diagram_b::fx::narrow32(acc32, 57, 28, st_b);
  v = diagram_b::fx::add32(v, diagram_b::fx::mul32(u32[3], 31, -5, 31, 28, st_b), st_b);
  v = diagram_b::fx::sub32(v, diagram_b::fx::convert32(u32[4], 30, 28, st_b), st_b);
  v = diagram_b::fx::clamp32(v, -(1 << 28), 1 << 28);
  y[0] = diagram_a::fx::dequantize16(w, 12) + diagram_b::fx::dequantize32(v, 28) +
         diagram_b::fx::dequantize_acc32(acc32, 57);
  y[1] = static_cast<double>(diagram_a::fx::quantize16(y[0], 12, st) + diagram_b::fx::quantize32(y[0], 28, st_b));
  return static_cast<int32_t>(st.saturations + st_b.saturations);
}
