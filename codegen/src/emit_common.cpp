#include "emit_common.hpp"

#include <cmath>
#include <cstdio>
#include <set>

#include "dmbd/version.hpp"

namespace dmbd::codegen::detail {

std::string state_member(const Slot& s) { return s.name + "_"; }

std::string fixed_arithmetic(const FixedProgram& f) {
  long wide = 0;
  for (int b : f.bits) wide += b != f.word_bits ? 1 : 0;
  const std::string w = std::to_string(f.word_bits) + "-bit fixed point";
  if (wide == 0) return w;
  return w + ", " + std::to_string(f.state_bits) + "-bit states (" + std::to_string(wide) + " word" + (wide > 1 ? "s" : "") +
         " of the state update widened)";
}

namespace {

const char* kind_word(SlotKind k) {
  return k == SlotKind::Input ? "input " : k == SlotKind::Output ? "output" : k == SlotKind::State ? "state " : "signal";
}

std::string block_heading(const BlockInfo& b) {
  return b.path + " (" + b.type + (b.summary.empty() ? "" : ": " + b.summary) + ")";
}

// The statements of a floating-point op list, each block's first preceded by its comment.
void float_statements(std::ostream& h, const LoopProgram& p, const std::vector<Op>& ops, Scalar scalar,
                      const StepSyntax& x, const std::vector<std::string>& name) {
  int last_block = -2;
  for (const Op& op : ops) {
    if (op.block != last_block) {
      if (op.block >= 0) h << x.indent << "// " << block_heading(p.blocks[static_cast<size_t>(op.block)]) << "\n";
      last_block = op.block;
    }
    const std::string& d = name[static_cast<size_t>(op.dst)];
    const std::string& a = name[static_cast<size_t>(op.a)];
    std::string stmt;
    switch (op.kind) {
      case OpKind::Mul:
        stmt = op.c == 1.0 ? d + " = " + a + ";" : op.c == -1.0 ? d + " = -" + a + ";"
                                                               : d + " = " + literal(op.c, scalar) + " * " + a + ";";
        break;
      case OpKind::Mac:
        if (op.c == 1.0) {
          stmt = d + " += " + a + ";";
        } else if (op.c == -1.0) {
          stmt = d + " -= " + a + ";";
        } else if (op.c < 0.0) {  // x + (-c) a == x - c a exactly in IEEE arithmetic
          stmt = d + " -= " + literal(-op.c, scalar) + " * " + a + ";";
        } else {
          stmt = d + " += " + literal(op.c, scalar) + " * " + a + ";";
        }
        break;
      case OpKind::Copy:
        stmt = d + " = " + a + ";";
        break;
      case OpKind::Clamp: {
        const std::string lo = literal(op.lo, scalar), hi = literal(op.hi, scalar);
        stmt = d + " = " + a + " < " + lo + " ? " + lo + " : (" + a + " > " + hi + " ? " + hi + " : " + a + ");";
        break;
      }
    }
    h << x.indent << stmt << (op.note.empty() ? "" : "  // " + op.note) << "\n";
  }
}

// The fixed program's statements; the writes of y and the update marker before the
// first update statement. Returns whether they were written.
bool fixed_statements(std::ostream& h, const LoopProgram& p, const FixedProgram& f, const StepSyntax& x,
                      const std::vector<std::string>& name, const std::string& outputs) {
  const std::string fx = x.fx, in = x.indent + "  ";
  auto q = [&](int slot) { return f.q[static_cast<size_t>(slot)]; };
  auto bits = [&](int slot) { return f.bits[static_cast<size_t>(slot)]; };
  auto word = [&](int64_t v, int w) {
    if (v == -(int64_t{1} << (w - 1))) return "(-" + std::to_string((int64_t{1} << (w - 1)) - 1) + " - 1)";
    return std::to_string(v);
  };
  bool outputs_done = false;
  int last_block = -2;
  for (const FixedStatement& s : f.statements) {
    if (s.update && !outputs_done) {
      h << outputs << x.indent << "// ---- state update ----\n";
      outputs_done = true;
    }
    if (s.block != last_block) {
      if (s.block >= 0) h << x.indent << "// " << block_heading(p.blocks[static_cast<size_t>(s.block)]) << "\n";
      last_block = s.block;
    }
    const std::string& d = name[static_cast<size_t>(s.dst)];
    const std::string note = s.note.empty() ? "" : "  // " + s.note;
    const int a0 = s.terms[0].a;
    // Between words of different widths: a 16-bit word widens exactly into convert32,
    // a 32-bit one narrows by convert32_16 / narrow32_16 (a 16-bit program's 32-bit states).
    const bool to16 = bits(s.dst) == 16;
    if (s.kind == FixedStatement::Kind::Copy || s.kind == FixedStatement::Kind::Clamp) {
      const std::string from = std::to_string(bits(a0));
      const std::string convert = to16 ? (bits(a0) == 32 ? "convert32_16" : "convert16") : "convert32";
      const std::string arg = s.kind == FixedStatement::Kind::Copy
                                  ? name[static_cast<size_t>(a0)]
                                  : fx + "clamp" + from + "(" + name[static_cast<size_t>(a0)] + ", " + word(s.lo, bits(a0)) +
                                        ", " + word(s.hi, bits(a0)) + ")";
      h << x.indent << d << " = " << fx << convert << "(" << arg << ", " << q(a0) << ", " << q(s.dst) << ", " << x.status
        << ");" << note << "\n";
    } else {
      const std::string sfx = std::to_string(s.bits), ACC = fx + (s.bits == 32 ? "Acc32" : "Acc16");
      h << x.indent << "{" << note << "\n" << in << ACC << " acc = 0;  // Q" << s.qacc << ", headroom rule (G): no overflow\n";
      for (const FixedTerm& t : s.terms) {
        const std::string& a = name[static_cast<size_t>(t.a)];
        if (t.sign > 0) {
          h << in << "acc = " << fx << "acc" << sfx << "_add_g(acc, " << a << ", " << q(t.a) << ", " << s.qacc << ");\n";
        } else if (t.sign < 0) {
          h << in << "acc = " << fx << "acc" << sfx << "_sub_g(acc, " << a << ", " << q(t.a) << ", " << s.qacc << ");\n";
        } else if (t.c != 0) {
          char cv[48];
          std::snprintf(cv, sizeof cv, "%.9g", std::ldexp(static_cast<double>(t.c), -t.qc));
          h << in << "acc = " << fx << "mac" << sfx << "_g(acc, " << a << ", " << q(t.a) << ", " << word(t.c, s.bits) << ", "
            << t.qc << ", " << s.qacc << ");  // coefficient " << cv << "\n";
        }
      }
      const std::string narrow = s.bits == 16 ? "narrow16" : to16 ? "narrow32_16" : "narrow32";
      h << in << d << " = " << fx << narrow << "(acc, " << s.qacc << ", " << q(s.dst) << ", " << x.status << ");\n"
        << x.indent << "}\n";
    }
  }
  return outputs_done;
}

}  // namespace

void write_preamble(std::ostream& h, const LoopProgram& p, const std::string& file, const std::string& source,
                    const std::string& arithmetic, const std::vector<std::string>& contract, const FixedProgram* fixed,
                    Scalar scalar) {
  h << "// " << file << ": generated by dmbd " << kVersion << " from " << source << ". Do not edit.\n"
    << "// Rate " << p.rate_hz << " Hz (sample time " << literal(p.ts, Scalar::Double) << " s), continuous blocks "
    << "discretised by " << blocks::to_string(p.method) << "; arithmetic: " << arithmetic << ".\n";
  for (const std::string& line : contract) h << "// " << line << "\n";
  h << "//\n";
  if (fixed) {
    h << "// Signals: format, guaranteed range\n";
    if (fixed->bits != std::vector<int>(p.slots.size(), fixed->word_bits))
      h << "// (\"(32-bit)\": a word of the state update widened by the range analysis, docs/codegen.md)\n";
  } else {
    h << "// Signals (all " << to_string(scalar) << "):\n";
  }
  for (size_t k = 0; k < p.slots.size(); ++k) {
    const Slot& s = p.slots[k];
    h << "//   " << kind_word(s.kind) << "  " << s.name << (s.unit.empty() ? "" : " [" + s.unit + "]");
    if (fixed) {
      char rng[64];
      std::snprintf(rng, sizeof rng, "%.6g", fixed->bound[k]);
      h << "  Q" << fixed->q[k] << (fixed->bits[k] != fixed->word_bits ? " (" + std::to_string(fixed->bits[k]) + "-bit)" : "")
        << "  |x| <= " << rng;
    }
    h << "  (" << s.origin << ")\n";
  }
  h << "//\n// Blocks:\n";
  for (const BlockInfo& b : p.blocks)
    h << "//   " << b.path << " (" << b.type << (b.summary.empty() ? "" : ": " + b.summary) << "): " << b.realisation << "\n";
  for (const std::string& w : p.warnings) h << "// Warning: " << w << "\n";
}

std::string port_list(const LoopProgram& p, const FixedProgram* fixed) {
  auto port = [&](const char* array, size_t k, int slot) {
    std::string t = std::string(k ? ", " : " ") + array + "[" + std::to_string(k) + "] = " + p.slots[static_cast<size_t>(slot)].origin;
    if (fixed) t += " (Q" + std::to_string(fixed->q[static_cast<size_t>(slot)]) + ")";
    return t;
  };
  std::string t = "inputs";
  for (size_t k = 0; k < p.inputs.size(); ++k) t += port("u", k, p.inputs[k]);
  t += "; outputs";
  for (size_t k = 0; k < p.outputs.size(); ++k) t += port("y", k, p.outputs[k]);
  return t;
}

void write_step_body(std::ostream& h, const LoopProgram& p, const FixedProgram* fixed, Scalar scalar,
                     const StepSyntax& x) {
  // How each slot is spelled: inputs and signals are locals of step(), states members.
  std::vector<std::string> name;
  for (const Slot& s : p.slots) name.push_back(s.kind == SlotKind::State ? x.state_prefix + state_member(s) : s.name);
  // A slot's type: the scalar, or its word (a 16-bit program's widened slots: Word32).
  auto T = [&](size_t k) {
    return fixed ? x.fx + (fixed->bits[k] == 32 ? "Word32" : "Word16") : std::string(to_string(scalar));
  };
  for (size_t k = 0; k < p.inputs.size(); ++k) {
    const auto slot = static_cast<size_t>(p.inputs[k]);
    h << x.indent << "const " << T(slot) << " " << name[slot] << " = u[" << k << "];\n";
  }
  for (size_t k = 0; k < p.slots.size(); ++k)
    if (p.slots[k].kind == SlotKind::Signal || p.slots[k].kind == SlotKind::Output)
      h << x.indent << T(k) << " " << p.slots[k].name << ";\n";
  std::string outputs;
  for (size_t k = 0; k < p.outputs.size(); ++k)
    outputs += x.indent + "y[" + std::to_string(k) + "] = " + name[static_cast<size_t>(p.outputs[k])] + ";\n";
  h << x.indent << "// ---- outputs ----\n";
  std::set<int> read(p.outputs.begin(), p.outputs.end());
  if (fixed) {
    if (!fixed_statements(h, p, *fixed, x, name, outputs)) h << outputs;
    for (const FixedStatement& s : fixed->statements)
      for (const FixedTerm& t : s.terms) read.insert(t.a);
  } else {
    float_statements(h, p, p.output_ops, scalar, x, name);
    h << outputs << x.indent << "// ---- state update ----\n";
    float_statements(h, p, p.update_ops, scalar, x, name);
    // An accumulation (dst += c a) does not read its slot for anyone else: a signal only
    // accumulated into is set but not used (clang warns of it).
    for (const auto* ops : {&p.output_ops, &p.update_ops})
      for (const Op& op : *ops) read.insert(op.a);
  }
  for (size_t i = 0; i < p.slots.size(); ++i) {
    const Slot& s = p.slots[i];
    if ((s.kind == SlotKind::Signal || s.kind == SlotKind::Input) && !read.count(static_cast<int>(i)))
      h << x.indent << "(void)" << s.name << ";  // not read by any block\n";
  }
}

}  // namespace dmbd::codegen::detail
