#pragma once
// `dmbd codegen DIAGRAM|--tf EXPR --rate HZ`: a C++ control loop (header), or with
// `--language c` a C99 one (header and source), from a diagram or a transfer function,
// with its report (codegen_report.hpp) and, with --verify, the generated code checked
// against the interpreter (codegen_verify.hpp).
#include <string>
#include <vector>

#include "command.hpp"

namespace dmbd::apps {

class CodegenCommand : public Command {
 public:
  explicit CodegenCommand(CLI::App& app);
  int run() override;

 private:
  std::string diagram_, tf_, rate_, method_, scalar_ = "double", word_ = "32", input_range_, name_, out_ = ".",
              language_ = "cpp", state_bits_ = "auto";
  std::vector<std::string> params_, block_methods_;
  bool verify_ = false;
};

}  // namespace dmbd::apps
