#include "dmbd/codegen/ranges.hpp"

#include <cmath>
#include <limits>

#include "dmbd/blocks/error.hpp"
#include "dmbd/codegen/interpreter.hpp"

namespace dmbd::codegen {

std::vector<double> slot_bounds(const LoopProgram& p, const std::vector<std::pair<double, double>>& input_ranges,
                                int max_samples) {
  // The program with every clamp replaced by a new input: the linear part alone.
  LoopProgram lin = p;
  std::vector<double> source_bound;
  for (size_t k = 0; k < p.inputs.size(); ++k) {
    const auto r = k < input_ranges.size() ? input_ranges[k] : std::make_pair(-1.0, 1.0);
    source_bound.push_back(std::max(std::abs(r.first), std::abs(r.second)));
  }
  for (auto* ops : {&lin.output_ops, &lin.update_ops})
    for (Op& o : *ops)
      if (o.kind == OpKind::Clamp) {
        Slot s{"clamp_source_" + std::to_string(lin.slots.size()), SlotKind::Input, "clamp", ""};
        lin.slots.push_back(s);
        const int src = static_cast<int>(lin.slots.size()) - 1;
        lin.inputs.push_back(src);
        source_bound.push_back(std::max(std::abs(o.lo), std::abs(o.hi)));
        o.kind = OpKind::Copy;
        o.a = src;
      }
  std::vector<double> bound(p.slots.size(), 0.0);
  const size_t ns = p.slots.size();
  Interpreter<double> it(lin);
  std::vector<double> u(lin.inputs.size(), 0.0), y(lin.outputs.size(), 0.0);
  for (size_t j = 0; j < lin.inputs.size(); ++j) {
    if (source_bound[j] == 0.0) continue;
    it.reset();
    std::vector<double> l1(ns, 0.0), peak(ns, 0.0);
    bool decayed = false;
    int quiet = 0;
    for (int n = 0; n < max_samples; ++n) {
      std::fill(u.begin(), u.end(), 0.0);
      if (n == 0) u[j] = 1.0;
      it.step(u.data(), y.data());
      double now = 0.0, top = 0.0;
      for (size_t k = 0; k < ns; ++k) {
        const double v = std::abs(it.slots()[k]);
        l1[k] += v;
        peak[k] = std::max(peak[k], v);
        now = std::max(now, v);
        top = std::max(top, peak[k]);
      }
      // Decayed: everything (signals and states) below 1e-12 of the peak for a while.
      quiet = now <= 1e-12 * top ? quiet + 1 : 0;
      if (quiet >= 16) {
        decayed = true;
        break;
      }
    }
    for (size_t k = 0; k < ns; ++k)
      bound[k] += decayed ? l1[k] * source_bound[j] : (l1[k] > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
  }
  // Inputs and clamp outputs are bounded by their own ranges.
  for (size_t k = 0; k < p.inputs.size(); ++k) bound[static_cast<size_t>(p.inputs[k])] = source_bound[k];
  for (const auto* ops : {&p.output_ops, &p.update_ops})
    for (const Op& o : *ops)
      if (o.kind == OpKind::Clamp) bound[static_cast<size_t>(o.dst)] = std::max(std::abs(o.lo), std::abs(o.hi));
  return bound;
}

int q_format(double bound, int word_bits) {
  if (!(bound > 0.0)) return word_bits - 1;
  if (!std::isfinite(bound)) throw InputError("an unbounded signal has no fixed-point format");
  return word_bits - 2 - static_cast<int>(std::ceil(std::log2(bound)));
}

}  // namespace dmbd::codegen
