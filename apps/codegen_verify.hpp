#pragma once
// `dmbd codegen --verify`: compile the generated header, run it and the interpreter on
// the verification chirp and step, and (fixed point) check the exact program against
// the predicted error bound; the figures go into the report and on stdout.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "codegen_report.hpp"
#include "dmbd/codegen/emit.hpp"

namespace dmbd::apps {

struct VerifyOutcome {
  bool identical = true;     // generated code and interpreter agree bit for bit
  bool within_bound = true;  // fixed point: the error within its bound wherever its hypothesis held
};

// The harness is built in `out_dir`/.verify_<name> and removed afterwards.
VerifyOutcome verify_generated(const codegen::LoopProgram& program, codegen::Scalar scalar, const std::string& header,
                               const std::string& out_dir, const std::vector<Range>& ranges,
                               const codegen::FixedProgram* fixed, nlohmann::json& report);

}  // namespace dmbd::apps
