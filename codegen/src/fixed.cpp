#include "dmbd/codegen/fixed.hpp"

#include <cmath>
#include <algorithm>
#include <cstdint>
#include <limits>
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

namespace {

// The slots' bounds: guaranteed (slot_bounds), else simulated on the verification input.
void bounds(FixedProgram& f, const LoopProgram& p, const std::vector<std::pair<double, double>>& input_ranges) {
  f.bound = slot_bounds(p, input_ranges);
  f.simulated.assign(p.slots.size(), false);
  bool any = false;
  for (double b : f.bound) any = any || !std::isfinite(b);
  if (!any) return;
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

int64_t word_max(int bits) { return (int64_t{1} << (bits - 1)) - 1; }

// c in a `bits`-bit word with the finest format it holds: |c| 2^qc in [2^(bits-2), 2^(bits-1)).
int64_t quantise(double c, int bits, int& qc) {
  const int e = static_cast<int>(std::floor(std::log2(std::abs(c))));
  qc = bits - 2 - e;
  return std::max(-word_max(bits), std::min(word_max(bits), static_cast<int64_t>(std::llround(std::ldexp(c, qc)))));
}

// The formats and statements of p for the words in f.bits (f.bound already set).
void realise(FixedProgram& f, const LoopProgram& p) {
  f.q.resize(p.slots.size());
  for (size_t k = 0; k < p.slots.size(); ++k) f.q[k] = q_format(f.bound[k], f.bits[k]);
  f.quantised = p;
  f.statements.clear();
  const std::vector<std::pair<const std::vector<Op>*, bool>> all{{&p.output_ops, false}, {&p.update_ops, true}};
  for (const auto& part : all) {
    const std::vector<Op>& ops = *part.first;
    const bool update = part.second;
    for (size_t i = 0; i < ops.size();) {
      const Op& o = ops[i];
      FixedStatement st;
      st.dst = o.dst;
      st.block = o.block;
      st.note = o.note;
      st.update = update;
      // A Mul and the Macs that follow it on the same slot: one accumulation.
      size_t j = i + 1;
      if (o.kind != OpKind::Copy && o.kind != OpKind::Clamp)
        while (j < ops.size() && ops[j].kind == OpKind::Mac && ops[j].dst == o.dst) ++j;
      // The path: 32 bits if any word it reads or writes is.
      st.bits = f.bits[static_cast<size_t>(o.dst)];
      for (size_t k = i; k < j; ++k) st.bits = std::max(st.bits, f.bits[static_cast<size_t>(ops[k].a)]);
      if (o.kind == OpKind::Copy || o.kind == OpKind::Clamp) {
        st.kind = o.kind == OpKind::Copy ? FixedStatement::Kind::Copy : FixedStatement::Kind::Clamp;
        st.terms.push_back({o.a, 1, 0, 0});
        if (o.kind == OpKind::Clamp) {
          // Limits in the input's format and word: clamp first, then convert (the input
          // may exceed what the output's format holds, which is what the clamp is for).
          const auto a = static_cast<size_t>(o.a);
          const double scale = std::ldexp(1.0, f.q[a]);
          const int64_t m = word_max(f.bits[a]);
          st.lo = std::max(-m - 1, std::min(m, static_cast<int64_t>(std::llround(o.lo * scale))));
          st.hi = std::max(-m - 1, std::min(m, static_cast<int64_t>(std::llround(o.hi * scale))));
        }
        f.statements.push_back(st);
        ++i;
        continue;
      }
      for (size_t k = i; k < j; ++k) {
        const Op& t = ops[k];
        FixedTerm term;
        term.a = t.a;
        if (t.c == 1.0 || t.c == -1.0) {
          term.sign = t.c > 0 ? 1 : -1;
        } else {
          term.sign = 0;  // a zero coefficient contributes nothing
          if (t.c != 0.0) term.c = quantise(t.c, st.bits, term.qc);
        }
        // The quantised program, for the report and the bound.
        Op& qo = update ? f.quantised.update_ops[k] : f.quantised.output_ops[k];
        if (term.sign == 0) qo.c = std::ldexp(static_cast<double>(term.c), -term.qc);
        st.terms.push_back(term);
      }
      // Accumulator format: g guard bits for N terms (runtime rule (G)), in the path's
      // accumulator (a 16-bit word on the 32-bit path has all the more headroom).
      const int n = static_cast<int>(st.terms.size());
      int g = 0;
      while ((1 << (g + 1)) - 1 < n) ++g;
      int qacc = 1 << 20;
      for (const FixedTerm& t : st.terms) {
        const int qa = f.q[static_cast<size_t>(t.a)];
        qacc = std::min(qacc, t.sign == 0 ? (t.c == 0 ? qacc : qa + t.qc - g) : qa + st.bits - 1 - g);
      }
      if (qacc == (1 << 20)) qacc = f.q[static_cast<size_t>(o.dst)];
      st.qacc = qacc;
      f.statements.push_back(st);
      i = j;
    }
  }
}

// The words that may be widened: states and the signals the state update reads.
std::vector<int> recursion_slots(const LoopProgram& p) {
  std::vector<char> in(p.slots.size(), 0);
  for (int s : p.states) in[static_cast<size_t>(s)] = 1;
  for (const Op& o : p.update_ops) in[static_cast<size_t>(o.a)] = 1;
  std::vector<int> out;
  for (size_t k = 0; k < p.slots.size(); ++k)
    if (in[k] && (p.slots[k].kind == SlotKind::State || p.slots[k].kind == SlotKind::Signal))
      out.push_back(static_cast<int>(k));
  return out;
}

}  // namespace

FixedProgram make_fixed(const LoopProgram& p, const std::vector<std::pair<double, double>>& input_ranges,
                        int word_bits, int state_bits) {
  if (word_bits != 16 && word_bits != 32) throw InputError("the word must be 16 or 32 bits");
  if (state_bits != kStateBitsAuto && state_bits != word_bits && !(word_bits == 16 && state_bits == 32))
    throw InputError("state words of " + std::to_string(state_bits) + " bits in a " + std::to_string(word_bits) +
                     "-bit program: expected auto, " + std::to_string(word_bits) +
                     (word_bits == 16 ? " or 32" : " (64-bit states would need a 128-bit accumulator)"));
  FixedProgram f;
  f.word_bits = word_bits;
  f.state_bits = word_bits == 16 && state_bits != 16 ? 32 : word_bits;
  bounds(f, p, input_ranges);
  f.bits.assign(p.slots.size(), word_bits);
  realise(f, p);
  if (f.state_bits == word_bits) return f;
  std::vector<int> wide = recursion_slots(p);
  if (state_bits == kStateBitsAuto) {
    // Widen where the rounding, accumulated, costs more than the output's own half LSB.
    const blocks::Matrix c = rounding_contributions(p, f, kVerifySamples);
    std::vector<int> keep;
    for (int s : wide)
      for (long j = 0; j < c.rows(); ++j)
        if (c(j, s) > std::ldexp(0.5, -f.q[static_cast<size_t>(p.outputs[static_cast<size_t>(j)])])) {
          keep.push_back(s);
          break;
        }
    wide = keep;
  }
  if (wide.empty()) return f;
  for (int s : wide) f.bits[static_cast<size_t>(s)] = f.state_bits;
  realise(f, p);
  return f;
}

namespace {

// One accumulation in the runtime's arithmetic for one path (16-bit words and a 32-bit
// accumulator, or 32-bit words and a 64-bit one); the accumulator format follows the
// headroom rule (G), so the unchecked forms are used. Returns the accumulator.
template <class Word, class Acc, Acc (*Add)(Acc, Word, int, int), Acc (*Sub)(Acc, Word, int, int),
          Acc (*Mac)(Acc, Word, int, Word, int, int)>
Acc accumulate_words(const FixedStatement& s, const std::vector<int64_t>& slots, const std::vector<int>& q) {
  Acc acc = 0;
  for (const FixedTerm& t : s.terms) {
    const auto x = static_cast<Word>(slots[static_cast<size_t>(t.a)]);
    const int qa = q[static_cast<size_t>(t.a)];
    if (t.sign > 0) acc = Add(acc, x, qa, s.qacc);
    if (t.sign < 0) acc = Sub(acc, x, qa, s.qacc);
    if (t.sign == 0 && t.c != 0) acc = Mac(acc, x, qa, static_cast<Word>(t.c), t.qc, s.qacc);
  }
  return acc;
}

// A Sum statement: accumulate on its path, narrow to the destination's word.
int64_t sum_statement(const FixedStatement& s, const std::vector<int64_t>& slots, const FixedProgram& f, fx::Status& st) {
  const int qd = f.q[static_cast<size_t>(s.dst)];
  if (s.bits == 16)
    return fx::narrow16(accumulate_words<fx::Word16, fx::Acc16, fx::acc16_add_g, fx::acc16_sub_g, fx::mac16_g>(s, slots, f.q),
                        s.qacc, qd, st);
  const fx::Acc32 acc = accumulate_words<fx::Word32, fx::Acc32, fx::acc32_add_g, fx::acc32_sub_g, fx::mac32_g>(s, slots, f.q);
  return f.bits[static_cast<size_t>(s.dst)] == 32 ? int64_t{fx::narrow32(acc, s.qacc, qd, st)}
                                                  : int64_t{fx::narrow32_16(acc, s.qacc, qd, st)};
}

// A Copy or Clamp statement: clamp in the source's word, convert to the destination's.
int64_t copy_statement(const FixedStatement& s, int64_t x, const FixedProgram& f, fx::Status& st) {
  const auto a = static_cast<size_t>(s.terms[0].a), d = static_cast<size_t>(s.dst);
  const bool from32 = f.bits[a] == 32, to32 = f.bits[d] == 32;
  const int qa = f.q[a], qd = f.q[d];
  if (s.kind == FixedStatement::Kind::Clamp)
    x = from32 ? fx::clamp32(static_cast<fx::Word32>(x), static_cast<fx::Word32>(s.lo), static_cast<fx::Word32>(s.hi))
               : fx::clamp16(static_cast<fx::Word16>(x), static_cast<fx::Word16>(s.lo), static_cast<fx::Word16>(s.hi));
  if (to32) return fx::convert32(static_cast<fx::Word32>(x), qa, qd, st);  // a 16-bit word widens exactly
  if (from32) return fx::convert32_16(static_cast<fx::Word32>(x), qa, qd, st);
  return fx::convert16(static_cast<fx::Word16>(x), qa, qd, st);
}

}  // namespace

FixedInterpreter::FixedInterpreter(const LoopProgram& p, const FixedProgram& f)
    : p_(p), f_(f), s_(p.slots.size(), 0), in_(p.inputs.size(), 0), out_(p.outputs.size(), 0) {}

void FixedInterpreter::reset() {
  std::fill(s_.begin(), s_.end(), 0);
  saturations_ = 0;
  clamp_events_ = 0;
}

void FixedInterpreter::step(const int64_t* u, int64_t* y) {
  fx::Status st{saturations_};
  for (size_t k = 0; k < p_.inputs.size(); ++k) s_[static_cast<size_t>(p_.inputs[k])] = u[k];
  bool outputs_done = false;
  for (const FixedStatement& s : f_.statements) {
    if (s.update && !outputs_done) {
      for (size_t k = 0; k < p_.outputs.size(); ++k) y[k] = s_[static_cast<size_t>(p_.outputs[k])];
      outputs_done = true;
    }
    int64_t& dst = s_[static_cast<size_t>(s.dst)];
    if (s.kind == FixedStatement::Kind::Sum) {
      dst = sum_statement(s, s_, f_, st);
      continue;
    }
    const int64_t x = s_[static_cast<size_t>(s.terms[0].a)];
    if (s.kind == FixedStatement::Kind::Clamp && (x < s.lo || x > s.hi)) ++clamp_events_;
    dst = copy_statement(s, x, f_, st);
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

blocks::StateSpace program_state_space(const LoopProgram& p, const std::vector<int>& inject_at) {
  LoopProgram q = p;
  // Saturations as identity (the linear part).
  for (auto* ops : {&q.output_ops, &q.update_ops})
    for (Op& o : *ops)
      if (o.kind == OpKind::Clamp) o.kind = OpKind::Copy;
  // Injections: a new input per listed slot, added right after the slot's last writer.
  if (!inject_at.empty()) {
    std::vector<std::vector<Op>> after_output(q.output_ops.size()), after_update(q.update_ops.size());
    std::vector<Op> at_start;
    for (int at : inject_at) {
      q.slots.push_back({"injection_" + std::to_string(q.slots.size()), SlotKind::Input, "", ""});
      const int src = static_cast<int>(q.slots.size()) - 1;
      q.inputs.push_back(src);
      Op inj;
      inj.kind = OpKind::Mac;
      inj.dst = at;
      inj.a = src;
      inj.c = 1.0;
      bool placed = false;
      for (size_t k = q.update_ops.size(); k-- > 0 && !placed;)
        if (q.update_ops[k].dst == at) after_update[k].push_back(inj), placed = true;
      for (size_t k = q.output_ops.size(); k-- > 0 && !placed;)
        if (q.output_ops[k].dst == at) after_output[k].push_back(inj), placed = true;
      if (!placed) at_start.push_back(inj);
    }
    auto rebuild = [](const std::vector<Op>& ops, const std::vector<std::vector<Op>>& after, std::vector<Op> head) {
      for (size_t k = 0; k < ops.size(); ++k) {
        head.push_back(ops[k]);
        head.insert(head.end(), after[k].begin(), after[k].end());
      }
      return head;
    };
    q.output_ops = rebuild(q.output_ops, after_output, at_start);
    q.update_ops = rebuild(q.update_ops, after_update, {});
  }
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

ImpulseL1 impulse_l1(const blocks::StateSpace& ss, int horizon, int max_samples) {
  const blocks::Matrix &A = ss.a(), &B = ss.b(), &C = ss.c(), &D = ss.d();
  const long n = A.rows(), m = B.cols(), p = C.rows();
  horizon = std::max(horizon, 0);
  max_samples = std::max(max_samples, horizon);
  ImpulseL1 r;
  blocks::Matrix sum = D.cwiseAbs();  // samples 0 .. k
  r.truncated = horizon > 0 ? sum : blocks::Matrix::Zero(p, m);
  // Per input: the largest state magnitude so far, the run of quiet samples, decayed.
  std::vector<double> top(static_cast<size_t>(m), 0.0);
  std::vector<int> quiet(static_cast<size_t>(m), 0);
  std::vector<char> decayed(static_cast<size_t>(m), n == 0 ? 1 : 0);
  std::vector<char> endless(static_cast<size_t>(m), 0);  // will not decay: +inf
  Eigen::MatrixXi seen = Eigen::MatrixXi::Zero(p, m);      // output sees a state of an endless input
  std::vector<long> active;                                // inputs still simulated
  for (long j = 0; j < m; ++j) active.push_back(j);
  blocks::Matrix X = B;  // x_k for the active inputs, k = 1 first
  bool checked = false;  // the check for responses that will not decay, done once
  auto compact = [&](const std::vector<long>& keep) {
    blocks::Matrix nx(n, static_cast<long>(keep.size()));
    for (size_t i = 0, w = 0; i < active.size(); ++i)
      if (w < keep.size() && active[i] == keep[w]) nx.col(static_cast<long>(w++)) = X.col(static_cast<long>(i));
    X = nx;
    active = keep;
  };
  for (long k = 1; n > 0 && k < max_samples && !active.empty(); ++k) {
    // Sample k of the output, and whether the state response has decayed.
    const blocks::Matrix Y = C * X;
    for (size_t i = 0; i < active.size(); ++i) {
      const long j = active[i];
      sum.col(j) += Y.col(static_cast<long>(i)).cwiseAbs();
      const double now = X.col(static_cast<long>(i)).cwiseAbs().maxCoeff();
      const auto ju = static_cast<size_t>(j);
      top[ju] = std::max(top[ju], now);
      quiet[ju] = now <= 1e-13 * top[ju] ? quiet[ju] + 1 : 0;
      if (quiet[ju] >= 16) decayed[ju] = 1;
    }
    if (k + 1 == horizon) r.truncated = sum;
    if (k + 1 >= horizon) {
      if (!checked) {
        checked = true;
        // Past the horizon only the infinite sums remain: inputs whose state at
        // max_samples is still above 1e-13 of its peak so far will not decay.
        blocks::Matrix P = blocks::Matrix::Identity(n, n), S = A;
        for (long e = max_samples - k; e > 0; e >>= 1) {
          if (e & 1) P = P * S;
          S = S * S;
        }
        const blocks::Matrix XK = P * X, YK = C * XK;
        for (size_t i = 0; i < active.size(); ++i) {
          const long j = active[i];
          const auto ju = static_cast<size_t>(j);
          if (decayed[ju] || XK.col(static_cast<long>(i)).cwiseAbs().maxCoeff() <= 1e-13 * top[ju]) continue;
          endless[ju] = 1;
          // Outputs that see the state that stays (an output blind to it keeps its sum).
          for (long o = 0; o < p; ++o)
            if (!(YK(o, static_cast<long>(i)) == 0.0)) seen(o, j) = 1;
        }
      }
      std::vector<long> keep;
      for (long j : active)
        if (!decayed[static_cast<size_t>(j)] && !endless[static_cast<size_t>(j)]) keep.push_back(j);
      if (keep.size() != active.size()) compact(keep);
    }
    X = A * X;
  }
  r.infinite = sum;
  for (long j = 0; j < m; ++j)
    if (!decayed[static_cast<size_t>(j)])
      for (long i = 0; i < p; ++i)
        if (sum(i, j) > 0.0 || seen(i, j)) r.infinite(i, j) = std::numeric_limits<double>::infinity();
  return r;
}

namespace {

// Per slot: the largest error one step adds there (0 where nothing rounds).
std::vector<double> rounding_errors(const LoopProgram& p, const FixedProgram& f) {
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
  return err;
}

// e_s ||g_s|| per output (rows) and slot (columns), over the horizon and over all steps.
struct Contributions {
  blocks::Matrix truncated, infinite;
  int sources = 0;
};
Contributions contributions(const LoopProgram& p, const FixedProgram& f, int horizon) {
  const long no = static_cast<long>(p.outputs.size()), ns = static_cast<long>(p.slots.size());
  Contributions r{blocks::Matrix::Zero(no, ns), blocks::Matrix::Zero(no, ns), 0};
  const std::vector<double> err = rounding_errors(p, f);
  std::vector<int> sources;
  for (size_t k = 0; k < p.slots.size(); ++k)
    if (err[k] > 0.0) sources.push_back(static_cast<int>(k));
  r.sources = static_cast<int>(sources.size());
  if (sources.empty()) return r;
  // The responses from the injections, in the quantised program (where the fixed
  // program rounds), one column per source.
  const blocks::StateSpace all = program_state_space(f.quantised, sources);
  std::vector<int> outs, cols;
  for (long j = 0; j < no; ++j) outs.push_back(static_cast<int>(j));
  for (size_t k = 0; k < sources.size(); ++k) cols.push_back(static_cast<int>(p.inputs.size() + k));
  const ImpulseL1 g = impulse_l1(all.select(outs, cols), horizon);
  for (long j = 0; j < no; ++j)
    for (size_t k = 0; k < sources.size(); ++k) {
      const double e = err[static_cast<size_t>(sources[k])];
      r.truncated(j, sources[k]) = e * g.truncated(j, static_cast<long>(k));
      r.infinite(j, sources[k]) = e * g.infinite(j, static_cast<long>(k));
    }
  return r;
}

}  // namespace

blocks::Matrix rounding_contributions(const LoopProgram& p, const FixedProgram& f, int horizon) {
  return contributions(p, f, horizon).truncated;
}

ErrorBound predicted_error_bound(const LoopProgram& p, const FixedProgram& f,
                                 const std::vector<std::pair<double, double>>& ranges, int horizon) {
  const size_t no = p.outputs.size();
  ErrorBound r;
  r.horizon = horizon;
  r.rounding.assign(no, 0.0);
  r.coefficients.assign(no, 0.0);
  std::vector<double> rounding_inf(no, 0.0), coefficients_inf(no, 0.0);
  // Rounding: per source, the largest error one step adds times its response's L1 norm.
  const Contributions rc = contributions(p, f, horizon);
  r.sources = rc.sources;
  for (size_t j = 0; j < no; ++j)
    for (long k = 0; k < rc.truncated.cols(); ++k) {  // in slot order, as a plain sum
      r.rounding[j] += rc.truncated(static_cast<long>(j), k);
      rounding_inf[j] += rc.infinite(static_cast<long>(j), k);
    }
  // Quantised coefficients: the difference of the two programs' impulse responses, as
  // one model with both programs' states side by side.
  const blocks::StateSpace exact = program_state_space(p), quant = program_state_space(f.quantised);
  const long ne = exact.num_states(), nq = quant.num_states();
  blocks::Matrix a = blocks::Matrix::Zero(ne + nq, ne + nq), b(ne + nq, exact.num_inputs()), c(exact.num_outputs(), ne + nq);
  a.topLeftCorner(ne, ne) = exact.a();
  a.bottomRightCorner(nq, nq) = quant.a();
  b.topRows(ne) = exact.b();
  b.bottomRows(nq) = quant.b();
  c.leftCols(ne) = -exact.c();
  c.rightCols(nq) = quant.c();
  const ImpulseL1 dh = impulse_l1(blocks::StateSpace(a, b, c, quant.d() - exact.d(), p.ts), horizon);
  for (size_t i = 0; i < p.inputs.size(); ++i) {
    const double range = i < ranges.size() ? std::max(std::abs(ranges[i].first), std::abs(ranges[i].second)) : 1.0;
    if (range == 0.0) continue;  // an input that cannot move contributes nothing (not 0 x inf)
    for (size_t j = 0; j < no; ++j) {
      r.coefficients[j] += range * dh.truncated(static_cast<long>(j), static_cast<long>(i));
      coefficients_inf[j] += range * dh.infinite(static_cast<long>(j), static_cast<long>(i));
    }
  }
  r.over_horizon.resize(no);
  r.infinite.resize(no);
  for (size_t j = 0; j < no; ++j) {
    r.over_horizon[j] = r.rounding[j] + r.coefficients[j];
    r.infinite[j] = rounding_inf[j] + coefficients_inf[j];
  }
  return r;
}

}  // namespace dmbd::codegen
