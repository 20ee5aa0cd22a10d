#include "dmbd/codegen/verify.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "dmbd/base/process.hpp"
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

// The C++ harness: reads the inputs, runs the generated step (native types, converted
// as the interpreter converts them), writes the outputs, and times the step alone.
std::string cpp_harness(const LoopProgram& p, Scalar scalar, const std::string& header, const FixedProgram* fixed) {
  const std::string T = fixed ? (fixed->word_bits == 32 ? "int32_t" : "int16_t") : std::string(to_string(scalar));
  const std::string ns = p.name, sfx = fixed ? std::to_string(fixed->word_bits) : "";
  // Conversions as the interpreters do them: a cast for float/double, the runtime's
  // quantiser and converter for fixed point.
  const std::string to_in = fixed ? ns + "::fx::quantize" + sfx + "(u[k * ni + j], " + ns + "::kInputQ[j], st)"
                                  : "static_cast<" + T + ">(u[k * ni + j])";
  const std::string to_out = fixed ? ns + "::fx::dequantize" + sfx + "(yo[j], " + ns + "::kOutputQ[j])"
                                   : "static_cast<double>(yo[j])";
  std::ostringstream h;
  h << "#include \"" << header << "\"\n#include <chrono>\n#include <cstdio>\n#include <vector>\n"
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
  return h.str();
}

// The C harness: the same in C99 (compiled with the same flags as the generated C). The
// inputs are quantised with a scratch state, so that the controller's counter holds the
// step's saturations alone, as in the C++ harness.
std::string c_harness(const LoopProgram& p, const std::string& header, const FixedProgram* fixed) {
  const std::string n = p.name;
  const std::string to_in = fixed ? n + "_quantize_input(&scratch, j, u[k * ni + j])" : "(" + n + "_input)u[k * ni + j]";
  const std::string to_out = fixed ? n + "_dequantize_output(j, yo[j])" : "(double)yo[j]";
  const std::string N = c_macro_prefix(n);
  std::ostringstream h;
  h << "#define _POSIX_C_SOURCE 199309L  // clock_gettime\n#include \"" << header
    << "\"\n#include <stdio.h>\n#include <stdlib.h>\n#include <time.h>\n"
    << "int main(int argc, char** argv) {\n"
    << "  enum { ni = " << N << "_NUM_INPUTS, no = " << N << "_NUM_OUTPUTS, reps = 20 };\n"
    << "  size_t cap = 1024, len = 0, n, k;\n  int j, r;\n  double v, ns_step;\n  volatile double sink = 0;\n"
    << "  long saturations;\n  struct timespec t0, t1;\n  " << n << "_state c, scratch;\n  " << n << "_output yo[no];\n"
    << "  double *u = malloc(cap * sizeof *u), *out;\n  " << n << "_input* uq;\n  FILE *f, *g;\n"
    << "  if (argc != 3 || !u || !(f = fopen(argv[1], \"rb\"))) return 1;\n"
    << "  while (fread(&v, sizeof v, 1, f) == 1) {\n"
    << "    if (len == cap && !(u = realloc(u, (cap *= 2) * sizeof *u))) return 1;\n    u[len++] = v;\n  }\n"
    << "  fclose(f);\n  n = len / ni;\n"
    << "  out = malloc((n * no + 1) * sizeof *out);\n  uq = malloc((n * ni + 1) * sizeof *uq);\n"
    << "  if (!out || !uq) return 1;\n  " << n << "_reset(&c);\n  " << n << "_reset(&scratch);\n"
    << "  for (k = 0; k < n; ++k)\n    for (j = 0; j < ni; ++j) uq[k * ni + j] = " << to_in << ";\n"
    << "  for (k = 0; k < n; ++k) {\n    " << n << "_step(&c, &uq[k * ni], yo);\n"
    << "    for (j = 0; j < no; ++j) out[k * no + j] = " << to_out << ";\n  }\n"
    << "  if (!(g = fopen(argv[2], \"wb\"))) return 1;\n  fwrite(out, sizeof(double), n * no, g);\n  fclose(g);\n"
    << "  saturations = " << (fixed ? "(long)" + n + "_saturations(&c)" : std::string("0")) << ";\n"
    << "  // Timing: the whole sequence, repeated, after a warm-up.\n  " << n << "_reset(&c);\n"
    << "  clock_gettime(CLOCK_MONOTONIC, &t0);\n"
    << "  for (r = 0; r < reps; ++r)\n    for (k = 0; k < n; ++k) {\n"
    << "      " << n << "_step(&c, &uq[k * ni], yo);\n      sink = sink + yo[0];\n    }\n"
    << "  clock_gettime(CLOCK_MONOTONIC, &t1);\n"
    << "  ns_step = (double)(t1.tv_sec - t0.tv_sec) * 1e9 + (double)(t1.tv_nsec - t0.tv_nsec);\n"
    << "  printf(\"%.3f %ld\\n\", ns_step / (reps * (double)n), saturations);\n"
    << "  free(u);\n  free(out);\n  free(uq);\n  return 0;\n}\n";
  return h.str();
}

std::vector<std::string> compiler_and_flags(Language language) {
  return command_words(language == Language::C ? "cc -std=c99 -O2 -Wall -Wextra -pedantic -Werror -ffp-contract=off"
                                               : "c++ -std=c++11 -O2 -Wall -Wextra -Werror -fno-exceptions -fno-rtti "
                                                 "-ffp-contract=off");
}

std::vector<std::string> output_and_sources(const std::vector<std::string>& sources, const std::string& binary) {
  std::vector<std::string> words;
  if (!binary.empty()) words = {"-o", binary};
  words.insert(words.end(), sources.begin(), sources.end());
  return words;
}

// The first line of a compiler's log that mentions an error ("" when none does).
std::string first_error_line(const fs::path& log) {
  std::ifstream lf(log);
  for (std::string line; std::getline(lf, line);)
    if (line.find("error") != std::string::npos) return line;
  return "";
}

}  // namespace

std::vector<std::string> compile_arguments(Language language, const std::vector<std::string>& sources, const std::string& binary) {
  std::vector<std::string> argv = compiler_and_flags(language);
  const std::vector<std::string> rest = output_and_sources(sources, binary);
  argv.insert(argv.end(), rest.begin(), rest.end());
  return argv;
}

std::string compile_command(Language language, const std::vector<std::string>& sources, const std::string& binary,
                            const std::string& extra) {
  std::string cmd = shell_line(compiler_and_flags(language));
  if (!extra.empty()) cmd += " " + extra;
  const std::vector<std::string> rest = output_and_sources(sources, binary);
  return rest.empty() ? cmd : cmd + " " + shell_line(rest);
}

bool BoundCheck::within(const ErrorBound& b) const {
  for (size_t j = 0; j < max_error_covered.size(); ++j)
    if (!(j < b.over_horizon.size() && max_error_covered[j] <= b.over_horizon[j])) return false;
  return true;
}

BoundCheck check_bound(const LoopProgram& p, const FixedProgram& f, const std::vector<std::vector<double>>& u,
                       int horizon, const std::vector<double>* fixed_outputs) {
  const size_t no = p.outputs.size();
  BoundCheck c;
  c.scale = 1.0;
  c.steps = static_cast<int>(u.size());
  c.max_error.assign(no, 0.0);
  c.max_error_covered.assign(no, 0.0);
  Interpreter<double> exact(p);
  FixedInterpreter fi(p, f);
  std::vector<double> ye(no), yf(no);
  for (size_t n = 0; n < u.size(); ++n) {
    const auto ce = exact.clamp_events(), cf = fi.clamp_events();
    const auto sat = fi.saturations();
    exact.step(u[n].data(), ye.data());
    fi.step_real(u[n].data(), yf.data());
    const bool engaged_exact = exact.clamp_events() != ce, engaged_fixed = fi.clamp_events() != cf,
               saturated = fi.saturations() != sat;
    c.clamp_steps_exact += engaged_exact;
    c.clamp_steps_fixed += engaged_fixed;
    c.saturation_steps += saturated;
    c.violation_steps += engaged_exact || engaged_fixed || saturated;
    if ((engaged_exact || engaged_fixed || saturated) && c.first_violation < 0) c.first_violation = static_cast<int>(n);
    const bool covered = c.first_violation < 0 && static_cast<int>(n) < horizon;
    c.covered_steps += covered;
    for (size_t j = 0; j < no; ++j) {
      double y = yf[j];
      if (fixed_outputs) {
        y = (*fixed_outputs)[n * no + j];
        c.max_vs_interpreter = std::max(c.max_vs_interpreter, std::abs(y - yf[j]));
      }
      const double e = std::abs(y - ye[j]);
      c.max_error[j] = std::max(c.max_error[j], e);
      if (covered) c.max_error_covered[j] = std::max(c.max_error_covered[j], e);
    }
  }
  return c;
}

std::vector<std::vector<double>> scaled_inputs(const std::vector<std::vector<double>>& u,
                                               const std::vector<std::pair<double, double>>& ranges, double s) {
  std::vector<std::vector<double>> v = u;
  for (auto& row : v)
    for (size_t j = 0; j < row.size(); ++j) {
      const auto [lo, hi] = j < ranges.size() ? ranges[j] : std::make_pair(-1.0, 1.0);
      const double c = std::min(std::max(0.0, lo), hi);
      row[j] = c + s * (row[j] - c);
    }
  return v;
}

double clamp_free_scale(const LoopProgram& p, const FixedProgram& f, const std::vector<std::vector<double>>& u,
                        const std::vector<std::pair<double, double>>& ranges) {
  for (int k = 0; k <= 40; ++k) {
    const double s = std::ldexp(1.0, -k);
    if (check_bound(p, f, scaled_inputs(u, ranges, s), static_cast<int>(u.size())).hypothesis_held()) return s;
  }
  return 0.0;
}

VerifyResult verify(const LoopProgram& p, Scalar scalar, const std::string& header, const std::string& work_dir,
                    const std::vector<std::pair<double, double>>& ranges, const FixedProgram* fixed, Language language) {
  VerifyResult r;
  fs::create_directories(work_dir);
  const auto u = verification_inputs(p, ranges);
  r.samples = static_cast<int>(u.size());
  {
    std::ofstream f(fs::path(work_dir) / "inputs.bin", std::ios::binary);
    for (const auto& row : u) f.write(reinterpret_cast<const char*>(row.data()), static_cast<std::streamsize>(row.size() * sizeof(double)));
  }
  const fs::path src = fs::path(work_dir) / (language == Language::C ? "harness.c" : "harness.cpp"),
                 bin = fs::path(work_dir) / "harness", log = fs::path(work_dir) / "compile.log",
                 out = fs::path(work_dir) / "outputs.bin", timing = fs::path(work_dir) / "timing.txt";
  std::vector<std::string> sources{src.string()};
  if (language == Language::C) {
    sources.push_back(fs::path(header).replace_extension(".c").string());
    std::ofstream(src) << c_harness(p, fs::absolute(header).string(), fixed);
  } else {
    std::ofstream(src) << cpp_harness(p, scalar, fs::absolute(header).string(), fixed);
  }
  const std::vector<std::string> compile = compile_arguments(language, sources, bin.string());
  r.compiler_command = shell_line(compile);
  const ProgramRun built = run_program(compile, log.string(), log.string());
  if (!built.ok())
    throw InputError("the generated code does not compile: " + (built.exit_code < 0 ? built.why : first_error_line(log)) +
                     " (full log: " + log.string() + ")");
  // Runs the harness on an input file; returns the generated code's outputs.
  const std::string harness = fs::absolute(bin).string(), harness_log = (fs::path(work_dir) / "harness.log").string();
  auto run = [&](const fs::path& inputs, const fs::path& outputs, const fs::path& timing_file, size_t rows) {
    const ProgramRun ran = run_program({harness, inputs.string(), outputs.string()}, timing_file.string(), harness_log);
    if (!ran.ok())
      throw InputError("the verification harness failed to run: " +
                       (ran.exit_code < 0 ? ran.why : "exit status " + std::to_string(ran.exit_code)) + " (its errors: " + harness_log + ")");
    std::vector<double> values;
    std::ifstream f(outputs, std::ios::binary);
    double v;
    while (f.read(reinterpret_cast<char*>(&v), sizeof v)) values.push_back(v);
    if (values.size() != rows * p.outputs.size()) throw InputError("the verification harness wrote the wrong number of outputs");
    return values;
  };
  const std::vector<double> got = run(fs::path(work_dir) / "inputs.bin", out, timing, u.size());
  std::ifstream(timing) >> r.ns_per_step >> r.saturations;
  std::vector<double> want;
  double bit_error = 0.0;  // |generated - interpreter| on the clamp-free run, when there is one
  if (fixed) {
    FixedInterpreter fi(p, *fixed);
    std::vector<double> yo(p.outputs.size());
    for (const auto& row : u) {
      fi.step_real(row.data(), yo.data());
      want.insert(want.end(), yo.begin(), yo.end());
    }
    // The bound over the run's length, and its hypothesis checked step by step.
    r.bound = predicted_error_bound(p, *fixed, ranges, r.samples);
    r.full = check_bound(p, *fixed, u, r.samples, &got);
    for (double e : r.full.max_error) r.max_abs_error_vs_exact = std::max(r.max_abs_error_vs_exact, e);
    r.clamp_free = r.full;
    if (!r.full.hypothesis_held()) {
      r.clamp_free = BoundCheck{};
      const double s = clamp_free_scale(p, *fixed, u, ranges);
      if (s > 0.0) {
        const auto us = scaled_inputs(u, ranges, s);
        const fs::path in2 = fs::path(work_dir) / "inputs_clamp_free.bin";
        {
          std::ofstream f(in2, std::ios::binary);
          for (const auto& row : us)
            f.write(reinterpret_cast<const char*>(row.data()), static_cast<std::streamsize>(row.size() * sizeof(double)));
        }
        const std::vector<double> got2 =
            run(in2, fs::path(work_dir) / "outputs_clamp_free.bin", fs::path(work_dir) / "timing_clamp_free.txt", us.size());
        r.clamp_free = check_bound(p, *fixed, us, r.samples, &got2);
        r.clamp_free.scale = s;
        bit_error = r.clamp_free.max_vs_interpreter;
      }
    }
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
  r.max_abs_error = std::max(r.max_abs_error, bit_error);
  r.sqnr_db = se == 0.0 ? INFINITY : 10.0 * std::log10(sy / se);
  return r;
}

}  // namespace dmbd::codegen
