#pragma once
// Built-in verification: compile the generated code (C++ header, or C header and source)
// with the system compiler, drive it and the interpreter with the same chirp and step,
// and compare.
#include <string>
#include <utility>
#include <vector>

#include "dmbd/codegen/emit.hpp"
#include "dmbd/codegen/emit_c.hpp"
#include "dmbd/codegen/fixed.hpp"

namespace dmbd::codegen {

// The verification input's length: an exponential chirp, then a step. Also the horizon
// of the fixed-point error bound that `dmbd codegen` reports.
constexpr int kVerifyChirpSamples = 4000, kVerifyStepSamples = 2000;  // the step: half at hi, half at lo
// The whole verification input, in samples (3 s at 2 kHz).
constexpr int kVerifySamples = kVerifyChirpSamples + kVerifyStepSamples;

// One run of the fixed program against the exact (double) program from reset, with the
// hypothesis of the error bound (fixed.hpp, predicted_error_bound) checked at every step:
// no saturation block engaged in either program, no word saturated in the fixed one.
struct BoundCheck {
  double scale = 0.0;              // the input: the verification input scaled by this (0: not run)
  int steps = 0;                   // steps run: the input's rows
  long clamp_steps_exact = 0;      // steps on which a saturation block engaged, exact program
  long clamp_steps_fixed = 0;      // the same, fixed program
  long saturation_steps = 0;       // steps on which the fixed program saturated a word
  long violation_steps = 0;        // steps on which any of the three happened
  int first_violation = -1;        // first step that broke the hypothesis; -1: it held throughout
  int covered_steps = 0;           // leading steps the bound covers: before first_violation, within the horizon
  std::vector<double> max_error;          // per output: max |fixed - exact| over the run
  std::vector<double> max_error_covered;  // per output: the same over the covered steps
  double max_vs_interpreter = 0.0;  // with the generated code's outputs: max |generated - fixed interpreter|
  // The run happened and the hypothesis held at every step of it (so the bound covers
  // every step within the horizon).
  bool hypothesis_held() const { return steps > 0 && first_violation < 0; }
  // Every output's error over the covered steps within its bound over the horizon.
  bool within(const ErrorBound& b) const;
};

// Runs the exact program and the fixed interpreter on `u` (one row per step, one real
// value per program input; the fixed interpreter quantises them as step_real()) from
// reset; scale is set to 1. `fixed_outputs` (one row of outputs per step, flattened:
// entry n * outputs + j): the generated code's outputs on the same input, compared with
// the exact program instead of the interpreter's (and with the interpreter's, bit for bit).
BoundCheck check_bound(const LoopProgram& p, const FixedProgram& f, const std::vector<std::vector<double>>& u,
                       int horizon, const std::vector<double>* fixed_outputs = nullptr);

// `u` scaled by `s` towards, per input, the point of its range nearest 0 (0 when the range
// contains it): c + s (u - c), still within the range for 0 <= s <= 1. An input without
// a range takes [-1, 1].
std::vector<std::vector<double>> scaled_inputs(const std::vector<std::vector<double>>& u,
                                               const std::vector<std::pair<double, double>>& ranges, double s);

// The largest s = 2^-k, k = 0 .. 40, for which the hypothesis of the bound holds on
// scaled_inputs(u, ranges, s) (exact and fixed interpreters); 0 when there is none.
double clamp_free_scale(const LoopProgram& p, const FixedProgram& f, const std::vector<std::vector<double>>& u,
                        const std::vector<std::pair<double, double>>& ranges);

// What verify() measured: the generated code against the interpreter of the same
// arithmetic (Interpreter in double or float, FixedInterpreter for fixed point) and, for
// fixed point, against the exact program with the predicted error bound.
struct VerifyResult {
  double max_abs_error = 0.0;      // generated vs interpreter, over all outputs and samples (fixed: of both runs)
  double max_output = 0.0;         // largest |output| seen (scale for the error)
  // y_ref: the exact (double) program for fixed point, else the interpreter (then inf
  // when the code is right); err: generated - y_ref; over all outputs and samples.
  double sqnr_db = 0.0;            // 10 log10(sum y_ref^2 / sum err^2); inf when identical
  // The generated fixed-point code's saturations() after the full run, its inputs
  // quantised apart (so not counted: unlike FixedInterpreter's); 0 in floating point.
  long saturations = 0;
  double ns_per_step = 0.0;        // generated code, measured in the harness
  int samples = 0;                 // steps of the verification input (kVerifySamples)
  std::string compiler_command;    // the command that built the harness (compile_command)
  // Fixed point: the generated code against the exact (double) program, and the bound
  // predicted for that difference over the verification run's length (the horizon).
  double max_abs_error_vs_exact = 0.0;  // over all outputs and samples of the full run
  ErrorBound bound;       // predicted_error_bound over `samples` steps (fixed point; empty otherwise)
  BoundCheck full;        // the verification input (scale 1)
  BoundCheck clamp_free;  // where the hypothesis failed on it: the generated code on the
                          // largest 2^-k scaled copy on which it holds (scale 0: none);
                          // otherwise the same as `full`
};

// The verification input: for each input an exponential chirp from 0.1 Hz to 0.4 x the
// rate over `chirp_samples`, then a step, within its range [lo, hi].
std::vector<std::vector<double>> verification_inputs(const LoopProgram& p,
                                                     const std::vector<std::pair<double, double>>& ranges,
                                                     int chirp_samples = kVerifyChirpSamples,
                                                     int step_samples = kVerifyStepSamples);

// The argument vector that compiles and links `sources` into `binary` with the flags
// generated code must compile with, and without floating-point contraction (so that C,
// C++ and the interpreter round alike whatever the compiler's default):
//   C++: c++ -std=c++11 -O2 -Wall -Wextra -Werror -fno-exceptions -fno-rtti -ffp-contract=off
//   C:   cc -std=c99 -O2 -Wall -Wextra -pedantic -Werror -ffp-contract=off
// then -o `binary` (none when it is empty) and the sources, each one word whatever its
// characters: started with run_program (base/process.hpp), no shell reads them.
std::vector<std::string> compile_arguments(Language language, const std::vector<std::string>& sources, const std::string& binary);

// The same as one line for sh (messages, reports, tests that run it through a shell):
// each path quoted so that any name survives; `extra` (more flags, e.g. -c) is put in
// verbatim after the flags.
std::string compile_command(Language language, const std::vector<std::string>& sources, const std::string& binary,
                            const std::string& extra = "");

// Compiles the generated code of `language` with a harness (compile_command), runs it
// and the interpreter of `scalar` on verification_inputs(p, ranges) (ranges: [lo, hi] per
// program input) and compares their outputs.
// `header` is the path of the generated header (C: <name>.h, its <name>.c beside it);
// `work_dir` receives the harness, its binary and the data files. InputError when the
// compiler fails (its first error line in the message), or when the harness fails to
// run or writes the wrong number of outputs (std::filesystem errors pass through).
// With `fixed`, the header is the fixed-point one: compared bit for bit with the fixed
// interpreter, and against the double program with the predicted bound, its hypothesis
// checked (on the full input, then if need be on a scaled copy: `clamp_free`); `scalar`
// is then unused. The compiler and the harness are started without a shell (an argument
// vector: run_program), so any path works; c++ (C: cc) must be on the PATH.
VerifyResult verify(const LoopProgram& p, Scalar scalar, const std::string& header, const std::string& work_dir,
                    const std::vector<std::pair<double, double>>& ranges, const FixedProgram* fixed = nullptr,
                    Language language = Language::Cpp);

}  // namespace dmbd::codegen
