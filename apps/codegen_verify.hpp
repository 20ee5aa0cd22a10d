#pragma once
// `dmbd codegen --verify`: compile the generated code (C++ or C), run it and the interpreter on
// the verification chirp and step, and (fixed point) check the exact program against
// the predicted error bound; the figures go into the report and on stdout.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "codegen_report.hpp"
#include "dmbd/codegen/emit.hpp"
#include "dmbd/codegen/emit_c.hpp"

namespace dmbd::apps {

struct VerifyOutcome {
  bool identical = true;     // generated code and interpreter agree bit for bit
  bool within_bound = true;  // fixed point: the error within its bound wherever its hypothesis held
};

// The harness is built in `out_dir`/.verify_<name> and removed afterwards. `header`: the
// generated C++ header, or for C the generated <name>.h (its <name>.c beside it).
VerifyOutcome verify_generated(const codegen::LoopProgram& program, codegen::Scalar scalar, const std::string& header,
                               const std::string& out_dir, const std::vector<Range>& ranges,
                               const codegen::FixedProgram* fixed, nlohmann::json& report,
                               codegen::Language language = codegen::Language::Cpp);

}  // namespace dmbd::apps
