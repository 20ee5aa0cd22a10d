#pragma once
// Fixed-point realisation of a loop program: a Q format for every slot and every
// coefficient, chosen from guaranteed ranges, and an interpreter that runs the integer
// arithmetic of the generated code (the runtime fragment codegen/runtime/fixed_point.inc,
// compiled into this library unchanged), so that both agree bit for bit.
#include <cstdint>
#include <string>
#include <utility>
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
// identity), by probing: one step from each unit state and each unit input. With
// `inject_at`, one more input per listed slot, added to that slot right after its last
// writer in the step (at the start of the step for a slot nothing writes, e.g. a program
// input): where a fixed-point narrowing puts its rounding error.
blocks::StateSpace program_state_space(const LoopProgram& p, const std::vector<int>& inject_at = {});

// L1 norms of the impulse responses h_k = D (k = 0), C A^(k-1) B (k >= 1) of a discrete
// model, per output and input, from one simulation of all inputs at once:
//   truncated(i, j) = sum_{k < horizon} |h_k(i, j)|   (exactly horizon samples), and
//   infinite(i, j)  = the whole sum, cut where input j's state response has fallen below
//                     1e-13 of its peak for 16 samples; +inf where it has not decayed
//                     (an integrator, an unstable pole) within max_samples.
// Cost: horizon x n (n + p) multiply-adds per input (n states, p outputs), then, for the
// infinite sums, the same per step for the inputs whose response has not yet decayed,
// after one check of A^max_samples x (log2(max_samples) products of n x n matrices)
// that declares +inf at once the ones that will not decay.
struct ImpulseL1 {
  blocks::Matrix truncated, infinite;
};
ImpulseL1 impulse_l1(const blocks::StateSpace& ss, int horizon, int max_samples = 200000);

// Worst-case |fixed - exact| per output (exact: the program in double), for inputs within
// their ranges, from reset:
//   sum over rounding sources s of e_s * ||g_s||  +  sum over inputs i of R_i * ||hq_i - h_i||
// e_s: the largest error one step adds at slot s (half an LSB of its format for a rounded
// narrowing, or an input's quantisation; one LSB of the accumulator per term aligned by a
// floor shift); g_s: the impulse response from an injection at s to the output in the
// quantised program (the fixed program's coefficients); hq_i - h_i: the difference of the
// quantised and exact programs' impulse responses from input i; R_i: the input's largest
// magnitude. ||.|| is the L1 norm over the first `horizon` samples (over_horizon), or over
// all samples (infinite; +inf where rounding errors accumulate without bound, e.g. an
// integrator or integral action in the linear part).
//
// Hypothesis (the analysis is of the linear part): on the run, no saturation block
// engages (its input outside its limits) in the exact or the fixed program and no word
// saturates in the fixed one. Then both programs are their linear parts and the bound
// holds at every step up to the horizon; since outputs depend only on past steps, it
// still holds at every step before the first one that breaks the hypothesis.
struct ErrorBound {
  int horizon = 0;                   // N, steps from reset
  std::vector<double> over_horizon;  // per output: worst case over the first N steps
  std::vector<double> infinite;      // per output: over any number of steps (+inf: none)
  std::vector<double> rounding, coefficients;  // the two terms of over_horizon
  int sources = 0;                   // rounding sources (one impulse response each)
};
ErrorBound predicted_error_bound(const LoopProgram& p, const FixedProgram& f,
                                 const std::vector<std::pair<double, double>>& input_ranges, int horizon);

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
  // Saturation blocks that engaged (input word outside the limits) since reset().
  unsigned long long clamp_events() const { return clamp_events_; }

 private:
  const LoopProgram& p_;
  const FixedProgram& f_;
  std::vector<int64_t> s_;
  std::vector<int64_t> in_, out_;
  uint32_t saturations_ = 0;
  unsigned long long clamp_events_ = 0;
};

}  // namespace dmbd::codegen
