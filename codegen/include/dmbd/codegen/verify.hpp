#pragma once
// Built-in verification: compile the generated header with the system compiler, drive
// it and the interpreter with the same chirp and step, and compare.
#include <string>
#include <utility>
#include <vector>

#include "dmbd/codegen/emit.hpp"

namespace dmbd::codegen {

struct FixedProgram;

struct VerifyResult {
  double max_abs_error = 0.0;      // generated vs interpreter, over all outputs and samples
  double max_output = 0.0;         // largest |output| seen (scale for the error)
  double sqnr_db = 0.0;            // 10 log10(sum y_ref^2 / sum err^2); inf when identical
  long saturations = 0;            // fixed point only (0 here)
  double ns_per_step = 0.0;        // generated code, measured in the harness
  int samples = 0;
  std::string compiler_command;
  // Fixed point: the generated code against the exact (double) program, and the bound
  // predicted for that difference.
  double max_abs_error_vs_exact = 0.0;
  std::vector<double> predicted_bound;
};

// The verification input: for each input an exponential chirp from 0.1 Hz to 0.4 x the
// rate over `chirp_samples`, then a step, within its range [lo, hi].
std::vector<std::vector<double>> verification_inputs(const LoopProgram& p,
                                                     const std::vector<std::pair<double, double>>& ranges,
                                                     int chirp_samples = 4000, int step_samples = 2000);

// `header` is the path of the generated header; `work_dir` receives the harness, its
// binary and the data files. InputError when the compiler fails (its first error line
// in the message).
// With `fixed`, the header is the fixed-point one: compared bit for bit with the fixed
// interpreter, and against the double program within the predicted bound.
VerifyResult verify(const LoopProgram& p, Scalar scalar, const std::string& header, const std::string& work_dir,
                    const std::vector<std::pair<double, double>>& ranges, const FixedProgram* fixed = nullptr);

}  // namespace dmbd::codegen
