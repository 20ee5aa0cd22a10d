#include "dmbd/codegen/verify.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "dmbd/blocks/error.hpp"
#include "dmbd/codegen/fixed.hpp"
#include "dmbd/codegen/interpreter.hpp"

namespace dmbd::codegen {

namespace fs = std::filesystem;

std::vector<std::vector<double>> verification_inputs(const LoopProgram& p,
                                                     const std::vector<std::pair<double, double>>& ranges,
                                                     int chirp_samples, int step_samples) {
  const size_t ni = p.inputs.size();
  std::vector<std::vector<double>> u(static_cast<size_t>(chirp_samples + step_samples), std::vector<double>(ni));
  const double f0 = 0.1, f1 = 0.4 * p.rate_hz, T = chirp_samples * p.ts;
  const double k = std::log(f1 / f0) / T;
  for (size_t j = 0; j < ni; ++j) {
    const auto [lo, hi] = j < ranges.size() ? ranges[j] : std::make_pair(-1.0, 1.0);
    const double mid = 0.5 * (lo + hi), amp = 0.5 * (hi - lo);
    for (int n = 0; n < chirp_samples; ++n) {
      const double t = n * p.ts;
      u[static_cast<size_t>(n)][j] = mid + amp * std::sin(2 * M_PI * f0 * (std::exp(k * t) - 1.0) / k + 0.7 * j);
    }
    for (int n = 0; n < step_samples; ++n) u[static_cast<size_t>(chirp_samples + n)][j] = n < step_samples / 2 ? hi : lo;
  }
  return u;
}

namespace {

template <class T>
std::vector<double> interpret(const LoopProgram& p, const std::vector<std::vector<double>>& u) {
  Interpreter<T> it(p);
  std::vector<T> ui(p.inputs.size()), yo(p.outputs.size());
  std::vector<double> out;
  for (const auto& row : u) {
    for (size_t j = 0; j < row.size(); ++j) ui[j] = static_cast<T>(row[j]);
    it.step(ui.data(), yo.data());
    for (T v : yo) out.push_back(static_cast<double>(v));
  }
  return out;
}

}  // namespace

VerifyResult verify(const LoopProgram& p, Scalar scalar, const std::string& header, const std::string& work_dir,
                    const std::vector<std::pair<double, double>>& ranges, const FixedProgram* fixed) {
  VerifyResult r;
  fs::create_directories(work_dir);
  const auto u = verification_inputs(p, ranges);
  r.samples = static_cast<int>(u.size());
  {
    std::ofstream f(fs::path(work_dir) / "inputs.bin", std::ios::binary);
    for (const auto& row : u) f.write(reinterpret_cast<const char*>(row.data()), static_cast<std::streamsize>(row.size() * sizeof(double)));
  }
  // The harness: reads the inputs, runs the generated step (native types, converted as
  // the interpreter converts them), writes the outputs, and times the step alone.
  const std::string T = fixed ? (fixed->word_bits == 32 ? "int32_t" : "int16_t") : std::string(to_string(scalar));
  const std::string ns = p.name, sfx = fixed ? std::to_string(fixed->word_bits) : "";
  // Conversions as the interpreters do them: a cast for float/double, the runtime's
  // quantiser and converter for fixed point.
  const std::string to_in = fixed ? ns + "::fx::quantize" + sfx + "(u[k * ni + j], " + ns + "::kInputQ[j], st)"
                                  : "static_cast<" + T + ">(u[k * ni + j])";
  const std::string to_out = fixed ? ns + "::fx::dequantize" + sfx + "(yo[j], " + ns + "::kOutputQ[j])"
                                   : "static_cast<double>(yo[j])";
  std::ostringstream h;
  h << "#include \"" << fs::absolute(header).string() << "\"\n#include <chrono>\n#include <cstdio>\n#include <vector>\n"
    << "int main(int argc, char** argv) {\n  (void)argc;\n"
    << "  const int ni = " << ns << "::kNumInputs, no = " << ns << "::kNumOutputs;\n"
    << "  std::FILE* f = std::fopen(argv[1], \"rb\");\n  std::vector<double> u;\n  double v;\n"
    << "  while (std::fread(&v, sizeof v, 1, f) == 1) u.push_back(v);\n  std::fclose(f);\n"
    << "  const size_t n = u.size() / ni;\n  std::vector<double> out;\n"
    << (fixed ? "  " + ns + "::fx::Status st{0};\n" : std::string())
    << "  " << ns << "::Controller c;\n  " << T << " ui[ni], yo[no];\n  std::vector<" << T << "> uq(n * ni);\n"
    << "  for (size_t k = 0; k < n; ++k)\n    for (int j = 0; j < ni; ++j) uq[k * ni + j] = " << to_in << ";\n"
    << "  for (size_t k = 0; k < n; ++k) {\n    for (int j = 0; j < ni; ++j) ui[j] = uq[k * ni + j];\n"
    << "    c.step(ui, yo);\n    for (int j = 0; j < no; ++j) out.push_back(" << to_out << ");\n  }\n"
    << "  std::FILE* g = std::fopen(argv[2], \"wb\");\n  std::fwrite(out.data(), sizeof(double), out.size(), g);\n  std::fclose(g);\n"
    << "  long saturations = " << (fixed ? "static_cast<long>(c.saturations())" : "0") << ";\n"
    << "  // Timing: the whole sequence, repeated, after a warm-up.\n"
    << "  volatile double sink = 0;\n  c.reset();\n  const int reps = 20;\n"
    << "  const auto t0 = std::chrono::steady_clock::now();\n"
    << "  for (int r = 0; r < reps; ++r)\n    for (size_t k = 0; k < n; ++k) {\n"
    << "      c.step(&uq[k * ni], yo);\n      sink = sink + yo[0];\n    }\n"
    << "  const double ns_step = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();\n"
    << "  std::printf(\"%.3f %ld\\n\", ns_step / (reps * static_cast<double>(n)), saturations);\n  return 0;\n}\n";
  const fs::path src = fs::path(work_dir) / "harness.cpp", bin = fs::path(work_dir) / "harness",
                 log = fs::path(work_dir) / "compile.log", out = fs::path(work_dir) / "outputs.bin",
                 timing = fs::path(work_dir) / "timing.txt";
  std::ofstream(src) << h.str();
  r.compiler_command = "c++ -std=c++11 -O2 -Wall -Wextra -Werror -fno-exceptions -fno-rtti -o '" + bin.string() +
                       "' '" + src.string() + "'";
  if (std::system((r.compiler_command + " > '" + log.string() + "' 2>&1").c_str()) != 0) {
    std::ifstream lf(log);
    std::string line, first;
    while (std::getline(lf, line))
      if (line.find("error") != std::string::npos) {
        first = line;
        break;
      }
    throw InputError("the generated code does not compile: " + first + " (full log: " + log.string() + ")");
  }
  if (std::system(("'" + bin.string() + "' '" + (fs::path(work_dir) / "inputs.bin").string() + "' '" + out.string() +
                   "' > '" + timing.string() + "'").c_str()) != 0)
    throw InputError("the verification harness failed to run");
  std::ifstream(timing) >> r.ns_per_step >> r.saturations;
  std::vector<double> got;
  {
    std::ifstream f(out, std::ios::binary);
    double v;
    while (f.read(reinterpret_cast<char*>(&v), sizeof v)) got.push_back(v);
  }
  std::vector<double> want;
  if (fixed) {
    FixedInterpreter fi(p, *fixed);
    std::vector<double> yo(p.outputs.size());
    for (const auto& row : u) {
      fi.step_real(row.data(), yo.data());
      want.insert(want.end(), yo.begin(), yo.end());
    }
    const std::vector<double> exact = interpret<double>(p, u);
    for (size_t k = 0; k < exact.size() && k < got.size(); ++k)
      r.max_abs_error_vs_exact = std::max(r.max_abs_error_vs_exact, std::abs(got[k] - exact[k]));
    r.predicted_bound = predicted_error_bound(p, *fixed, ranges);
  } else {
    want = scalar == Scalar::Double ? interpret<double>(p, u) : interpret<float>(p, u);
  }
  if (got.size() != want.size()) throw InputError("the verification harness wrote the wrong number of outputs");
  // SQNR against the exact program for fixed point (against the interpreter of the same
  // arithmetic otherwise, where it is infinite when the code is right).
  const std::vector<double> ref = fixed ? interpret<double>(p, u) : want;
  double se = 0.0, sy = 0.0;
  for (size_t k = 0; k < got.size(); ++k) {
    r.max_abs_error = std::max(r.max_abs_error, std::abs(got[k] - want[k]));
    r.max_output = std::max(r.max_output, std::abs(want[k]));
    const double e = got[k] - ref[k];
    se += e * e;
    sy += ref[k] * ref[k];
  }
  r.sqnr_db = se == 0.0 ? INFINITY : 10.0 * std::log10(sy / se);
  return r;
}

}  // namespace dmbd::codegen
