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
// One statement of the fixed-point program: an accumulation (a Mul and the Macs that
// follow it on the same slot), a copy or a clamp of the loop program, with its formats.
struct FixedStatement {
  // Sum: dst = narrow(sum of terms), each term aligned to Q(qacc) in a double-width
  // accumulator, narrowed once to the dst format (rounding half up, saturating). Copy:
  // dst = the word of terms[0].a converted to the dst format. Clamp: the word of
  // terms[0].a clamped to [lo, hi], then converted to the dst format.
  enum class Kind { Sum, Copy, Clamp } kind = Kind::Sum;  // this statement's kind
  int dst = 0;                  // the slot written (index into LoopProgram::slots)
  // The arithmetic path: 16 (16-bit words, Acc16 = 32-bit accumulator) or 32 (32-bit
  // words, Acc32 = 64-bit accumulator; 16-bit operands widen exactly). In a 16-bit
  // program a statement that reads or writes a 32-bit word (FixedProgram::bits) runs on
  // the 32-bit path, its coefficients quantised to 32-bit words.
  int bits = 32;
  int qacc = 0;                 // accumulator fractional bits (Sum)
  std::vector<FixedTerm> terms; // Sum; Copy/Clamp use terms[0].a
  // Clamp: the lower limit, a word in the format of the source slot terms[0].a (clamp
  // first, then convert: the source may exceed what the dst format holds).
  int64_t lo = 0, hi = 0;       // Clamp: the upper limit, in the same format
  int block = -1;               // index into LoopProgram::blocks, as the Op's (-1: a diagram output's copy)
  std::string note;             // what it computes, the Op::note of its first operation
  bool update = false;          // part of the state update
};

// A loop program's fixed-point realisation (make_fixed): a signed word of bits[k] bits
// per slot (word_bits, or state_bits for the slots widened: states and the signals the
// state update reads) in the Q format q[k] (value = word / 2^q[k]), and the statements that
// the fixed-point emitters print and FixedInterpreter runs. Indexed like
// LoopProgram::slots, valid with the program it was made from.
struct FixedProgram {
  int word_bits = 32;            // 16 or 32 (make_fixed refuses any other): inputs, outputs, signals
  int state_bits = 32;           // the word of widened slots: 32 (a 16-bit program may widen), or word_bits
  std::vector<int> bits;         // word bits per slot: word_bits, or state_bits where widened
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
  // outputs x inputs: the sum over the first `horizon` samples (zero for horizon <= 0).
  blocks::Matrix truncated, infinite;  // outputs x inputs: the whole sum (+inf: not decayed)
};
// The two L1 norms above of the discrete model ss (its sample time is not used). For a
// model without states both are |D| (truncated: when horizon >= 1). For an input whose
// response does not decay, the infinite sum is +inf for every output that has seen a
// non-zero sample of it or that sees the state that stays (the others keep their sum).
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
  // The two terms of over_horizon, per output: the rounding term (sum over the sources s)
  std::vector<double> rounding, coefficients;  // and the coefficient term (sum over the inputs i)
  int sources = 0;                   // rounding sources (one impulse response each)
};
// The bound above for the program p and its fixed realisation f (make_fixed of p), over
// `horizon` steps. input_ranges: [lo, hi] per program input, in the inputs' order (the
// magnitude R_i = max(|lo|, |hi|)); an input without one counts as R_i = 1, and an input
// with R_i = 0 contributes no coefficient term.
ErrorBound predicted_error_bound(const LoopProgram& p, const FixedProgram& f,
                                 const std::vector<std::pair<double, double>>& input_ranges, int horizon);

// The rounding term of the bound above, source by source: (outputs x slots) e_s ||g_s||
// over the first `horizon` steps, 0 for a slot where nothing rounds. What make_fixed
// reads to decide which words to widen.
blocks::Matrix rounding_contributions(const LoopProgram& p, const FixedProgram& f, int horizon);

// make_fixed's state_bits: chosen by the analysis (below).
constexpr int kStateBitsAuto = 0;

// The fixed-point realisation of p in signed words of word_bits bits (16 or 32): every
// slot's Q format from its bound (slot_bounds, then q_format in the slot's word), every
// coefficient other than 0 and +-1 quantised to the finest format its statement's word
// holds (F_c = bits - 2 - floor(log2 |c|), rounded to nearest), and the accumulators'
// formats by the runtime's headroom rule (G). input_ranges as slot_bounds takes them
// (default [-1, 1]). Slots without a guaranteed bound (a loop closed through a
// saturation, an integrator) take a simulated one: twice the largest value seen on the
// verification chirp and step.
//
// Wider states (16-bit programs): the candidates are the states and the signals the
// state update reads (the words of the recursion; never an input or an output, whose
// words are the interface). state_bits 16: none widened; 32: every candidate in a
// 32-bit word; kStateBitsAuto: the candidates whose rounding term (rounding_contributions
// of the all-16-bit program over kVerifySamples steps) exceeds, at some output, half an
// LSB of that output's format: where errors accumulate beyond the output's own
// resolution. A 32-bit program keeps every word at 32 bits (state_bits 32 or auto; the
// runtime has no 128-bit accumulator for 64-bit states). InputError when a bound
// diverges even on the simulation, for word_bits other than 16 or 32, or for a
// state_bits other than auto, word_bits or (16-bit programs) 32.
FixedProgram make_fixed(const LoopProgram& p, const std::vector<std::pair<double, double>>& input_ranges,
                        int word_bits, int state_bits = kStateBitsAuto);

// Runs the integer program with the runtime of the generated code, statement for
// statement, so that it matches the generated fixed-point code bit for bit; step()
// takes and returns words, step_real() real values (quantising the inputs and
// converting the outputs as step_real() of the generated code does).
class FixedInterpreter {
 public:
  // Keeps references to p and f (make_fixed of p): both must outlive the interpreter.
  // Every slot starts at 0.
  FixedInterpreter(const LoopProgram& p, const FixedProgram& f);
  // Every slot (states included), saturations() and clamp_events() to zero.
  void reset();
  // One sample in real values: u (one per program input) quantised to the inputs'
  // formats (rounding half up, saturating, a clamp counted), step(), and y (one per
  // output) the outputs' words converted exactly to double.
  void step_real(const double* u, double* y);
  void step(const int64_t* u, int64_t* y);  // words in each slot's format
  // Word saturations (results clamped to the word, inputs quantised by step_real()
  // included) since reset(); sticky at 2^32 - 1, as the generated saturations().
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
