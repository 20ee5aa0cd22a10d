#include "dmbd/codegen/fixed.hpp"

#include <cmath>
#include <cstdint>
#include <string>

#include "dmbd/blocks/error.hpp"
#include "dmbd/codegen/interpreter.hpp"
#include "dmbd/codegen/ranges.hpp"
#include "dmbd/codegen/verify.hpp"

namespace dmbd::codegen {

// The same runtime the generated headers contain, so that the interpreter's integer
// arithmetic is the generated code's by construction.
namespace fx {
#include "../runtime/fixed_point.inc"
}  // namespace fx

FixedProgram make_fixed(const LoopProgram& p, const std::vector<std::pair<double, double>>& input_ranges,
                        int word_bits) {
  if (word_bits != 16 && word_bits != 32) throw InputError("the word must be 16 or 32 bits");
  FixedProgram f;
  f.word_bits = word_bits;
  f.bound = slot_bounds(p, input_ranges);
  f.simulated.assign(p.slots.size(), false);
  bool any = false;
  for (double b : f.bound) any = any || !std::isfinite(b);
  if (any) {
    // Simulated ranges where no guarantee exists (docs/codegen.md).
    Interpreter<double> it(p);
    std::vector<double> peak(p.slots.size(), 0.0), y(p.outputs.size());
    for (const auto& row : verification_inputs(p, input_ranges)) {
      it.step(row.data(), y.data());
      for (size_t k = 0; k < peak.size(); ++k) peak[k] = std::max(peak[k], std::abs(it.slots()[k]));
    }
    for (size_t k = 0; k < p.slots.size(); ++k)
      if (!std::isfinite(f.bound[k])) {
        if (!std::isfinite(peak[k]))
          throw InputError("signal '" + p.slots[k].name + "' (" + p.slots[k].origin +
                           ") diverges on the verification input: it cannot be given a fixed-point format");
        f.bound[k] = 2.0 * peak[k];
        f.simulated[k] = true;
      }
  }
  f.q.resize(p.slots.size());
  for (size_t k = 0; k < p.slots.size(); ++k) f.q[k] = q_format(f.bound[k], word_bits);
  const int64_t word_max = (int64_t{1} << (word_bits - 1)) - 1;
  f.quantised = p;
  auto quantise = [&](double c, int& qc) {
    const int e = static_cast<int>(std::floor(std::log2(std::abs(c))));
    qc = word_bits - 2 - e;  // |c| 2^qc in [2^(W-2), 2^(W-1))
    int64_t w = std::llround(std::ldexp(c, qc));
    if (w > word_max) w = word_max;
    if (w < -word_max) w = -word_max;
    return w;
  };
  auto all = std::vector<std::pair<const std::vector<Op>*, bool>>{{&p.output_ops, false}, {&p.update_ops, true}};
  for (const auto& [ops, update] : all) {
    for (size_t i = 0; i < ops->size();) {
      const Op& o = (*ops)[i];
      FixedStatement st;
      st.dst = o.dst;
      st.block = o.block;
      st.note = o.note;
      st.update = update;
      if (o.kind == OpKind::Copy || o.kind == OpKind::Clamp) {
        st.kind = o.kind == OpKind::Copy ? FixedStatement::Kind::Copy : FixedStatement::Kind::Clamp;
        st.terms.push_back({o.a, 1, 0, 0});
        if (o.kind == OpKind::Clamp) {
          // Limits in the input's format: clamp first, then convert (the input may
          // exceed what the output's format holds, which is what the clamp is for).
          const double scale = std::ldexp(1.0, f.q[static_cast<size_t>(o.a)]);
          st.lo = std::max(-word_max - 1, std::min(word_max, static_cast<int64_t>(std::llround(o.lo * scale))));
          st.hi = std::max(-word_max - 1, std::min(word_max, static_cast<int64_t>(std::llround(o.hi * scale))));
        }
        f.statements.push_back(st);
        ++i;
        continue;
      }
      // A Mul and the Macs that follow it on the same slot: one accumulation.
      size_t j = i;
      do {
        const Op& t = (*ops)[j];
        FixedTerm term;
        term.a = t.a;
        if (t.c == 1.0 || t.c == -1.0) {
          term.sign = t.c > 0 ? 1 : -1;
        } else if (t.c != 0.0) {
          term.sign = 0;
          term.c = quantise(t.c, term.qc);
        } else {
          term.sign = 0;  // a zero coefficient: contributes nothing
          term.c = 0;
          term.qc = 0;
        }
        // The quantised program, for the report.
        Op& qo = update ? f.quantised.update_ops[j] : f.quantised.output_ops[j];
        if (term.sign == 0) qo.c = std::ldexp(static_cast<double>(term.c), -term.qc);
        st.terms.push_back(term);
        ++j;
      } while (j < ops->size() && (*ops)[j].kind == OpKind::Mac && (*ops)[j].dst == o.dst);
      // Accumulator format: g guard bits for N terms (runtime rule (G)).
      const int n = static_cast<int>(st.terms.size());
      int g = 0;
      while ((1 << (g + 1)) - 1 < n) ++g;
      int qacc = 1 << 20;
      for (const FixedTerm& t : st.terms) {
        const int qa = f.q[static_cast<size_t>(t.a)];
        qacc = std::min(qacc, t.sign == 0 ? (t.c == 0 ? qacc : qa + t.qc - g) : qa + word_bits - 1 - g);
      }
      if (qacc == (1 << 20)) qacc = f.q[static_cast<size_t>(o.dst)];
      st.qacc = qacc;
      f.statements.push_back(st);
      i = j;
    }
  }
  return f;
}

namespace {

// One accumulation in the runtime's arithmetic for one word width; the accumulator
// format follows the headroom rule (G), so the unchecked forms are used.
template <class Word, class Acc, Acc (*Add)(Acc, Word, int, int), Acc (*Sub)(Acc, Word, int, int),
          Acc (*Mac)(Acc, Word, int, Word, int, int), Word (*Narrow)(Acc, int, int, fx::Status&)>
int64_t accumulate_words(const FixedStatement& s, const std::vector<int64_t>& slots, const std::vector<int>& q, int qd,
                         fx::Status& st) {
  Acc acc = 0;
  for (const FixedTerm& t : s.terms) {
    const auto x = static_cast<Word>(slots[static_cast<size_t>(t.a)]);
    const int qa = q[static_cast<size_t>(t.a)];
    if (t.sign > 0) acc = Add(acc, x, qa, s.qacc);
    if (t.sign < 0) acc = Sub(acc, x, qa, s.qacc);
    if (t.sign == 0 && t.c != 0) acc = Mac(acc, x, qa, static_cast<Word>(t.c), t.qc, s.qacc);
  }
  return Narrow(acc, s.qacc, qd, st);
}

}  // namespace

FixedInterpreter::FixedInterpreter(const LoopProgram& p, const FixedProgram& f)
    : p_(p), f_(f), s_(p.slots.size(), 0), in_(p.inputs.size(), 0), out_(p.outputs.size(), 0) {}

void FixedInterpreter::reset() {
  std::fill(s_.begin(), s_.end(), 0);
  saturations_ = 0;
}

void FixedInterpreter::step(const int64_t* u, int64_t* y) {
  fx::Status st{saturations_};
  const bool w32 = f_.word_bits == 32;
  for (size_t k = 0; k < p_.inputs.size(); ++k) s_[static_cast<size_t>(p_.inputs[k])] = u[k];
  bool outputs_done = false;
  for (const FixedStatement& s : f_.statements) {
    if (s.update && !outputs_done) {
      for (size_t k = 0; k < p_.outputs.size(); ++k) y[k] = s_[static_cast<size_t>(p_.outputs[k])];
      outputs_done = true;
    }
    const int qd = f_.q[static_cast<size_t>(s.dst)];
    int64_t& dst = s_[static_cast<size_t>(s.dst)];
    switch (s.kind) {
      case FixedStatement::Kind::Copy:
      case FixedStatement::Kind::Clamp: {
        const int qa = f_.q[static_cast<size_t>(s.terms[0].a)];
        const int64_t x = s_[static_cast<size_t>(s.terms[0].a)];
        int64_t v = x;
        if (s.kind == FixedStatement::Kind::Clamp)
          v = w32 ? fx::clamp32(static_cast<fx::Word32>(v), static_cast<fx::Word32>(s.lo), static_cast<fx::Word32>(s.hi))
                  : fx::clamp16(static_cast<fx::Word16>(v), static_cast<fx::Word16>(s.lo), static_cast<fx::Word16>(s.hi));
        dst = w32 ? int64_t{fx::convert32(static_cast<fx::Word32>(v), qa, qd, st)}
                  : int64_t{fx::convert16(static_cast<fx::Word16>(v), qa, qd, st)};
        break;
      }
      case FixedStatement::Kind::Sum:
        dst = w32 ? accumulate_words<fx::Word32, fx::Acc32, fx::acc32_add_g, fx::acc32_sub_g, fx::mac32_g, fx::narrow32>(
                        s, s_, f_.q, qd, st)
                  : accumulate_words<fx::Word16, fx::Acc16, fx::acc16_add_g, fx::acc16_sub_g, fx::mac16_g, fx::narrow16>(
                        s, s_, f_.q, qd, st);
        break;
    }
  }
  if (!outputs_done)
    for (size_t k = 0; k < p_.outputs.size(); ++k) y[k] = s_[static_cast<size_t>(p_.outputs[k])];
  saturations_ = st.saturations;
}

void FixedInterpreter::step_real(const double* u, double* y) {
  fx::Status st{saturations_};
  for (size_t k = 0; k < p_.inputs.size(); ++k) {
    const int q = f_.q[static_cast<size_t>(p_.inputs[k])];
    in_[k] = f_.word_bits == 32 ? int64_t{fx::quantize32(u[k], q, st)} : int64_t{fx::quantize16(u[k], q, st)};
  }
  saturations_ = st.saturations;
  step(in_.data(), out_.data());
  for (size_t k = 0; k < p_.outputs.size(); ++k) {
    const int q = f_.q[static_cast<size_t>(p_.outputs[k])];
    y[k] = f_.word_bits == 32 ? fx::dequantize32(static_cast<fx::Word32>(out_[k]), q)
                              : fx::dequantize16(static_cast<fx::Word16>(out_[k]), q);
  }
}

}  // namespace dmbd::codegen

namespace dmbd::codegen {

namespace {

// L1 norms, per output, of the impulse response from an injection added to slot `at`
// right after it is written (at -1: from program input `input`).
std::vector<double> l1_to_outputs(const LoopProgram& p, int at, int input, int max_samples = 200000) {
  LoopProgram q = p;
  int src = -1;
  if (at >= 0) {
    q.slots.push_back({"injection", SlotKind::Input, "", ""});
    src = static_cast<int>(q.slots.size()) - 1;
    q.inputs.push_back(src);
    Op inj;
    inj.kind = OpKind::Mac;
    inj.dst = at;
    inj.a = src;
    inj.c = 1.0;
    // After the last writer of `at`; an input slot: first thing in the step.
    bool placed = false;
    for (auto* ops : {&q.update_ops, &q.output_ops}) {
      for (size_t k = ops->size(); k-- > 0 && !placed;)
        if ((*ops)[k].dst == at) {
          ops->insert(ops->begin() + static_cast<long>(k) + 1, inj);
          placed = true;
        }
      if (placed) break;
    }
    if (!placed) q.output_ops.insert(q.output_ops.begin(), inj);
  }
  // Saturations as identity (the linear part).
  for (auto* ops : {&q.output_ops, &q.update_ops})
    for (Op& o : *ops)
      if (o.kind == OpKind::Clamp) o.kind = OpKind::Copy;
  Interpreter<double> it(q);
  const size_t ni = q.inputs.size(), no = q.outputs.size();
  std::vector<double> u(ni, 0.0), y(no, 0.0), l1(no, 0.0);
  const size_t hit = at >= 0 ? ni - 1 : static_cast<size_t>(input);
  double top = 0.0;
  int quiet = 0;
  for (int n = 0; n < max_samples; ++n) {
    std::fill(u.begin(), u.end(), 0.0);
    if (n == 0) u[hit] = 1.0;
    it.step(u.data(), y.data());
    double now = 0.0;
    for (size_t k = 0; k < no; ++k) l1[k] += std::abs(y[k]);
    for (double v : it.slots()) now = std::max(now, std::abs(v)), top = std::max(top, std::abs(v));
    quiet = now <= 1e-13 * top ? quiet + 1 : 0;
    if (quiet >= 16) return l1;
  }
  for (double& v : l1) v = v > 0.0 ? INFINITY : 0.0;
  return l1;
}

}  // namespace

blocks::StateSpace program_state_space(const LoopProgram& p) {
  LoopProgram q = p;
  for (auto* ops : {&q.output_ops, &q.update_ops})
    for (Op& o : *ops)
      if (o.kind == OpKind::Clamp) o.kind = OpKind::Copy;
  const int nx = static_cast<int>(q.states.size()), nu = static_cast<int>(q.inputs.size()),
            ny = static_cast<int>(q.outputs.size());
  blocks::Matrix a(nx, nx), b(nx, nu), c(ny, nx), d(ny, nu);
  Interpreter<double> it(q);
  std::vector<double> u(static_cast<size_t>(nu)), y(static_cast<size_t>(ny));
  for (int col = 0; col < nx + nu; ++col) {
    it.reset();
    std::fill(u.begin(), u.end(), 0.0);
    if (col < nx) {
      it.mutable_slots()[static_cast<size_t>(q.states[static_cast<size_t>(col)])] = 1.0;
    } else {
      u[static_cast<size_t>(col - nx)] = 1.0;
    }
    it.step(u.data(), y.data());
    for (int r = 0; r < ny; ++r) (col < nx ? c(r, col) : d(r, col - nx)) = y[static_cast<size_t>(r)];
    for (int r = 0; r < nx; ++r)
      (col < nx ? a(r, col) : b(r, col - nx)) = it.slots()[static_cast<size_t>(q.states[static_cast<size_t>(r)])];
  }
  return blocks::StateSpace(a, b, c, d, p.ts);
}

std::vector<double> predicted_error_bound(const LoopProgram& p, const FixedProgram& f,
                                          const std::vector<std::pair<double, double>>& ranges) {
  const size_t no = p.outputs.size();
  std::vector<double> bound(no, 0.0);
  // Rounding sources: per written slot, the largest error one step can add there.
  std::vector<double> err(p.slots.size(), 0.0);
  for (int k : p.inputs) err[static_cast<size_t>(k)] += std::ldexp(0.5, -f.q[static_cast<size_t>(k)]);
  for (const FixedStatement& s : f.statements) {
    const int qd = f.q[static_cast<size_t>(s.dst)];
    double e = 0.0;
    if (s.kind == FixedStatement::Kind::Sum) {
      for (const FixedTerm& t : s.terms) {
        const int qa = f.q[static_cast<size_t>(t.a)];
        const int own = t.sign == 0 ? qa + t.qc : qa;
        // A term aligned by a floor shift: up to one LSB of the accumulator.
        if (own > s.qacc && !(t.sign == 0 && t.c == 0)) e += std::ldexp(1.0, -s.qacc);
      }
      if (s.qacc > qd) e += std::ldexp(0.5, -qd);
    } else if (f.q[static_cast<size_t>(s.terms[0].a)] > qd) {
      e += std::ldexp(0.5, -qd);
    }
    err[static_cast<size_t>(s.dst)] += e;
  }
  for (size_t k = 0; k < p.slots.size(); ++k) {
    if (err[k] == 0.0) continue;
    const auto g = l1_to_outputs(p, static_cast<int>(k), -1);
    for (size_t j = 0; j < no; ++j) bound[j] += err[k] * g[j];
  }
  // Quantised coefficients: the difference of the two programs' impulse responses.
  const blocks::StateSpace exact = program_state_space(p), quant = program_state_space(f.quantised);
  for (size_t i = 0; i < p.inputs.size(); ++i) {
    const double r = i < ranges.size() ? std::max(std::abs(ranges[i].first), std::abs(ranges[i].second)) : 1.0;
    blocks::Vector xe = blocks::Vector::Zero(exact.num_states()), xq = blocks::Vector::Zero(quant.num_states());
    std::vector<double> l1(no, 0.0);
    double top = 0.0;
    int quiet = 0;
    for (int n = 0; n < 200000; ++n) {
      const double u = n == 0 ? 1.0 : 0.0;
      const blocks::Vector ye = exact.c() * xe + exact.d().col(static_cast<long>(i)) * u;
      const blocks::Vector yq = quant.c() * xq + quant.d().col(static_cast<long>(i)) * u;
      xe = exact.a() * xe + exact.b().col(static_cast<long>(i)) * u;
      xq = quant.a() * xq + quant.b().col(static_cast<long>(i)) * u;
      double now = 0.0;
      for (size_t j = 0; j < no; ++j) l1[j] += std::abs(yq(static_cast<long>(j)) - ye(static_cast<long>(j)));
      now = std::max(xe.size() ? xe.cwiseAbs().maxCoeff() : 0.0, xq.size() ? xq.cwiseAbs().maxCoeff() : 0.0);
      top = std::max(top, now);
      quiet = now <= 1e-13 * top ? quiet + 1 : 0;
      if (quiet >= 16) break;
    }
    for (size_t j = 0; j < no; ++j) bound[j] += r * l1[j];
  }
  return bound;
}

}  // namespace dmbd::codegen
