#pragma once
// Fixed-point realisation of a loop program: a Q format for every slot and every
// coefficient, chosen from guaranteed ranges, and an interpreter that runs the integer
// arithmetic of the generated code (the runtime fragment codegen/runtime/fixed_point.inc,
// compiled into this library unchanged), so that both agree bit for bit.
#include <cstdint>
#include <vector>

#include "dmbd/blocks/state_space.hpp"
#include "dmbd/codegen/loop_program.hpp"

namespace dmbd::codegen {

// One accumulation: dst = narrow(sum of terms) in the slot's format.
struct FixedTerm {
  int a = 0;          // source slot
  int sign = 1;       // +1 / -1 when the coefficient is exactly +-1 (no multiply)
  int64_t c = 0;      // quantised coefficient (word), when sign == 0
  int qc = 0;         // its fractional bits
};
struct FixedStatement {
  enum class Kind { Sum, Copy, Clamp } kind = Kind::Sum;
  int dst = 0;
  int qacc = 0;                 // accumulator fractional bits (Sum)
  std::vector<FixedTerm> terms; // Sum; Copy/Clamp use terms[0].a
  int64_t lo = 0, hi = 0;       // Clamp limits in the dst format
  int block = -1;
  std::string note;
  bool update = false;          // part of the state update
};

struct FixedProgram {
  int word_bits = 32;
  std::vector<int> q;            // fractional bits per slot
  std::vector<double> bound;     // |value| per slot: guaranteed, or simulated where not
  std::vector<bool> simulated;   // the bound of this slot is simulated (2 x the largest
                                 // value on the verification chirp and step), not guaranteed
  std::vector<FixedStatement> statements;  // output statements, then update statements
  // The program with every coefficient replaced by its quantised value (for the
  // report: what quantisation did to the loop).
  LoopProgram quantised;
};

// The linear part of a program as a discrete state-space model (saturations taken as
// identity), by probing: one step from each unit state and each unit input.
blocks::StateSpace program_state_space(const LoopProgram& p);

// Worst-case |fixed - exact| per output for inputs within their ranges: the rounding
// at every narrowing (half an LSB of its format, and one LSB of the accumulator for
// every term aligned by a floor shift) times the L1 gain from that point to the output, plus the
// effect of the quantised coefficients (the L1 norm of the difference between the
// quantised and the exact programs' impulse responses times the input bounds).
std::vector<double> predicted_error_bound(const LoopProgram& p, const FixedProgram& f,
                                          const std::vector<std::pair<double, double>>& input_ranges);

// Slots without a guaranteed bound (a loop closed through a saturation, an integrator)
// take a simulated one: twice the largest value seen on the verification chirp and
// step. InputError when even that diverges.
FixedProgram make_fixed(const LoopProgram& p, const std::vector<std::pair<double, double>>& input_ranges,
                        int word_bits);

// Runs the integer program; step() takes and returns real values (quantising the inputs
// and converting the outputs as step_real() of the generated code does).
class FixedInterpreter {
 public:
  FixedInterpreter(const LoopProgram& p, const FixedProgram& f);
  void reset();
  void step_real(const double* u, double* y);
  void step(const int64_t* u, int64_t* y);  // words in each slot's format
  uint32_t saturations() const { return saturations_; }

 private:
  const LoopProgram& p_;
  const FixedProgram& f_;
  std::vector<int64_t> s_;
  std::vector<int64_t> in_, out_;
  uint32_t saturations_ = 0;
};

}  // namespace dmbd::codegen
