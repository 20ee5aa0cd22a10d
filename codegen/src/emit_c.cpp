#include "dmbd/codegen/emit_c.hpp"

#include <cctype>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "dmbd/blocks/error.hpp"
#include "dmbd/codegen/fixed.hpp"
#include "dmbd/version.hpp"
#include "emit_common.hpp"
#include "reserved_names.hpp"

namespace dmbd::codegen {

const char* to_string(Language l) { return l == Language::C ? "c" : "cpp"; }

std::string c_macro_prefix(const std::string& name) {
  std::string m;
  for (char c : name) m += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return m;
}

extern const char* const kFixedPointRuntimeC;

namespace {

// The C spelling of step(): a function of the state struct `self`, the runtime's
// functions prefixed fx_, the saturation counter a member of the struct.
const detail::StepSyntax kC{"  ", "self->", "fx_", "&self->saturations"};

// The runtime functions that `code` calls: fx_name( ... ).
std::set<std::string> runtime_calls(const std::string& code) {
  std::set<std::string> out;
  for (size_t at = code.find("fx_"); at != std::string::npos; at = code.find("fx_", at + 3)) {
    if (at > 0 && (std::isalnum(static_cast<unsigned char>(code[at - 1])) || code[at - 1] == '_')) continue;
    size_t end = at + 3;
    while (end < code.size() && (std::isalnum(static_cast<unsigned char>(code[end])) || code[end] == '_')) ++end;
    if (end < code.size() && code[end] == '(') out.insert(code.substr(at, end - at));
  }
  return out;
}

// The C runtime reduced to what `code` needs (clang warns of an unused static function):
// every paragraph (lines up to a blank line) that defines no function, and of those that
// define one (one each, fixed_point_c.inc), the functions `code` calls and, in turn,
// the functions those call.
std::string runtime_for(const std::string& code) {
  const std::string text = kFixedPointRuntimeC;
  std::vector<std::string> paragraphs;
  for (size_t at = 0; at < text.size();) {
    const size_t end = text.find("\n\n", at);
    paragraphs.push_back(text.substr(at, end == std::string::npos ? std::string::npos : end - at));
    at = end == std::string::npos ? text.size() : end + 2;
  }
  std::vector<std::string> defines(paragraphs.size());  // the function a paragraph defines, if any
  for (size_t k = 0; k < paragraphs.size(); ++k) {
    const std::string key = "\nstatic inline ";
    const size_t at = ("\n" + paragraphs[k]).find(key);
    if (at == std::string::npos) continue;
    const size_t paren = paragraphs[k].find('(', at), name = paragraphs[k].rfind(' ', paren) + 1;  // type name(
    defines[k] = paragraphs[k].substr(name, paren - name);
  }
  std::set<std::string> needed = runtime_calls(code);
  for (bool grew = true; grew;) {
    grew = false;
    for (size_t k = 0; k < paragraphs.size(); ++k)
      if (!defines[k].empty() && needed.count(defines[k]))
        for (const std::string& f : runtime_calls(paragraphs[k])) grew = needed.insert(f).second || grew;
  }
  std::string out;
  for (size_t k = 0; k < paragraphs.size(); ++k)
    if (defines[k].empty() || needed.count(defines[k])) out += paragraphs[k] + "\n\n";
  return out;
}

// The two files of one program, floating point (f null) or fixed.
CFiles emit(const LoopProgram& p, const FixedProgram* f, const EmitOptions& o) {
  if (p.inputs.empty() || p.outputs.empty()) throw InputError("a controller needs at least one input and one output");
  detail::check_c_names(p);
  const std::string& n = p.name;
  const std::string N = c_macro_prefix(n);
  const std::string sfx = f ? std::to_string(f->word_bits) : "";
  const std::string T = f ? (f->word_bits == 32 ? "int32_t" : "int16_t") : std::string(to_string(o.scalar));
  const std::string state = n + "_state", NI = N + "_NUM_INPUTS", NO = N + "_NUM_OUTPUTS";

  std::ostringstream h;
  std::vector<std::string> contract;
  if (f) {
    contract = {"Contract (docs/codegen.md, C output): " + n + "_step(self, u, y) takes and gives integer words",
                "in the formats below (Qf: value = word / 2^f), integer arithmetic only, saturating on overflow and",
                "counting it (" + n + "_saturations()); rounding half up at every narrowing; " + n + "_step_real()",
                "quantises and converts. C99; no heap, no library calls."};
  } else {
    contract = {"Contract (docs/codegen.md, C output): " + n + "_reset(self) zeroes the states; " + n + "_step(self, u, y)",
                "reads " + NI + " values, writes " + NO + " values. C99; no heap, no library calls."};
  }
  detail::write_preamble(h, p, n + ".h", o.source, f ? detail::fixed_arithmetic(*f) : T, contract, f, o.scalar);
  const std::string guard = "DMBD_GENERATED_" + n + "_H";
  h << "#ifndef " << guard << "\n#define " << guard << "\n\n" << (f ? "#include <stdint.h>\n\n" : "")
    << "#ifdef __cplusplus\nextern \"C\" {\n#endif\n\n"
    << "#define " << N << "_SAMPLE_TIME " << literal(p.ts, Scalar::Double) << "  // s\n"
    << "#define " << NI << " " << p.inputs.size() << "\n#define " << NO << " " << p.outputs.size() << "\n\n"
    << "typedef " << T << " " << n << "_input;\ntypedef " << T << " " << n << "_output;\n\n"
    << "// The loop's states" << (f ? " and saturation counter" : "") << ", all zero after " << n << "_reset().\n"
    << "typedef struct " << state << " {\n";
  for (int s : p.states) {
    const Slot& sl = p.slots[static_cast<size_t>(s)];
    const std::string type = f && f->bits[static_cast<size_t>(s)] == 32 ? "int32_t" : T;
    h << "  " << type << " " << detail::state_member(sl) << ";  // " << sl.origin;
    if (f) h << ", Q" << f->q[static_cast<size_t>(s)];
    h << "\n";
  }
  if (f) h << "  uint32_t saturations;  // results clamped since " << n << "_reset()\n";
  if (!f && p.states.empty()) h << "  char no_state_;  // the loop has no state (C has no empty struct)\n";
  h << "} " << state << ";\n\n";
  if (f)
    h << "extern const int " << n << "_input_q[" << NI << "];  // fractional bits of u[k]\n"
      << "extern const int " << n << "_output_q[" << NO << "];  // fractional bits of y[k]\n\n";
  h << "// All states" << (f ? " and the saturation counter" : "") << " to zero.\nvoid " << n << "_reset(" << state
    << "* self);\n// One sample" << (f ? ", integer words: " : ": ") << detail::port_list(p, f) << ".\nvoid " << n
    << "_step(" << state << "* self, const " << n << "_input* u, " << n << "_output* y);\n";
  if (f) {
    h << "// Host convenience: quantise the inputs (rounding half up, saturating), step, convert the outputs.\n";
  } else {
    h << "// Host convenience: the same step in double.\n";
  }
  h << "void " << n << "_step_real(" << state << "* self, const double* u, double* y);\n";
  if (f)
    h << "// Results clamped since " << n << "_reset().\nuint32_t " << n << "_saturations(const " << state << "* self);\n"
      << "// Host conversions (double): the word of input k (0 <= k < " << NI << ") for the value v, rounded half\n"
      << "// up and saturated (a clamp counted in self), and the value of output k's word.\n"
      << n << "_input " << n << "_quantize_input(" << state << "* self, int k, double v);\n"
      << "double " << n << "_dequantize_output(int k, " << n << "_output y);\n";
  h << "\n#ifdef __cplusplus\n}  // extern \"C\"\n#endif\n\n#endif  // " << guard << "\n";

  // The definitions; the fixed-point runtime, reduced to what they call, goes before them.
  std::ostringstream c;
  if (f) {
    c << "const int " << n << "_input_q[" << NI << "] = {";
    for (size_t k = 0; k < p.inputs.size(); ++k) c << (k ? ", " : "") << f->q[static_cast<size_t>(p.inputs[k])];
    c << "};\nconst int " << n << "_output_q[" << NO << "] = {";
    for (size_t k = 0; k < p.outputs.size(); ++k) c << (k ? ", " : "") << f->q[static_cast<size_t>(p.outputs[k])];
    c << "};\n\n";
  }
  c << "void " << n << "_reset(" << state << "* self) {\n";
  for (int s : p.states)
    c << "  self->" << detail::state_member(p.slots[static_cast<size_t>(s)]) << " = "
      << (f ? std::string("0") : literal(0.0, o.scalar)) << ";\n";
  if (f) c << "  self->saturations = 0;\n";
  if (!f && p.states.empty()) c << "  (void)self;\n";
  c << "}\n\nvoid " << n << "_step(" << state << "* self, const " << n << "_input* u, " << n << "_output* y) {\n";
  if (p.states.empty() && !(f && !f->statements.empty())) c << "  (void)self;  // the loop has no state\n";
  detail::write_step_body(c, p, f, o.scalar, kC);
  c << "}\n\nvoid " << n << "_step_real(" << state << "* self, const double* u, double* y) {\n";
  if (!f && o.scalar == Scalar::Double) {
    c << "  " << n << "_step(self, u, y);\n";
  } else {
    const std::string to_in = f ? n + "_quantize_input(self, k, u[k])" : "(" + n + "_input)u[k]";
    const std::string to_out = f ? n + "_dequantize_output(k, yo[k])" : "(double)yo[k]";
    c << "  " << n << "_input ui[" << NI << "];\n  " << n << "_output yo[" << NO << "];\n"
      << "  for (int k = 0; k < " << NI << "; ++k) ui[k] = " << to_in << ";\n  " << n << "_step(self, ui, yo);\n"
      << "  for (int k = 0; k < " << NO << "; ++k) y[k] = " << to_out << ";\n";
  }
  c << "}\n";
  if (f)
    c << "\nuint32_t " << n << "_saturations(const " << state << "* self) { return self->saturations; }\n\n"
      << n << "_input " << n << "_quantize_input(" << state << "* self, int k, double v) {\n"
      << "  return fx_quantize" << sfx << "(v, " << n << "_input_q[k], &self->saturations);\n}\n\n"
      << "double " << n << "_dequantize_output(int k, " << n << "_output y) {\n"
      << "  return fx_dequantize" << sfx << "(y, " << n << "_output_q[k]);\n}\n";
  std::ostringstream file;
  file << "// " << n << ".c: generated by dmbd " << kVersion << " from " << o.source << ". Do not edit.\n"
       << "// The definitions of " << n << ".h (there: the contract, every signal and block). C99.\n"
       << "#include \"" << n << ".h\"\n\n";
  if (f) {
    file << "// ---- fixed-point runtime (codegen/runtime/fixed_point_c.inc: the functions used here) ----\n"
         << runtime_for(c.str()) << "// ---- end of the fixed-point runtime ----\n\n";
  } else {
    file << "#include <math.h>  // HUGE_VAL, HUGE_VALF\n\n";
  }
  return {h.str(), file.str() + c.str()};
}

}  // namespace

CFiles emit_c(const LoopProgram& p, const EmitOptions& o) { return emit(p, nullptr, o); }

CFiles emit_fixed_c(const LoopProgram& p, const FixedProgram& f, const EmitOptions& o) { return emit(p, &f, o); }

}  // namespace dmbd::codegen
