#include "dmbd/codegen/verify.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "dmbd/blocks/error.hpp"
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
                    const std::vector<std::pair<double, double>>& ranges) {
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
  const std::string T = to_string(scalar);
  std::ostringstream h;
  h << "#include \"" << fs::absolute(header).string() << "\"\n#include <chrono>\n#include <cstdio>\n#include <vector>\n"
    << "int main(int argc, char** argv) {\n  (void)argc;\n"
    << "  const int ni = " << p.name << "::kNumInputs, no = " << p.name << "::kNumOutputs;\n"
    << "  std::FILE* f = std::fopen(argv[1], \"rb\");\n  std::vector<double> u;\n  double v;\n"
    << "  while (std::fread(&v, sizeof v, 1, f) == 1) u.push_back(v);\n  std::fclose(f);\n"
    << "  const size_t n = u.size() / ni;\n  std::vector<double> out;\n"
    << "  " << p.name << "::Controller c;\n  " << T << " ui[ni], yo[no];\n"
    << "  for (size_t k = 0; k < n; ++k) {\n    for (int j = 0; j < ni; ++j) ui[j] = static_cast<" << T << ">(u[k * ni + j]);\n"
    << "    c.step(ui, yo);\n    for (int j = 0; j < no; ++j) out.push_back(static_cast<double>(yo[j]));\n  }\n"
    << "  std::FILE* g = std::fopen(argv[2], \"wb\");\n  std::fwrite(out.data(), sizeof(double), out.size(), g);\n  std::fclose(g);\n"
    << "  // Timing: the whole sequence, repeated, after a warm-up.\n"
    << "  volatile double sink = 0;\n  c.reset();\n  const int reps = 20;\n"
    << "  const auto t0 = std::chrono::steady_clock::now();\n"
    << "  for (int r = 0; r < reps; ++r)\n    for (size_t k = 0; k < n; ++k) {\n"
    << "      for (int j = 0; j < ni; ++j) ui[j] = static_cast<" << T << ">(u[k * ni + j]);\n"
    << "      c.step(ui, yo);\n      sink = sink + yo[0];\n    }\n"
    << "  const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();\n"
    << "  std::printf(\"%.3f\\n\", ns / (reps * static_cast<double>(n)));\n  return 0;\n}\n";
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
  std::ifstream(timing) >> r.ns_per_step;
  std::vector<double> got;
  {
    std::ifstream f(out, std::ios::binary);
    double v;
    while (f.read(reinterpret_cast<char*>(&v), sizeof v)) got.push_back(v);
  }
  const std::vector<double> want = scalar == Scalar::Double ? interpret<double>(p, u) : interpret<float>(p, u);
  if (got.size() != want.size()) throw InputError("the verification harness wrote the wrong number of outputs");
  double se = 0.0, sy = 0.0;
  for (size_t k = 0; k < got.size(); ++k) {
    const double e = got[k] - want[k];
    r.max_abs_error = std::max(r.max_abs_error, std::abs(e));
    r.max_output = std::max(r.max_output, std::abs(want[k]));
    se += e * e;
    sy += want[k] * want[k];
  }
  r.sqnr_db = se == 0.0 ? INFINITY : 10.0 * std::log10(sy / se);
  return r;
}

}  // namespace dmbd::codegen
