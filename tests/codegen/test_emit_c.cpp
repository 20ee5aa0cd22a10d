// The C emitter (issue 16, item 4): for every diagram in examples/diagrams and each of
// double, float, 16- and 32-bit fixed point, the generated C compiles clean under
// `cc -std=c99 -Wall -Wextra -pedantic -Werror` (and stricter warnings, and clang), and on the
// verification chirp and step gives the same bits as the generated C++ and as the
// interpreter (memcmp of the outputs, and the same saturation count). One compiler call
// builds all C sources of a scalar type, one more the C harness, one the C++ harness.
// Both harnesses feed step_real() the same doubles; for fixed point its outputs are the
// words times 2^-q, exactly, so equal doubles are equal words.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "dmbd/codegen/emit.hpp"
#include "dmbd/codegen/emit_c.hpp"
#include "dmbd/codegen/fixed.hpp"
#include "dmbd/codegen/interpreter.hpp"
#include "dmbd/codegen/loop_program.hpp"
#include "dmbd/codegen/verify.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "codegen_examples.hpp"
#include "test_support.hpp"

namespace dmbd::codegen {
namespace {

namespace fs = std::filesystem;
using namespace test;
using Ranges = std::vector<std::pair<double, double>>;

// Warnings beyond the contract's that the generated C is also clean under.
const char* const kStrictC =
    "-Wconversion -Wsign-conversion -Wshadow -Wstrict-prototypes -Wmissing-prototypes -Wold-style-definition "
    "-Wdouble-promotion -Wfloat-equal -Wcast-qual -Wundef -Wredundant-decls";

struct Example {
  std::string name;
  LoopProgram p;
  Ranges ranges;
  Sequence u;  // the verification chirp and step
};

// Every diagram in examples/diagrams at 2 kHz, with its own discretisation method.
const std::vector<Example>& examples() {
  static const std::vector<Example> all = [] {
    const std::vector<std::string> names = dmbd::test::codegen_example_names(kExamples);
    std::vector<Example> out;
    for (const std::string& name : names) {
      const auto d = diagrams::Diagram::load(kExamples + "/diagrams/" + name + ".yaml");
      LowerOptions o = at(2000.0);
      if (d->discretization()) o.method = *d->discretization();
      Example x{name, lower(*d, o), {}, {}};
      for (const auto& in : d->inputs())
        for (int k = 0; k < in.size; ++k) x.ranges.push_back(in.range.value_or(std::make_pair(-1.0, 1.0)));
      x.u = verification_inputs(x.p, x.ranges);
      out.push_back(std::move(x));
    }
    return out;
  }();
  return all;
}

struct Config {
  const char* tag;
  Scalar scalar;
  int word;  // 0: floating point
};

std::vector<double> read_doubles(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::vector<double> v;
  double x;
  while (f.read(reinterpret_cast<char*>(&x), sizeof x)) v.push_back(x);
  return v;
}

void write_doubles(const std::string& path, const Sequence& u) {
  std::ofstream f(path, std::ios::binary);
  for (const auto& row : u) f.write(reinterpret_cast<const char*>(row.data()), static_cast<std::streamsize>(row.size() * sizeof(double)));
}

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size())) s.replace(at, from.size(), to);
  return s;
}

// A harness function that runs one program's step_real() over a file of inputs and
// writes the outputs, then the saturation count (as a double). $-names are filled in
// per language: C (the generated .h) and C++ (the generated .hpp); the C++ harness runs
// the C code too, through the C header included from C++ (extern "C").
const char* const kRunner = R"(static int run_$ID(const char* in_path, const char* out_path) {
  $STATE
  double u[$NI], y[$NO], saturations;
  FILE* in = fopen(in_path, "rb");
  FILE* out = fopen(out_path, "wb");
  if (!in || !out) return 1;
  $RESET
  while (fread(u, sizeof(double), (size_t)$NI, in) == (size_t)$NI) {
    $STEP
    fwrite(y, sizeof(double), (size_t)$NO, out);
  }
  saturations = $SATURATIONS;
  fwrite(&saturations, sizeof saturations, 1, out);
  fclose(in);
  fclose(out);
  return 0;
}
)";

std::string c_runner(const std::string& n, bool fixed, const std::string& id) {
  const std::string N = c_macro_prefix(n);
  std::string r = replace_all(kRunner, "$ID", id);
  r = replace_all(r, "$STATE", n + "_state c;");
  r = replace_all(r, "$NI", N + "_NUM_INPUTS");
  r = replace_all(r, "$NO", N + "_NUM_OUTPUTS");
  r = replace_all(r, "$RESET", n + "_reset(&c);");
  r = replace_all(r, "$STEP", n + "_step_real(&c, u, y);");
  return replace_all(r, "$SATURATIONS", fixed ? "(double)" + n + "_saturations(&c)" : std::string("0.0"));
}

std::string cpp_runner(const std::string& n, bool fixed) {
  std::string r = replace_all(kRunner, "$ID", "cpp_" + n);
  r = replace_all(r, "$STATE", n + "::Controller c;");
  r = replace_all(r, "$NI", n + "::kNumInputs");
  r = replace_all(r, "$NO", n + "::kNumOutputs");
  r = replace_all(r, "$RESET", "c.reset();");
  r = replace_all(r, "$STEP", "c.step_real(u, y);");
  return replace_all(r, "$SATURATIONS", fixed ? "static_cast<double>(c.saturations())" : std::string("0.0"));
}

// main(): runs every program; argv holds its input file, then one output file per runner.
std::string harness_main(const std::vector<std::string>& runners) {
  std::string m = "int main(int argc, char** argv) {\n  int rc = 0, a = 1;\n  (void)argc;\n";
  for (const std::string& r : runners) m += "  rc |= run_" + r + "(argv[a], argv[a + 1]);\n  a += 2;\n";
  return m + "  return rc;\n}\n";
}

int run(const std::string& command, const std::string& log) {
  return std::system((command + " > '" + log + "' 2>&1").c_str());
}

// The interpreter's outputs on u (step_real for fixed point), then its saturation count.
std::vector<double> interpreted(const Example& x, const Config& cfg, const FixedProgram* f) {
  std::vector<double> out;
  if (f) {
    FixedInterpreter fi(x.p, *f);
    std::vector<double> y(x.p.outputs.size());
    for (const auto& row : x.u) {
      fi.step_real(row.data(), y.data());
      out.insert(out.end(), y.begin(), y.end());
    }
    out.push_back(static_cast<double>(fi.saturations()));
    return out;
  }
  const Sequence ys = cfg.scalar == Scalar::Float ? interpret<float>(x.p, x.u) : interpret<double>(x.p, x.u);
  for (const auto& row : ys) out.insert(out.end(), row.begin(), row.end());
  out.push_back(0.0);
  return out;
}

::testing::AssertionResult same_bits(const std::vector<double>& got, const std::vector<double>& want) {
  if (got.size() != want.size()) return ::testing::AssertionFailure() << got.size() << " values, want " << want.size();
  if (std::memcmp(got.data(), want.data(), got.size() * sizeof(double)) == 0) return ::testing::AssertionSuccess();
  size_t k = 0;
  while (std::memcmp(&got[k], &want[k], sizeof(double)) == 0) ++k;
  return ::testing::AssertionFailure() << "first difference at value " << k << ": " << got[k] << " vs " << want[k];
}

// Static checks of one program's C files.
void check_c_text(const LoopProgram& p, const CFiles& c, const Config& cfg) {
  const std::string hcode = code_only(c.header), ccode = code_only(c.source);
  for (const char* word : {"malloc", "calloc", "realloc", "free", "printf", "abort", "exit"})
    EXPECT_FALSE(std::regex_search(hcode + ccode, std::regex(std::string("\\b") + word + "\\b"))) << word;
  for (const std::string& l : lines(hcode + ccode))
    if (l.find("#include") != std::string::npos) {
      EXPECT_TRUE(l.find("<math.h>") != std::string::npos || l.find("<stdint.h>") != std::string::npos ||
                  l.find("\"" + p.name + ".h\"") != std::string::npos)
          << l;
    }
  const std::string n = p.name, N = c_macro_prefix(n), T = cfg.word ? (cfg.word == 32 ? "int32_t" : "int16_t") : to_string(cfg.scalar);
  EXPECT_NE(hcode.find("#define " + N + "_SAMPLE_TIME " + literal(p.ts, Scalar::Double)), std::string::npos);
  EXPECT_NE(hcode.find("#define " + N + "_NUM_INPUTS " + std::to_string(p.inputs.size())), std::string::npos);
  EXPECT_NE(hcode.find("typedef " + T + " " + n + "_input;"), std::string::npos);
  for (const std::string& decl :
       {"void " + n + "_reset(" + n + "_state* self);", "void " + n + "_step(" + n + "_state* self, const " + n + "_input* u, " + n + "_output* y);",
        "void " + n + "_step_real(" + n + "_state* self, const double* u, double* y);"})
    EXPECT_NE(hcode.find(decl), std::string::npos) << decl;
  if (cfg.word) {
    EXPECT_NE(hcode.find("uint32_t " + n + "_saturations(const " + n + "_state* self);"), std::string::npos);
  }
  EXPECT_NE(c.header.find("generated by dmbd"), std::string::npos);
  expect_commented_statements(p, c.header + c.source, "_step_real(");  // the block list is in the header
  if (cfg.scalar == Scalar::Float && !cfg.word) expect_float_literals(ccode, n + "_step(", n + "_step_real(");
}

// One scalar type over every example: C and C++ built, run on the same inputs, compared
// with each other and with the interpreter, bit for bit.
void check_config(const Config& cfg) {
  const std::string dir = fresh_dir(std::string("c_") + cfg.tag);
  std::vector<std::optional<FixedProgram>> fixed;
  std::vector<std::string> c_sources, objects, c_runners, cpp_runners, args;
  std::string c_harness = "#include <stdio.h>\n", cpp_harness = "#include <stdio.h>\n", c_funcs, cpp_funcs;
  for (const Example& x : examples()) {
    SCOPED_TRACE(x.name);
    const LoopProgram& p = x.p;
    fixed.emplace_back();
    if (cfg.word) fixed.back() = make_fixed(p, x.ranges, cfg.word);
    const FixedProgram* f = cfg.word ? &*fixed.back() : nullptr;
    const EmitOptions eo{cfg.scalar, "examples/diagrams/" + x.name + ".yaml"};
    const CFiles c = f ? emit_fixed_c(p, *f, eo) : emit_c(p, eo);
    check_c_text(p, c, cfg);
    std::ofstream(dir + "/" + p.name + ".h") << c.header;
    std::ofstream(dir + "/" + p.name + ".c") << c.source;
    std::ofstream(dir + "/" + p.name + ".hpp") << (f ? emit_fixed_header(p, *f, eo) : emit_header(p, eo));
    write_doubles(dir + "/in_" + p.name + ".bin", x.u);
    c_sources.push_back(dir + "/" + p.name + ".c");
    objects.push_back(dir + "/" + p.name + ".o");
    c_harness += "#include \"" + p.name + ".h\"\n";
    cpp_harness += "#include \"" + p.name + ".hpp\"\n#include \"" + p.name + ".h\"\n";
    c_funcs += c_runner(p.name, f != nullptr, "c_" + p.name);
    cpp_funcs += cpp_runner(p.name, f != nullptr) + c_runner(p.name, f != nullptr, "c_from_cpp_" + p.name);
    c_runners.push_back("c_" + p.name);
    cpp_runners.push_back("cpp_" + p.name);
    cpp_runners.push_back("c_from_cpp_" + p.name);
  }
  // The C sources: one call, the contract's flags and stricter ones.
  ASSERT_EQ(run("cd '" + dir + "' && " + compile_command(Language::C, c_sources, "", std::string("-c ") + kStrictC), dir + "/c.log"), 0)
      << read_text(dir + "/c.log");
  EXPECT_EQ(read_text(dir + "/c.log"), "") << "the compiler said something";
  // clang too, where installed (it warns of what GCC does not: an unused static function,
  // a variable set but never read); and the C++ headers, with the C headers from C++.
  if (std::system("command -v clang > /dev/null 2>&1 && command -v clang++ > /dev/null 2>&1") == 0) {
    std::string sources;
    for (const std::string& c : c_sources) sources += " '" + c + "'";
    EXPECT_EQ(run("clang -std=c99 -Wall -Wextra -pedantic -Werror -fsyntax-only" + sources, dir + "/clang.log"), 0)
        << read_text(dir + "/clang.log");
    std::ofstream(dir + "/headers.cpp") << cpp_harness;
    EXPECT_EQ(run("clang++ -std=c++11 -Wall -Wextra -Werror -fno-exceptions -fno-rtti -fsyntax-only '" + dir + "/headers.cpp'",
                  dir + "/clang++.log"),
              0)
        << read_text(dir + "/clang++.log");
  } else {
    std::cout << "clang not found: the C is checked with cc only\n";
  }
  // Every external symbol of a program's object starts with the program's name.
  for (const Example& x : examples()) {
    ASSERT_EQ(run("nm -g --defined-only '" + dir + "/" + x.p.name + ".o' | awk '{print $3}'", dir + "/nm.log"), 0);
    const auto symbols = lines(read_text(dir + "/nm.log"));
    EXPECT_GE(symbols.size(), 3u) << x.name;
    for (const std::string& s : symbols) EXPECT_EQ(s.rfind(x.p.name + "_", 0), 0u) << x.name << ": symbol " << s;
  }
  std::ofstream(dir + "/harness.c") << c_harness << c_funcs << harness_main(c_runners);
  std::ofstream(dir + "/harness.cpp") << cpp_harness << cpp_funcs << harness_main(cpp_runners);
  std::vector<std::string> c_link{dir + "/harness.c"}, cpp_link{dir + "/harness.cpp"};
  c_link.insert(c_link.end(), objects.begin(), objects.end());
  cpp_link.insert(cpp_link.end(), objects.begin(), objects.end());
  ASSERT_EQ(run(compile_command(Language::C, c_link, dir + "/run_c"), dir + "/c_link.log"), 0) << read_text(dir + "/c_link.log");
  ASSERT_EQ(run(compile_command(Language::Cpp, cpp_link, dir + "/run_cpp"), dir + "/cpp.log"), 0)
      << read_text(dir + "/cpp.log");
  std::string c_args, cpp_args;
  for (const Example& x : examples()) {
    const std::string in = " '" + dir + "/in_" + x.p.name + ".bin' ";
    c_args += in + "'" + dir + "/c_" + x.p.name + ".out'";
    cpp_args += in + "'" + dir + "/cpp_" + x.p.name + ".out'" + in + "'" + dir + "/c_from_cpp_" + x.p.name + ".out'";
  }
  ASSERT_EQ(run("'" + dir + "/run_c'" + c_args, dir + "/run_c.log"), 0) << read_text(dir + "/run_c.log");
  ASSERT_EQ(run("'" + dir + "/run_cpp'" + cpp_args, dir + "/run_cpp.log"), 0) << read_text(dir + "/run_cpp.log");
  for (size_t k = 0; k < examples().size(); ++k) {
    const Example& x = examples()[k];
    SCOPED_TRACE(x.name);
    const FixedProgram* f = fixed[k] ? &*fixed[k] : nullptr;
    const std::vector<double> c = read_doubles(dir + "/c_" + x.p.name + ".out"),
                              cpp = read_doubles(dir + "/cpp_" + x.p.name + ".out"),
                              c_from_cpp = read_doubles(dir + "/c_from_cpp_" + x.p.name + ".out"),
                              want = interpreted(x, cfg, f);
    ASSERT_EQ(want.size(), x.u.size() * x.p.outputs.size() + 1);
    EXPECT_TRUE(same_bits(c, cpp)) << "C against C++";
    EXPECT_TRUE(same_bits(c, want)) << "C against the interpreter";
    EXPECT_TRUE(same_bits(c_from_cpp, c)) << "C called from C++ against C";
    double peak = 0.0;
    for (size_t j = 0; j + 1 < want.size(); ++j) peak = std::max(peak, std::abs(want[j]));
    EXPECT_GT(peak, 0.0) << "the verification input did not excite the outputs";
  }
}

TEST(EmitC, DoubleIsBitIdenticalToCppAndTheInterpreterOnEveryExample) { check_config({"double", Scalar::Double, 0}); }
TEST(EmitC, FloatIsBitIdenticalToCppAndTheInterpreterOnEveryExample) { check_config({"float", Scalar::Float, 0}); }
TEST(EmitC, Fixed16IsBitIdenticalToCppAndTheInterpreterOnEveryExample) { check_config({"fixed16", Scalar::Double, 16}); }
TEST(EmitC, Fixed32IsBitIdenticalToCppAndTheInterpreterOnEveryExample) { check_config({"fixed32", Scalar::Double, 32}); }

// verify() with C: the generated C against the interpreter (fixed point: against the
// fixed interpreter, and on the clamp-free scaled run as well), compiled as C99.
TEST(EmitC, VerifyCompilesAndComparesTheC) {
  const Example& x = examples().front();  // dob_controller: a saturation block that engages
  const std::string dir = fresh_dir("c_verify");
  const CFiles d = emit_c(x.p, {Scalar::Float, "test"});
  std::ofstream(dir + "/" + x.p.name + ".h") << d.header;
  std::ofstream(dir + "/" + x.p.name + ".c") << d.source;
  VerifyResult r;
  ASSERT_NO_THROW(r = verify(x.p, Scalar::Float, dir + "/" + x.p.name + ".h", dir + "/work", x.ranges, nullptr, Language::C));
  EXPECT_EQ(r.max_abs_error, 0.0);
  EXPECT_GT(r.max_output, 0.0);
  EXPECT_GT(r.ns_per_step, 0.0);
  for (const char* flag : {"cc ", "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", "-ffp-contract=off", "dob_controller.c"})
    EXPECT_NE(r.compiler_command.find(flag), std::string::npos) << flag << " missing from " << r.compiler_command;
  const FixedProgram f = make_fixed(x.p, x.ranges, 16);
  const CFiles c = emit_fixed_c(x.p, f, {Scalar::Double, "test"});
  std::ofstream(dir + "/" + x.p.name + ".h") << c.header;
  std::ofstream(dir + "/" + x.p.name + ".c") << c.source;
  ASSERT_NO_THROW(r = verify(x.p, Scalar::Double, dir + "/" + x.p.name + ".h", dir + "/work16", x.ranges, &f, Language::C));
  EXPECT_EQ(r.max_abs_error, 0.0);
  ASSERT_FALSE(r.full.hypothesis_held());  // the current limit engages on the full-range input
  ASSERT_TRUE(r.clamp_free.hypothesis_held());
  EXPECT_EQ(r.clamp_free.max_vs_interpreter, 0.0);
  // A damaged source: a compile error, reported as such.
  std::ofstream(dir + "/" + x.p.name + ".c", std::ios::app) << "this is not C;\n";
  EXPECT_THROW(verify(x.p, Scalar::Double, dir + "/" + x.p.name + ".h", dir + "/work_bad", x.ranges, &f, Language::C),
               InputError);
}

// Names C cannot take: a program name that is no identifier, a signal named as a C
// keyword or as a name the generated step() declares.
TEST(EmitC, NamesThatAreNotCAreRefused) {
  const LoopProgram p = lower(TransferFunction::parse("1/(s + 1)"), "lag", at(1000.0));
  EXPECT_NO_THROW(emit_c(p, {Scalar::Double, "test"}));
  LoopProgram bad = p;
  bad.name = "2lag";
  EXPECT_THROW(emit_c(bad, {Scalar::Double, "test"}), InputError);
  for (const char* name : {"int", "self", "acc", "u"}) {
    bad = p;
    bad.slots[static_cast<size_t>(bad.inputs[0])].name = name;
    try {
      emit_c(bad, {Scalar::Double, "test"});
      ADD_FAILURE() << "signal '" << name << "' accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("signal '") + name + "'"), std::string::npos) << e.what();
    }
  }
}

// A loop without state (a gain) still gives a valid struct and warning-free functions;
// a float saturation limit beyond the float range is HUGE_VALF, as in C++.
TEST(EmitC, StatelessProgramAndInfiniteLimitsCompile) {
  const auto d = wide_limits_diagram();
  const LoopProgram p = lower(*d, at(1000.0));
  ASSERT_TRUE(p.states.empty());
  const std::string dir = fresh_dir("c_stateless");
  for (Scalar s : {Scalar::Double, Scalar::Float}) {
    const CFiles c = emit_c(p, {s, "test"});
    if (s == Scalar::Float) {
      EXPECT_NE(c.source.find("HUGE_VALF"), std::string::npos);
    }
    std::ofstream(dir + "/wide_limits.h") << c.header;
    std::ofstream(dir + "/wide_limits.c") << c.source;
    VerifyResult r;
    ASSERT_NO_THROW(r = verify(p, s, dir + "/wide_limits.h", dir + "/work", {{-10.0, 10.0}}, nullptr, Language::C));
    EXPECT_EQ(r.max_abs_error, 0.0);
  }
}

}  // namespace
}  // namespace dmbd::codegen
