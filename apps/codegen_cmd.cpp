#include "codegen_cmd.hpp"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>

#include "cli_values.hpp"
#include "codegen_report.hpp"
#include "codegen_verify.hpp"
#include "dmbd/base/error.hpp"
#include "dmbd/base/file.hpp"
#include "dmbd/codegen/emit.hpp"
#include "dmbd/codegen/emit_c.hpp"
#include "dmbd/codegen/fixed.hpp"
#include "dmbd/diagrams/diagram.hpp"

namespace dmbd::apps {

namespace b = dmbd::blocks;
namespace cg = dmbd::codegen;

CodegenCommand::CodegenCommand(CLI::App& app)
    : Command(app, "codegen", "Generate a C++ or C control loop from a diagram or a transfer function") {
  cmd_->add_option("diagram", diagram_, "A diagram file (YAML)");
  cmd_->add_option("--tf", tf_, "A transfer function instead of a diagram");
  cmd_->add_option("--rate", rate_, "Loop rate in Hz")->required();
  cmd_->add_option("--method", method_,
                   "Discretisation of continuous blocks: tustin, zoh, backward-euler (default: the diagram's "
                   "`discretization`, else tustin)");
  cmd_->add_option("--block-method", block_methods_, "BLOCK=METHOD: another method for one block; repeatable");
  cmd_->add_option("--scalar", scalar_, "double (default), float or fixed");
  cmd_->add_option("--word", word_, "Fixed-point word: 16 or 32 bits (default 32)");
  cmd_->add_option("--state-bits", state_bits_,
                   "Fixed-point words of the state update: auto (default: 32 bits where the range analysis needs them, in "
                   "a 16-bit program), 16 or 32");
  cmd_->add_option("--language", language_, "cpp (default: <name>.hpp) or c (C99: <name>.h and <name>.c)");
  cmd_->add_option("--input-range", input_range_, "LO:HI of every input where the diagram gives none (verification)");
  cmd_->add_option("--name", name_, "Namespace (C: symbol prefix) and file name (default: the diagram's name, or 'tf')");
  cmd_->add_option("--out", out_, "Output folder (default .)");
  cmd_->add_option("--param", params_, "NAME=VALUE parameter override; repeatable");
  cmd_->add_flag("--verify", verify_, "Compile the generated code and compare it with the interpreter on a chirp and a step");
}

namespace {

cg::LowerOptions lower_options(const std::string& rate, const std::string& method, const std::vector<std::string>& block_methods,
                               const b::ParameterMap& params) {
  cg::LowerOptions lo;
  lo.rate_hz = parse_number(rate, "--rate", params);
  if (!(lo.rate_hz > 0.0) || !std::isfinite(lo.rate_hz)) throw InputError("--rate '" + rate + "': expected a rate > 0 Hz");
  lo.method = b::parse_c2d_method(method.empty() ? "tustin" : method);
  for (const std::string& bm : block_methods) {
    const auto eq = bm.find('=');
    if (eq == std::string::npos) throw InputError("--block-method '" + bm + "': expected BLOCK=METHOD");
    lo.block_methods.push_back({bm.substr(0, eq), b::parse_c2d_method(bm.substr(eq + 1))});
  }
  return lo;
}

std::optional<Range> parse_range(const std::string& text, const b::ParameterMap& params) {
  if (text.empty()) return std::nullopt;
  const auto parts = split(text, ':');
  if (parts.size() != 2) throw InputError("--input-range '" + text + "': expected LO:HI");
  const Range r{parse_number(parts[0], "--input-range", params), parse_number(parts[1], "--input-range", params)};
  if (!(r.first < r.second)) throw InputError("--input-range '" + text + "': LO must be below HI");
  return r;
}

// The program, and where it came from: its inputs' ranges, its outputs' ranges and units.
struct Generated {
  cg::LoopProgram program;
  CodegenSource source;
};

Generated from_tf(const std::string& tf, const b::ParameterMap& params, const cg::LowerOptions& lo,
                  const std::optional<Range>& range) {
  const b::TransferFunction g = [&] {
    try {
      return b::TransferFunction::parse(tf, params);
    } catch (InputError& e) {
      e.prepend("--tf '" + tf + "': ");
      throw;
    }
  }();
  Generated out{cg::lower(g, "tf", lo), {}};
  out.source.text = "the transfer function " + tf;
  out.source.input_ranges.push_back(range.value_or(Range{-1.0, 1.0}));
  out.source.output_ranges.push_back(std::nullopt);
  out.source.output_units.push_back("");
  return out;
}

Generated from_diagram(const std::string& file, const b::ParameterMap& params, cg::LowerOptions lo, bool method_given,
                       const std::optional<Range>& range) {
  const auto d = diagrams::Diagram::load(file, params);
  // The diagram's own `discretization` unless --method is given.
  if (!method_given && d->discretization()) lo.method = *d->discretization();
  Generated out{cg::lower(*d, lo), {}};
  out.source.text = "the diagram " + file;
  for (const auto& in : d->inputs())
    for (int k = 0; k < in.size; ++k)
      out.source.input_ranges.push_back(in.range.value_or(range.value_or(Range{-1.0, 1.0})));
  for (const auto& o : d->outputs())
    for (int k = 0; k < o.size; ++k) {
      out.source.output_ranges.push_back(o.range);
      out.source.output_units.push_back(o.unit);
    }
  return out;
}

void check_identifier(const std::string& name) {
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_'))
      throw InputError("--name '" + name + "': expected a C or C++ identifier");
}

}  // namespace

int CodegenCommand::run() {
  const bool tf_given = cmd_->get_option("--tf")->count() > 0;
  const b::ParameterMap params = parse_params(params_);
  if (diagram_.empty() != tf_given)
    throw InputError(tf_given ? "give either a diagram file or --tf, not both" : "give a diagram file or --tf EXPR");
  const cg::LowerOptions lo = lower_options(rate_, method_, block_methods_, params);
  if (scalar_ != "double" && scalar_ != "float" && scalar_ != "fixed")
    throw InputError("--scalar '" + scalar_ + "': expected double, float or fixed");
  const bool fixed = scalar_ == "fixed";
  const cg::Scalar scalar = scalar_ == "float" ? cg::Scalar::Float : cg::Scalar::Double;
  if (word_ != "32" && word_ != "16") throw InputError("--word '" + word_ + "': expected 16 or 32");
  if (state_bits_ != "auto" && state_bits_ != "16" && state_bits_ != "32")
    throw InputError("--state-bits '" + state_bits_ + "': expected auto, 16 or 32");
  if (word_ == "32" && state_bits_ == "16")
    throw InputError("--state-bits 16: narrower than the 32-bit word (--word 32 takes auto or 32)");
  const int state_bits = state_bits_ == "auto" ? cg::kStateBitsAuto : std::stoi(state_bits_);
  if (language_ != "cpp" && language_ != "c") throw InputError("--language '" + language_ + "': expected c or cpp");
  const cg::Language language = language_ == "c" ? cg::Language::C : cg::Language::Cpp;
  check_output_folder(out_, "--out");
  const std::optional<Range> range = parse_range(input_range_, params);
  Generated gen = tf_given ? from_tf(tf_, params, lo, range) : from_diagram(diagram_, params, lo, !method_.empty(), range);
  cg::LoopProgram& program = gen.program;
  if (!name_.empty()) program.name = name_;
  check_identifier(program.name);
  gen.source.scalar = fixed ? "fixed " + word_ + "-bit" : std::string(cg::to_string(scalar));
  gen.source.language = cg::to_string(language);
  // C++: <name>.hpp; C: <name>.h and <name>.c.
  auto path = [&](const char* ext) { return (std::filesystem::path(out_) / (program.name + ext)).string(); };
  const std::string header = path(language == cg::Language::C ? ".h" : ".hpp");
  std::vector<std::string> files{header, path(".report.json"), path(".report.md")};
  if (language == cg::Language::C) files.push_back(path(".c"));
  for (const std::string& file : files) check_output_file(file, "--out");

  std::optional<cg::FixedProgram> fx;
  if (fixed) fx = cg::make_fixed(program, gen.source.input_ranges, word_ == "32" ? 32 : 16, state_bits);
  const nlohmann::json base = codegen_report(program, fx ? &*fx : nullptr, gen.source);
  const cg::EmitOptions eo{scalar, gen.source.text};
  std::string wrote = header;
  if (language == cg::Language::C) {
    const cg::CFiles c = fixed ? cg::emit_fixed_c(program, *fx, eo) : cg::emit_c(program, eo);
    write_file_atomic(header, c.header);
    write_file_atomic(path(".c"), c.source);
    wrote += " and " + path(".c");
  } else {
    write_file_atomic(header, fixed ? cg::emit_fixed_header(program, *fx, eo) : cg::emit_header(program, eo));
  }
  std::cout << "wrote " << wrote << " (" << program.states.size() << " states, "
            << program.output_ops.size() + program.update_ops.size() << " operations per step)\n";
  for (const auto& w : base["warnings"]) std::cout << "warning: " << w.get<std::string>() << "\n";
  nlohmann::json report = base;
  VerifyOutcome v;
  if (verify_)
    v = verify_generated(program, scalar, header, out_, gen.source.input_ranges, fx ? &*fx : nullptr, report, language);
  write_codegen_report(report, out_, program.name);
  if (!v.identical) {
    std::cerr << "dmbd: error: generated code differs from the interpreter (it must be bit-identical)\n";
    return 1;
  }
  if (!v.within_bound) {
    std::cerr << "dmbd: error: the fixed-point error exceeds its predicted bound on steps where the bound's "
                 "hypothesis held (a defect of the generator or of the bound)\n";
    return 1;
  }
  return 0;
}

}  // namespace dmbd::apps
