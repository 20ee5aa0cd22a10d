// Lowering a diagram (or one transfer function) to a loop program.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "dmbd/blocks/discretize.hpp"
#include "dmbd/blocks/error.hpp"
#include "dmbd/codegen/loop_program.hpp"
#include "dmbd/diagrams/flat.hpp"
#include "lower_parts.hpp"
#include "pid_lowering.hpp"
#include "sections.hpp"

namespace dmbd::codegen {

namespace b = dmbd::blocks;
using b::Complex;

namespace {

std::string identifier(const std::string& s) {
  std::string out;
  for (char c : s) out.push_back(std::isalnum(static_cast<unsigned char>(c)) ? c : '_');
  if (out.empty() || std::isdigit(static_cast<unsigned char>(out[0]))) out = "_" + out;
  return out;
}

std::string fmt_coeff(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace

// Sections of a continuous transfer function discretised by `method`: poles (and for
// Tustin / backward Euler the zeros) mapped exactly from the continuous ones, better
// conditioned than the roots of the discrete polynomials; the gain matched at a point
// off the unit circle.
std::vector<Section> discretised_sections(const b::TransferFunction& g, double ts, b::C2dMethod method) {
  if (g.is_discrete()) return second_order_sections(g);
  const b::TransferFunction gd = b::c2d(g, ts, method);
  std::vector<Complex> poles, zeros;
  for (const Complex& p : g.poles()) poles.push_back(b::c2d_pole(p, ts, method));
  if (g.num().is_zero()) {
    // A numerator that a parameter at 0 made zero (D_q*s/(tau*s + 1) at D_q = 0): no
    // zeros at all, gain 0; the poles keep their states (the program's shape does not
    // depend on a parameter's value).
  } else if (method == b::C2dMethod::Zoh) {
    zeros = gd.zeros();
  } else {
    for (const Complex& z : g.zeros()) zeros.push_back(b::c2d_pole(z, ts, method));
    const Complex at_infinity = method == b::C2dMethod::Tustin ? Complex(-1.0, 0.0) : Complex(0.0, 0.0);
    for (int k = g.num().degree(); k < g.den().degree(); ++k) zeros.push_back(at_infinity);
  }
  // Make conjugates exact and reals real (the maps preserve conjugacy up to rounding).
  auto tidy = [](std::vector<Complex>& r) {
    for (auto& x : r)
      if (std::abs(x.imag()) <= 1e-13 * std::max(1.0, std::abs(x))) x = Complex(x.real(), 0.0);
    std::vector<Complex> pos;
    for (const auto& x : r)
      if (x.imag() > 0.0) pos.push_back(x);
    std::vector<Complex> out;
    for (const auto& x : r)
      if (x.imag() == 0.0) out.push_back(x);
    for (const auto& x : pos) {
      out.push_back(x);
      out.push_back(std::conj(x));
    }
    r = out;
  };
  tidy(poles);
  tidy(zeros);
  const Complex z0 = std::polar(1.7, 0.9);
  Complex prod(1.0);
  for (const Complex& z : zeros) prod *= z0 - z;
  for (const Complex& p : poles) prod /= z0 - p;
  const double gain = g.num().is_zero() ? 0.0 : (gd.evaluate(z0) / prod).real();
  return sections_from_roots(zeros, poles, gain);
}

namespace {

// A continuous pole or zero above the Nyquist frequency has no discrete counterpart at
// this rate: the discretisation folds it (Tustin maps it near z = -1, ZOH aliases it),
// so the generated loop does not behave as the block. Not an error (a far pole is often
// deliberate roll-off), but the engineer must know: one warning per block.
std::optional<std::string> above_nyquist(const std::vector<Complex>& roots, double ts, const std::string& path) {
  const double nyquist = M_PI / ts;  // rad/s
  double worst = 0.0;
  for (const Complex& r : roots) worst = std::max(worst, std::abs(r));
  if (!(worst > nyquist)) return std::nullopt;
  return "block '" + path + "' has a pole or zero at " + fmt_coeff(worst / (2 * M_PI)) + " Hz, above the Nyquist frequency " +
         fmt_coeff(0.5 / ts) + " Hz of the loop: its discretisation cannot reproduce it (raise the rate or lower the "
         "block's corner)";
}

std::optional<std::string> above_nyquist(const b::TransferFunction& g, double ts, const std::string& path) {
  if (g.is_discrete()) return std::nullopt;
  std::vector<Complex> roots = g.poles();
  for (const Complex& z : g.zeros()) roots.push_back(z);
  return above_nyquist(roots, ts, path);
}

}  // namespace

int Builder::new_slot(const std::string& name, SlotKind kind, const std::string& origin, const std::string& unit) {
  std::string id = identifier(name);
  std::string unique = id;
  for (int k = 2; taken.count(unique); ++k) unique = id + "_" + std::to_string(k);
  taken.insert(unique);
  p.slots.push_back({unique, kind, origin, unit});
  return static_cast<int>(p.slots.size()) - 1;
}

void op(std::vector<Op>& v, OpKind k, int dst, int a, double c, int block, const std::string& note) {
  Op o;
  o.kind = k;
  o.dst = dst;
  o.a = a;
  o.c = c;
  o.block = block;
  o.note = note;
  v.push_back(o);
}

// dst = sum_k c_k a_k, zero terms dropped (a single Mul by 0 if none is left).
void sum(std::vector<Op>& v, int dst, const std::vector<std::pair<int, double>>& terms, int block,
         const std::string& note) {
  bool first = true;
  for (const auto& [a, c] : terms) {
    if (c == 0.0) continue;
    op(v, first ? OpKind::Mul : OpKind::Mac, dst, a, c, block, first ? note : "");
    first = false;
  }
  if (first) op(v, OpKind::Mul, dst, terms.empty() ? dst : terms.front().first, 0.0, block, note);
}

// A cascade of sections from x to y (intermediate signals named after the block).
void cascade(Builder& bld, BlockCode& code, const std::vector<Section>& secs, int x, int y, int block,
             const std::string& base) {
  int in = x;
  bool ft = true;
  for (size_t k = 0; k < secs.size(); ++k) {
    const Section& s = secs[k];
    const int out = k + 1 == secs.size() ? y : bld.new_slot(base + "_sec" + std::to_string(k + 1), SlotKind::Signal, base);
    const std::string tag = secs.size() > 1 ? "section " + std::to_string(k + 1) + ": " : "";
    if (s.order == 0) {
      sum(code.out, out, {{in, s.b0}}, block, tag + "y = k u");
    } else {
      const int s1 = bld.new_slot(base + "_s" + std::to_string(2 * k + 1), SlotKind::State, base);
      bld.p.states.push_back(s1);
      if (s.order == 2) {
        const int s2 = bld.new_slot(base + "_s" + std::to_string(2 * k + 2), SlotKind::State, base);
        bld.p.states.push_back(s2);
        sum(code.out, out, {{in, s.b0}, {s1, 1.0}}, block, tag + "y = b0 u + s1");
        sum(code.upd, s1, {{in, s.b1}, {out, -s.a1}, {s2, 1.0}}, block, tag + "s1 = b1 u - a1 y + s2");
        sum(code.upd, s2, {{in, s.b2}, {out, -s.a2}}, block, tag + "s2 = b2 u - a2 y");
      } else {
        sum(code.out, out, {{in, s.b0}, {s1, 1.0}}, block, tag + "y = b0 u + s1");
        sum(code.upd, s1, {{in, s.b1}, {out, -s.a1}}, block, tag + "s1 = b1 u - a1 y");
      }
    }
    ft = ft && s.b0 != 0.0;
    in = out;
  }
  code.feedthrough = {ft};
}

std::string describe(const std::vector<Section>& secs, b::C2dMethod m, bool discrete_source) {
  int n2 = 0, n1 = 0;
  for (const auto& s : secs) {
    if (s.order == 2) ++n2;
    if (s.order == 1) ++n1;
  }
  std::string r;
  if (n2) r += std::to_string(n2) + " second-order section" + (n2 > 1 ? "s" : "");
  if (n1) r += std::string(r.empty() ? "" : " and ") + std::to_string(n1) + " first-order section" + (n1 > 1 ? "s" : "");
  if (r.empty()) return "static gain";
  r += ", direct form II transposed";
  if (!discrete_source) r += std::string(", ") + b::to_string(m);
  return r;
}

namespace {

// Drop the slots that no operation touches (the per-block states of blocks that were
// merged into a state-space group) and renumber the rest.
void compact(LoopProgram& p) {
  std::vector<bool> used(p.slots.size(), false);
  for (const auto* ops : {&p.output_ops, &p.update_ops})
    for (const Op& o : *ops) used[static_cast<size_t>(o.dst)] = used[static_cast<size_t>(o.a)] = true;
  for (int k : p.inputs) used[static_cast<size_t>(k)] = true;
  for (int k : p.outputs) used[static_cast<size_t>(k)] = true;
  std::vector<int> map(p.slots.size(), -1);
  std::vector<Slot> kept;
  for (size_t i = 0; i < p.slots.size(); ++i)
    if (used[i]) {
      map[i] = static_cast<int>(kept.size());
      kept.push_back(p.slots[i]);
    }
  p.slots = kept;
  for (auto* ops : {&p.output_ops, &p.update_ops})
    for (Op& o : *ops) o.dst = map[static_cast<size_t>(o.dst)], o.a = map[static_cast<size_t>(o.a)];
  for (int& k : p.inputs) k = map[static_cast<size_t>(k)];
  for (int& k : p.outputs) k = map[static_cast<size_t>(k)];
  std::vector<int> states;
  for (int k : p.states)
    if (map[static_cast<size_t>(k)] >= 0) states.push_back(map[static_cast<size_t>(k)]);
  p.states = states;
}

}  // namespace

LoopProgram lower(const diagrams::Diagram& d, const LowerOptions& opt) {
  if (!(opt.rate_hz > 0.0) || !std::isfinite(opt.rate_hz)) throw InputError("the rate must be a positive number of Hz");
  const double ts = 1.0 / opt.rate_hz;
  if (d.is_discrete() && std::abs(d.ts() - ts) > 1e-9 * d.ts())
    throw InputError("diagram '" + d.name() + "' is discrete at " + std::to_string(1.0 / d.ts()) +
                     " Hz: generate it at that rate");
  const diagrams::FlatDiagram f(d);
  for (const auto& [name, m] : opt.block_methods) {
    (void)m;
    if (std::find(f.atomic_name.begin(), f.atomic_name.end(), name) == f.atomic_name.end())
      throw InputError("a discretisation method is given for block '" + name + "', but diagram '" + d.name() +
                       "' has no block of that name");
  }
  Builder bld;
  LoopProgram& p = bld.p;
  p.name = d.name();
  p.rate_hz = opt.rate_hz;
  p.ts = ts;
  p.method = opt.method;
  // Slots of every signal: diagram inputs, then every atomic block output.
  std::vector<std::vector<int>> sig(f.signals.size());
  for (size_t i = 0; i < d.inputs().size(); ++i)
    for (int k = 0; k < d.inputs()[i].size; ++k) {
      const std::string n = d.inputs()[i].name + (d.inputs()[i].size > 1 ? "_" + std::to_string(k) : "");
      sig[i].push_back(bld.new_slot("in_" + n, SlotKind::Input, d.inputs()[i].name, d.inputs()[i].unit));
      p.inputs.push_back(sig[i].back());
    }
  for (size_t s = d.inputs().size(); s < f.signals.size(); ++s)
    for (int k = 0; k < f.signals[s].size; ++k)
      sig[s].push_back(bld.new_slot(f.signals[s].name + (f.signals[s].size > 1 ? "_" + std::to_string(k) : ""),
                                    SlotKind::Signal, f.signals[s].name));
  // Each atomic block's code.
  const int nb = static_cast<int>(f.atomic.size());
  std::vector<BlockCode> code(static_cast<size_t>(nb));
  for (int i = 0; i < nb; ++i) {
    const diagrams::Block& bl = *f.atomic[static_cast<size_t>(i)];
    const std::string path = f.atomic_name[static_cast<size_t>(i)];
    if (bl.sampled)
      throw InputError("block '" + path + "' is a sampled plant (a continuous subsystem in a discrete diagram), for "
                       "analysis only: generate code from the controller's own diagram");
    BlockInfo info{path, diagrams::to_string(bl.type), "", ""};
    for (const auto& [k, v] : bl.fields) info.summary += (info.summary.empty() ? "" : ", ") + k + ": " + v;
    // Input slots per port, output slots per port.
    std::vector<std::vector<int>> in, out;
    for (size_t k = 0; k < bl.inputs.size(); ++k)
      in.push_back(sig[static_cast<size_t>(f.readers[static_cast<size_t>(f.reader_base[static_cast<size_t>(i)] + static_cast<int>(k))].route.signal)]);
    for (size_t k = 0; k < bl.outputs.size(); ++k)
      out.push_back(sig[static_cast<size_t>(f.signal_base[static_cast<size_t>(i)] + static_cast<int>(k))]);
    BlockCode& c = code[static_cast<size_t>(i)];
    b::C2dMethod method = bl.method.value_or(opt.method);
    for (const auto& [name, m] : opt.block_methods)
      if (name == path) method = m;
    switch (bl.type) {
      case diagrams::BlockType::Gain: {
        for (int r = 0; r < bl.gain.rows(); ++r) {
          std::vector<std::pair<int, double>> terms;
          for (int q = 0; q < bl.gain.cols(); ++q) terms.push_back({in[0][static_cast<size_t>(q)], bl.gain(r, q)});
          sum(c.out, out[0][static_cast<size_t>(r)], terms, i, "y = k u");
        }
        c.feedthrough = {true};
        info.realisation = "gain";
        break;
      }
      case diagrams::BlockType::Sum: {
        const size_t w = out[0].size();
        for (size_t e = 0; e < w; ++e) {
          std::vector<std::pair<int, double>> terms;
          for (size_t k = 0; k < in.size(); ++k) terms.push_back({in[k][e], bl.signs[k]});
          sum(c.out, out[0][e], terms, i, "sum");
        }
        c.feedthrough.assign(in.size(), true);
        info.realisation = "sum";
        break;
      }
      case diagrams::BlockType::Saturation: {
        Op o;
        o.kind = OpKind::Clamp;
        o.dst = out[0][0];
        o.a = in[0][0];
        o.lo = bl.lower;
        o.hi = bl.upper;
        o.block = i;
        o.note = "saturation";
        c.out.push_back(o);
        c.feedthrough = {true};
        info.realisation = "clamp";
        break;
      }
      case diagrams::BlockType::Delay: {
        const double exact = d.is_discrete() ? bl.delay_samples : bl.delay_s * opt.rate_hz;
        const int n = static_cast<int>(std::lround(exact));
        if (n == 0 && exact > 1e-6)
          throw InputError("delay '" + path + "' of " + fmt_coeff(bl.delay_s) + " s is " + fmt_coeff(exact) +
                           " samples at " + fmt_coeff(opt.rate_hz) + " Hz: shorter than half a sample, it would vanish; "
                           "raise the rate or lengthen the delay");
        if (std::abs(exact - n) > 1e-6 * std::max(1.0, exact))
          p.warnings.push_back("delay '" + path + "' of " + fmt_coeff(bl.delay_s) + " s is " + fmt_coeff(exact) +
                               " samples at " + fmt_coeff(opt.rate_hz) + " Hz: rounded to " + std::to_string(n));
        if (n == 0) {
          op(c.out, OpKind::Copy, out[0][0], in[0][0], 1.0, i, "zero delay");
          c.feedthrough = {true};
        } else {
          std::vector<int> z;
          for (int k = 0; k < n; ++k) {
            z.push_back(bld.new_slot(path + "_z" + std::to_string(k + 1), SlotKind::State, path));
            p.states.push_back(z.back());
          }
          op(c.out, OpKind::Copy, out[0][0], z.back(), 1.0, i, "y = u[k-" + std::to_string(n) + "]");
          for (int k = n - 1; k > 0; --k) op(c.upd, OpKind::Copy, z[static_cast<size_t>(k)], z[static_cast<size_t>(k - 1)], 1.0, i, "shift");
          op(c.upd, OpKind::Copy, z[0], in[0][0], 1.0, i, "shift in");
          c.feedthrough = {false};
        }
        info.realisation = std::to_string(n) + "-sample delay";
        break;
      }
      case diagrams::BlockType::Ss: {
        b::StateSpace m = bl.model;
        if (!m.is_discrete()) {
          if (auto w = above_nyquist(m.poles(), ts, path)) p.warnings.push_back(*w);
          m = b::c2d(m, ts, method);
        }
        const int nx = m.num_states();
        std::vector<int> xs, nxt;
        for (int k = 0; k < nx; ++k) {
          xs.push_back(bld.new_slot(path + "_x" + std::to_string(k + 1), SlotKind::State, path));
          p.states.push_back(xs.back());
        }
        for (int k = 0; k < nx; ++k) nxt.push_back(bld.new_slot(path + "_x" + std::to_string(k + 1) + "_next", SlotKind::Signal, path));
        for (int r = 0; r < m.num_outputs(); ++r) {
          std::vector<std::pair<int, double>> terms;
          for (int k = 0; k < nx; ++k) terms.push_back({xs[static_cast<size_t>(k)], m.c()(r, k)});
          for (int k = 0; k < m.num_inputs(); ++k) terms.push_back({in[0][static_cast<size_t>(k)], m.d()(r, k)});
          sum(c.out, out[0][static_cast<size_t>(r)], terms, i, "y = C x + D u");
        }
        for (int r = 0; r < nx; ++r) {
          std::vector<std::pair<int, double>> terms;
          for (int k = 0; k < nx; ++k) terms.push_back({xs[static_cast<size_t>(k)], m.a()(r, k)});
          for (int k = 0; k < m.num_inputs(); ++k) terms.push_back({in[0][static_cast<size_t>(k)], m.b()(r, k)});
          sum(c.upd, nxt[static_cast<size_t>(r)], terms, i, "x' = A x + B u");
        }
        for (int r = 0; r < nx; ++r) op(c.upd, OpKind::Copy, xs[static_cast<size_t>(r)], nxt[static_cast<size_t>(r)], 1.0, i);
        c.feedthrough = {m.d().size() > 0 && m.d().cwiseAbs().maxCoeff() > 0.0};
        info.realisation = "state space (" + std::to_string(nx) + " states)" + (bl.model.is_discrete() ? "" : std::string(", ") + b::to_string(method));
        break;
      }
      default: {  // tf, pd, pid, lowpass, integrator
        if (bl.pid && bl.pid->output_limits) {  // its anti-windup needs its terms apart
          info.realisation = lower_limited_pid(bld, c, *bl.pid, ts, method, in[0][0], out[0][0], i, path);
          break;
        }
        if (auto w = above_nyquist(*bl.tf, ts, path)) p.warnings.push_back(*w);
        const auto secs = discretised_sections(*bl.tf, ts, method);
        cascade(bld, c, secs, in[0][0], out[0][0], i, path);
        info.realisation = describe(secs, method, bl.tf->is_discrete());
        break;
      }
    }
    p.blocks.push_back(info);
  }
  // Units of code: single blocks, or a group of blocks that pass their inputs straight
  // through in a loop once discretised (integrators and gains of a plant model under
  // Tustin). A group is interconnected in continuous time and discretised as one
  // state-space block, so its loops are solved exactly instead of being algebraic.
  struct Unit {
    std::vector<std::pair<int, bool>> reads;  // signal, direct feedthrough
    std::vector<int> produces;                // signals
    std::vector<Op> out, upd;
  };
  std::vector<int> producer(f.signals.size(), -1);
  for (int i = 0; i < nb; ++i)
    for (size_t k = 0; k < f.atomic[static_cast<size_t>(i)]->outputs.size(); ++k)
      producer[static_cast<size_t>(f.signal_base[static_cast<size_t>(i)]) + k] = i;
  auto reader_signal = [&](int i, size_t k) {
    return f.readers[static_cast<size_t>(f.reader_base[static_cast<size_t>(i)]) + k].route.signal;
  };
  std::vector<std::vector<int>> dep(static_cast<size_t>(nb));  // i depends on j directly
  for (int i = 0; i < nb; ++i)
    for (size_t k = 0; k < f.atomic[static_cast<size_t>(i)]->inputs.size(); ++k) {
      const int src = producer[static_cast<size_t>(reader_signal(i, k))];
      const auto& ft = code[static_cast<size_t>(i)].feedthrough;
      if (src >= 0 && ft[std::min(k, ft.size() - 1)]) dep[static_cast<size_t>(i)].push_back(src);
    }
  // Strongly connected components, each closed before the ones depending on it.
  std::vector<std::vector<int>> comps = b::strongly_connected_components(dep);
  std::vector<int> comp_of(static_cast<size_t>(nb), -1);
  for (size_t k = 0; k < comps.size(); ++k) {
    std::sort(comps[k].begin(), comps[k].end());
    for (int i : comps[k]) comp_of[static_cast<size_t>(i)] = static_cast<int>(k);
  }
  std::vector<Unit> units;
  for (const auto& c : comps) {
    Unit u;
    const bool loop = c.size() > 1 || std::count(dep[static_cast<size_t>(c[0])].begin(), dep[static_cast<size_t>(c[0])].end(), c[0]) > 0;
    if (!loop) {
      const int i = c[0];
      for (size_t k = 0; k < f.atomic[static_cast<size_t>(i)]->inputs.size(); ++k) {
        const auto& ft = code[static_cast<size_t>(i)].feedthrough;
        u.reads.push_back({reader_signal(i, k), ft[std::min(k, ft.size() - 1)]});
      }
      for (size_t k = 0; k < f.atomic[static_cast<size_t>(i)]->outputs.size(); ++k)
        u.produces.push_back(f.signal_base[static_cast<size_t>(i)] + static_cast<int>(k));
      u.out = code[static_cast<size_t>(i)].out;
      u.upd = code[static_cast<size_t>(i)].upd;
      units.push_back(std::move(u));
      continue;
    }
    // A group: stack the members' linear models and close the internal connections.
    std::string names;
    for (int i : c) names += (names.empty() ? "" : ", ") + f.atomic_name[static_cast<size_t>(i)];
    for (int i : c) {
      const diagrams::Block& bl = *f.atomic[static_cast<size_t>(i)];
      const bool limited = bl.pid && bl.pid->output_limits;
      if (bl.type == diagrams::BlockType::Saturation || bl.type == diagrams::BlockType::Delay || limited)
        throw InputError("algebraic loop after discretisation through " + names + ": the " + diagrams::to_string(bl.type) +
                         " block '" + f.atomic_name[static_cast<size_t>(i)] + "'" + (limited ? " (with output limits)" : "") +
                         " cannot be merged into a linear group (put a delay in the loop)");
    }
    std::vector<int> ext;  // external signals read, in first-use order
    int nx = 0, nu = 0, ny = 0;
    for (int i : c) {
      const auto& m = f.atomic[static_cast<size_t>(i)]->model;
      nx += m.num_states();
      nu += m.num_inputs();
      ny += m.num_outputs();
      for (size_t k = 0; k < f.atomic[static_cast<size_t>(i)]->inputs.size(); ++k) {
        const int sgl = reader_signal(i, k);
        const int src = producer[static_cast<size_t>(sgl)];
        if ((src < 0 || comp_of[static_cast<size_t>(src)] != comp_of[static_cast<size_t>(i)]) &&
            std::find(ext.begin(), ext.end(), sgl) == ext.end())
          ext.push_back(sgl);
      }
    }
    std::vector<int> ext_off;
    int nw = 0;
    for (int sgl : ext) ext_off.push_back(nw), nw += f.signals[static_cast<size_t>(sgl)].size;
    b::Matrix A = b::Matrix::Zero(nx, nx), B = b::Matrix::Zero(nx, nu), C = b::Matrix::Zero(ny, nx), D = b::Matrix::Zero(ny, nu);
    b::Matrix M = b::Matrix::Zero(nu, ny), N = b::Matrix::Zero(nu, nw);
    std::map<int, int> y_off;  // member output signal -> offset in y
    {
      int xo = 0, uo = 0, yo = 0;
      for (int i : c) {
        const auto& m = f.atomic[static_cast<size_t>(i)]->model;
        A.block(xo, xo, m.num_states(), m.num_states()) = m.a();
        B.block(xo, uo, m.num_states(), m.num_inputs()) = m.b();
        C.block(yo, xo, m.num_outputs(), m.num_states()) = m.c();
        D.block(yo, uo, m.num_outputs(), m.num_inputs()) = m.d();
        int off = yo;
        for (size_t k = 0; k < f.atomic[static_cast<size_t>(i)]->outputs.size(); ++k) {
          y_off[f.signal_base[static_cast<size_t>(i)] + static_cast<int>(k)] = off;
          off += f.atomic[static_cast<size_t>(i)]->outputs[k].size;
        }
        xo += m.num_states();
        uo += m.num_inputs();
        yo += m.num_outputs();
      }
      uo = 0;
      for (int i : c) {
        for (size_t k = 0; k < f.atomic[static_cast<size_t>(i)]->inputs.size(); ++k) {
          const int sgl = reader_signal(i, k), w = f.atomic[static_cast<size_t>(i)]->inputs[k].size;
          auto it = y_off.find(sgl);
          if (it != y_off.end()) {
            M.block(uo, it->second, w, w) = b::Matrix::Identity(w, w);
          } else {
            const auto e = std::find(ext.begin(), ext.end(), sgl) - ext.begin();
            N.block(uo, ext_off[static_cast<size_t>(e)], w, w) = b::Matrix::Identity(w, w);
          }
          uo += w;
        }
      }
    }
    b::Matrix rhs(nu, nx + nw);
    rhs << M * C, N;
    const b::Matrix sol = b::solve_in_dependency_order(M * D, rhs);
    const b::Matrix KMC = sol.leftCols(nx), KN = sol.rightCols(nw);
    b::StateSpace g(A + B * KMC, B * KN, C + D * KMC, D * KN, d.is_discrete() ? ts : 0.0);
    if (!g.is_discrete()) g = b::c2d(g.balanced(), ts, opt.method);
    // Code: y = C x + D w; x' = A x + B w.
    const int gi = c[0];
    std::vector<int> xs, nxt, ws, ys;
    const std::string base = "group_" + f.atomic_name[static_cast<size_t>(gi)];
    const std::string origin = "group of " + f.atomic_name[static_cast<size_t>(gi)] + " and " + std::to_string(c.size() - 1) + " more blocks";
    for (int k = 0; k < g.num_states(); ++k) {
      xs.push_back(bld.new_slot(base + "_x" + std::to_string(k + 1), SlotKind::State, origin));
      p.states.push_back(xs.back());
      nxt.push_back(bld.new_slot(base + "_x" + std::to_string(k + 1) + "_next", SlotKind::Signal, origin));
    }
    for (int sgl : ext)
      for (int e = 0; e < f.signals[static_cast<size_t>(sgl)].size; ++e) ws.push_back(sig[static_cast<size_t>(sgl)][static_cast<size_t>(e)]);
    for (int i : c)
      for (size_t k = 0; k < f.atomic[static_cast<size_t>(i)]->outputs.size(); ++k) {
        const int sgl = f.signal_base[static_cast<size_t>(i)] + static_cast<int>(k);
        for (int slot : sig[static_cast<size_t>(sgl)]) ys.push_back(slot);
        u.produces.push_back(sgl);
      }
    for (int r = 0; r < g.num_outputs(); ++r) {
      std::vector<std::pair<int, double>> terms;
      for (int k = 0; k < g.num_states(); ++k) terms.push_back({xs[static_cast<size_t>(k)], g.c()(r, k)});
      for (int k = 0; k < g.num_inputs(); ++k) terms.push_back({ws[static_cast<size_t>(k)], g.d()(r, k)});
      sum(u.out, ys[static_cast<size_t>(r)], terms, gi, "group: y = C x + D u");
    }
    for (int r = 0; r < g.num_states(); ++r) {
      std::vector<std::pair<int, double>> terms;
      for (int k = 0; k < g.num_states(); ++k) terms.push_back({xs[static_cast<size_t>(k)], g.a()(r, k)});
      for (int k = 0; k < g.num_inputs(); ++k) terms.push_back({ws[static_cast<size_t>(k)], g.b()(r, k)});
      sum(u.upd, nxt[static_cast<size_t>(r)], terms, gi, "group: x' = A x + B u");
    }
    for (int r = 0; r < g.num_states(); ++r) op(u.upd, OpKind::Copy, xs[static_cast<size_t>(r)], nxt[static_cast<size_t>(r)], 1.0, gi);
    {
      int col = 0;
      for (int sgl : ext) {
        const int w = f.signals[static_cast<size_t>(sgl)].size;
        u.reads.push_back({sgl, g.d().middleCols(col, w).cwiseAbs().maxCoeff() > 0.0});
        col += w;
      }
    }
    p.blocks[static_cast<size_t>(gi)].realisation = "with " + names + ": one state-space group (" + std::to_string(g.num_states()) +
                                                    " states), interconnected in continuous time and discretised by " +
                                                    b::to_string(opt.method) + " (their loop would be algebraic block by block)";
    p.warnings.push_back("blocks " + names + " form a loop with direct feedthrough once discretised block by block: "
                         "generated as one state-space group");
    units.push_back(std::move(u));
  }
  // Order the units' output computations: a unit after the units feeding its
  // feedthrough inputs (Kahn). The condensation of the SCCs is acyclic.
  const int nunits = static_cast<int>(units.size());
  std::vector<int> unit_of(f.signals.size(), -1);
  for (int k = 0; k < nunits; ++k)
    for (int sgl : units[static_cast<size_t>(k)].produces) unit_of[static_cast<size_t>(sgl)] = k;
  std::vector<std::vector<int>> next(static_cast<size_t>(nunits));
  std::vector<int> indeg(static_cast<size_t>(nunits), 0);
  for (int k = 0; k < nunits; ++k)
    for (const auto& [sgl, ft] : units[static_cast<size_t>(k)].reads) {
      const int src = unit_of[static_cast<size_t>(sgl)];
      if (ft && src >= 0 && src != k) {
        next[static_cast<size_t>(src)].push_back(k);
        ++indeg[static_cast<size_t>(k)];
      }
    }
  std::vector<int> order, ready;
  for (int k = nunits - 1; k >= 0; --k)
    if (!indeg[static_cast<size_t>(k)]) ready.push_back(k);
  while (!ready.empty()) {
    const int v = ready.back();
    ready.pop_back();
    order.push_back(v);
    for (int w : next[static_cast<size_t>(v)])
      if (--indeg[static_cast<size_t>(w)] == 0) ready.push_back(w);
  }
  if (static_cast<int>(order.size()) != nunits) throw InputError("internal: the block order has a cycle after grouping");
  for (int k : order) p.output_ops.insert(p.output_ops.end(), units[static_cast<size_t>(k)].out.begin(), units[static_cast<size_t>(k)].out.end());
  for (const Unit& u : units) p.update_ops.insert(p.update_ops.end(), u.upd.begin(), u.upd.end());
  // Diagram outputs.
  for (size_t j = 0; j < d.outputs().size(); ++j) {
    const auto& r = f.readers[static_cast<size_t>(f.first_top_output) + j];
    for (int k = 0; k < d.outputs()[j].size; ++k) {
      const std::string n = d.outputs()[j].name + (d.outputs()[j].size > 1 ? "_" + std::to_string(k) : "");
      const int slot = bld.new_slot("out_" + n, SlotKind::Output, d.outputs()[j].name, d.outputs()[j].unit);
      p.outputs.push_back(slot);
      op(p.output_ops, OpKind::Copy, slot, sig[static_cast<size_t>(r.route.signal)][static_cast<size_t>(k)], 1.0, -1,
         "diagram output " + d.outputs()[j].name);
    }
  }
  compact(p);
  return p;
}

LoopProgram lower(const b::TransferFunction& g, const std::string& name, const LowerOptions& opt) {
  if (!g.is_proper()) throw InputError("an improper transfer function cannot be generated");
  if (!(opt.rate_hz > 0.0) || !std::isfinite(opt.rate_hz)) throw InputError("the rate must be a positive number of Hz");
  const double ts = 1.0 / opt.rate_hz;
  if (g.is_discrete() && std::abs(g.ts() - ts) > 1e-9 * g.ts())
    throw InputError("the transfer function is discrete at " + std::to_string(1.0 / g.ts()) + " Hz: generate it at that rate");
  Builder bld;
  LoopProgram& p = bld.p;
  p.name = name;
  p.rate_hz = opt.rate_hz;
  p.ts = ts;
  p.method = opt.method;
  const int u = bld.new_slot("in_u", SlotKind::Input, "u");
  const int y = bld.new_slot("G_out", SlotKind::Signal, "G");
  p.inputs.push_back(u);
  BlockCode c;
  if (auto w = above_nyquist(g, ts, "G")) p.warnings.push_back(*w);
  const auto secs = discretised_sections(g, ts, opt.method);
  cascade(bld, c, secs, u, y, 0, "G");
  p.blocks.push_back({"G", "tf", "", describe(secs, opt.method, g.is_discrete())});
  p.output_ops = c.out;
  p.update_ops = c.upd;
  const int out = bld.new_slot("out_y", SlotKind::Output, "y");
  p.outputs.push_back(out);
  op(p.output_ops, OpKind::Copy, out, y, 1.0, -1, "output y");
  return p;
}

}  // namespace dmbd::codegen
