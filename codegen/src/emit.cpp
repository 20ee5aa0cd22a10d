#include "dmbd/codegen/emit.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "dmbd/blocks/error.hpp"
#include "dmbd/codegen/fixed.hpp"
#include "emit_common.hpp"
#include "reserved_names.hpp"

namespace dmbd::codegen {

const char* to_string(Scalar s) { return s == Scalar::Double ? "double" : "float"; }

std::string literal(double v, Scalar s) {
  // Beyond the type's range (a saturation limit of 1e39 in float): the infinity the
  // interpreter also gets from the same conversion.
  const double as_type = s == Scalar::Float ? static_cast<double>(static_cast<float>(v)) : v;
  if (std::isinf(as_type)) return std::string(as_type < 0 ? "-" : "") + (s == Scalar::Float ? "HUGE_VALF" : "HUGE_VAL");
  char buf[64];
  if (s == Scalar::Float) {
    std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(static_cast<float>(v)));
  } else {
    std::snprintf(buf, sizeof buf, "%.17g", v);
  }
  std::string t = buf;
  if (t.find_first_of(".eE") == std::string::npos) t += ".0";
  if (s == Scalar::Float) t += "f";
  return t;
}

namespace {

// The C++ spelling of step(): a member function, states are members, the runtime is
// the namespace fx and the saturation counter the member status_.
const detail::StepSyntax kCpp{"    ", "", "fx::", "status_"};

}  // namespace

std::string emit_header(const LoopProgram& p, const EmitOptions& o) {
  if (p.inputs.empty() || p.outputs.empty()) throw InputError("a controller needs at least one input and one output");
  detail::check_cpp_names(p);
  const std::string T = to_string(o.scalar);
  std::ostringstream h;
  detail::write_preamble(h, p, p.name + ".hpp", o.source, T,
                         {"Contract (docs/codegen.md): reset() zeroes the states; step(u, y) reads kNumInputs values,",
                          "writes kNumOutputs values; no heap, no exceptions, no virtual calls."},
                         nullptr, o.scalar);
  const std::string guard = "DMBD_GENERATED_" + p.name + "_HPP";
  h << "#ifndef " << guard << "\n#define " << guard << "\n\n#include <cmath>\n\nnamespace " << p.name << " {\n\n"
    << "constexpr double kSampleTime = " << literal(p.ts, Scalar::Double) << ";  // s\n"
    << "constexpr int kNumInputs = " << p.inputs.size() << ", kNumOutputs = " << p.outputs.size() << ";\n\n"
    << "class Controller {\n public:\n  using Input = " << T << ";\n  using Output = " << T << ";\n\n"
    << "  Controller() { reset(); }\n\n  // All states to zero.\n  void reset() {\n";
  for (int s : p.states)
    h << "    " << detail::state_member(p.slots[static_cast<size_t>(s)]) << " = " << literal(0.0, o.scalar) << ";\n";
  h << "  }\n\n  // One sample: " << detail::port_list(p, nullptr) << ".\n  void step(const Input* u, Output* y) {\n";
  detail::write_step_body(h, p, nullptr, o.scalar, kCpp);
  h << "  }\n\n  // Host convenience: the same step in double.\n  void step_real(const double* u, double* y) {\n";
  if (o.scalar == Scalar::Double) {
    h << "    step(u, y);\n";
  } else {
    h << "    Input ui[kNumInputs];\n    Output yo[kNumOutputs];\n"
      << "    for (int k = 0; k < kNumInputs; ++k) ui[k] = static_cast<Input>(u[k]);\n    step(ui, yo);\n"
      << "    for (int k = 0; k < kNumOutputs; ++k) y[k] = static_cast<double>(yo[k]);\n";
  }
  h << "  }\n\n private:\n";
  for (int s : p.states) {
    const Slot& sl = p.slots[static_cast<size_t>(s)];
    h << "  " << T << " " << detail::state_member(sl) << ";  // " << sl.origin << "\n";
  }
  h << "};\n\n}  // namespace " << p.name << "\n\n#endif  // " << guard << "\n";
  return h.str();
}

extern const char* const kFixedPointRuntime;

std::string emit_fixed_header(const LoopProgram& p, const FixedProgram& f, const EmitOptions& o) {
  if (p.inputs.empty() || p.outputs.empty()) throw InputError("a controller needs at least one input and one output");
  detail::check_cpp_names(p);
  const int w = f.word_bits;
  const std::string sfx = std::to_string(w), I = w == 32 ? "int32_t" : "int16_t";
  auto q = [&](int slot) { return f.q[static_cast<size_t>(slot)]; };
  std::ostringstream h;
  detail::write_preamble(h, p, p.name + ".hpp", o.source, detail::fixed_arithmetic(f),
                         {"Contract (docs/codegen.md): step(u, y) takes and gives integer words in the formats below",
                          "(Qf: value = word / 2^f), integer arithmetic only, saturating on overflow and counting it",
                          "(saturations()); rounding half up at every narrowing; step_real() quantises and converts."},
                         &f, o.scalar);
  const std::string guard = "DMBD_GENERATED_" + p.name + "_HPP";
  h << "#ifndef " << guard << "\n#define " << guard << "\n\n#include <cstdint>\n\nnamespace " << p.name << " {\n\n"
    << "// ---- fixed-point runtime (codegen/runtime/fixed_point.inc) ----\nnamespace fx {\n" << kFixedPointRuntime
    << "\n}  // namespace fx\n\n"
    << "constexpr double kSampleTime = " << literal(p.ts, Scalar::Double) << ";  // s\n"
    << "constexpr int kNumInputs = " << p.inputs.size() << ", kNumOutputs = " << p.outputs.size() << ";\n"
    << "constexpr int kInputQ[kNumInputs] = {";
  for (size_t k = 0; k < p.inputs.size(); ++k) h << (k ? ", " : "") << q(p.inputs[k]);
  h << "};  // fractional bits of u[k]\nconstexpr int kOutputQ[kNumOutputs] = {";
  for (size_t k = 0; k < p.outputs.size(); ++k) h << (k ? ", " : "") << q(p.outputs[k]);
  h << "};  // fractional bits of y[k]\n\n"
    << "class Controller {\n public:\n  using Input = " << I << ";\n  using Output = " << I << ";\n\n"
    << "  Controller() { reset(); }\n\n  // All states and the saturation counter to zero.\n  void reset() {\n";
  for (int s : p.states) h << "    " << detail::state_member(p.slots[static_cast<size_t>(s)]) << " = 0;\n";
  h << "    status_.saturations = 0;\n  }\n\n  // Results clamped since reset().\n"
    << "  uint32_t saturations() const { return status_.saturations; }\n\n  // One sample, integer words: "
    << detail::port_list(p, &f) << ".\n  void step(const Input* u, Output* y) {\n";
  detail::write_step_body(h, p, &f, o.scalar, kCpp);
  h << "  }\n\n  // Host convenience: quantise the inputs (rounding half up, saturating), step, convert the outputs.\n"
    << "  void step_real(const double* u, double* y) {\n    Input ui[kNumInputs];\n    Output yo[kNumOutputs];\n"
    << "    for (int k = 0; k < kNumInputs; ++k) ui[k] = fx::quantize" << sfx << "(u[k], kInputQ[k], status_);\n"
    << "    step(ui, yo);\n"
    << "    for (int k = 0; k < kNumOutputs; ++k) y[k] = fx::dequantize" << sfx << "(yo[k], kOutputQ[k]);\n  }\n\n private:\n";
  for (int s : p.states) {
    const Slot& sl = p.slots[static_cast<size_t>(s)];
    h << "  " << (f.bits[static_cast<size_t>(s)] == 32 ? "fx::Word32" : "fx::Word16") << " " << detail::state_member(sl)
      << ";  // " << sl.origin << ", Q" << q(s) << "\n";
  }
  h << "  fx::Status status_;\n};\n\n}  // namespace " << p.name << "\n\n#endif  // " << guard << "\n";
  return h.str();
}

}  // namespace dmbd::codegen
