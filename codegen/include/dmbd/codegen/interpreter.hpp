#pragma once
// The in-process interpreter of a loop program: exactly the emitted operation order
// and arithmetic, so that a double (or float) program gives bit-identical results to
// its generated code. No heap allocation in step().
#include <vector>

#include "dmbd/codegen/loop_program.hpp"

namespace dmbd::codegen {

// Runs a loop program in the scalar type T: double or float (the generated code's
// Scalar), one step() per sample period.
template <class T>
class Interpreter {
 public:
  // Keeps a reference to p, which must outlive the interpreter (and not change: the
  // coefficients are read once, here). Every slot starts at 0.
  explicit Interpreter(const LoopProgram& p) : p_(p), s_(p.slots.size(), T(0)) {
    // Coefficients rounded once to T, as the emitter prints them.
    for (const auto* ops : {&p.output_ops, &p.update_ops})
      for (const Op& o : *ops) coeff_.push_back({static_cast<T>(o.c), static_cast<T>(o.lo), static_cast<T>(o.hi)});
  }
  // Every slot (states included) and clamp_events() to zero, as the generated reset()
  // zeroes the states.
  void reset() {
    std::fill(s_.begin(), s_.end(), T(0));
    clamp_events_ = 0;
  }
  // One sample: u: one value per program input; y: one per output (in the order of
  // LoopProgram::inputs and outputs). The output operations, then y written, then the
  // state update.
  void step(const T* u, T* y) {
    for (size_t k = 0; k < p_.inputs.size(); ++k) s_[static_cast<size_t>(p_.inputs[k])] = u[k];
    size_t c = 0;
    run(p_.output_ops, c);
    for (size_t k = 0; k < p_.outputs.size(); ++k) y[k] = s_[static_cast<size_t>(p_.outputs[k])];
    run(p_.update_ops, c);
  }
  // Every slot's value after the last step(), indexed like LoopProgram::slots (the
  // states already advanced to the next step).
  const std::vector<T>& slots() const { return s_; }
  // Saturation blocks that engaged (input outside [lo, hi]) since construction or
  // reset(), counted per operation: the hypothesis of the fixed-point error bound
  // (docs/codegen.md) is that this stays 0.
  unsigned long long clamp_events() const { return clamp_events_; }
  // Direct access to the slots, for probing the program (states between steps).
  std::vector<T>& mutable_slots() { return s_; }

 private:
  struct Coeff {
    T c, lo, hi;
  };
  void run(const std::vector<Op>& ops, size_t& c) {
    for (const Op& o : ops) {
      const Coeff& k = coeff_[c++];
      T& dst = s_[static_cast<size_t>(o.dst)];
      const T a = s_[static_cast<size_t>(o.a)];
      switch (o.kind) {
        case OpKind::Mul:
          dst = o.c == 1.0 ? a : o.c == -1.0 ? -a : k.c * a;
          break;
        case OpKind::Mac:
          dst = o.c == 1.0 ? dst + a : o.c == -1.0 ? dst - a : dst + k.c * a;
          break;
        case OpKind::Copy:
          dst = a;
          break;
        case OpKind::Clamp:
          // The same result as a < lo ? lo : (a > hi ? hi : a), as emitted.
          if (a < k.lo) {
            dst = k.lo;
            ++clamp_events_;
          } else if (a > k.hi) {
            dst = k.hi;
            ++clamp_events_;
          } else {
            dst = a;
          }
          break;
      }
    }
  }
  const LoopProgram& p_;
  std::vector<T> s_;
  std::vector<Coeff> coeff_;
  unsigned long long clamp_events_ = 0;
};

}  // namespace dmbd::codegen
