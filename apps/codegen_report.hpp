#pragma once
// The report `dmbd codegen` writes next to the header: <name>.report.json and a readable
// <name>.report.md. Blocks and their realisation; every signal's bound and Q format;
// for fixed point the predicted error bound per output, the poles and frequency
// response of the quantised loop, and warnings (an error bound beyond an output's range).
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dmbd/codegen/fixed.hpp"
#include "dmbd/codegen/loop_program.hpp"

namespace dmbd::apps {

using Range = std::pair<double, double>;

struct CodegenSource {
  std::string text;                                 // "the diagram examples/...yaml"
  std::string scalar;                               // "double", "float", "fixed 16-bit"
  std::string language = "cpp";                     // of the generated code: "cpp" or "c"
  std::vector<Range> input_ranges;                  // per program input
  std::vector<std::optional<Range>> output_ranges;  // per program output, where the diagram gives one
  std::vector<std::string> output_units;
};

nlohmann::json codegen_report(const codegen::LoopProgram& program, const codegen::FixedProgram* fixed,
                              const CodegenSource& source);

// Writes the report's two files (atomically) into `dir`.
void write_codegen_report(const nlohmann::json& report, const std::string& dir, const std::string& name);

}  // namespace dmbd::apps
