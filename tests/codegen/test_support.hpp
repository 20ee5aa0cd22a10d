#pragma once
// Shared helpers of the dmbd_codegen tests: independent references (direct form I
// difference equations in long double, a long-double simulation of a diagram's
// discretised blocks interconnected by solving the algebraic equations of every
// sample), and small runners for the interpreter. Every helper that compares takes
// an explicit tolerance; callers justify it where they call.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "dmbd/blocks/discretize.hpp"
#include "dmbd/blocks/transfer_function.hpp"
#include "dmbd/codegen/interpreter.hpp"
#include "dmbd/codegen/loop_program.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "dmbd/diagrams/flat.hpp"

namespace dmbd::codegen::test {

using blocks::C2dMethod;
using blocks::Complex;
using blocks::TransferFunction;
using LMatrix = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
using LVector = Eigen::Matrix<long double, Eigen::Dynamic, 1>;
using Sequence = std::vector<std::vector<double>>;  // [sample][channel]

const std::string kExamples = DMBD_EXAMPLES;
const std::string kData = DMBD_CODEGEN_TEST_DATA;

// Lowering options at a rate (Tustin).
inline LowerOptions at(double rate_hz) {
  LowerOptions o;
  o.rate_hz = rate_hz;
  return o;
}

// A diagram written inline, parsed as if it lived in tests/codegen/data/ (for subsystem files).
inline std::shared_ptr<const diagrams::Diagram> parse(const std::string& yaml) {
  return diagrams::Diagram::parse(yaml, kData + "/inline.yaml");
}

// A gain and a saturation whose limits (+-1e39) lie beyond the float range, input range
// +-10: a program without state whose float limits are infinite.
inline std::shared_ptr<const diagrams::Diagram> wide_limits_diagram() {
  return parse(R"(
name: wide_limits
inputs: {u: {range: [-10, 10]}}
outputs: {y: {}}
blocks:
  g:   {type: gain, k: 2}
  sat: {type: saturation, lower: -1e39, upper: 1e39}
connections:
  - u -> g
  - g -> sat
  - sat -> y
)");
}

// A fresh empty folder under the test temp dir, removed when the test program exits
// (kept if DMBD_KEEP_TEST_DIRS is set, to look at generated code after a failure).
inline std::string fresh_dir(const std::string& tag) {
  namespace fs = std::filesystem;
  struct Cleanup {
    std::vector<fs::path> dirs;
    ~Cleanup() {
      if (std::getenv("DMBD_KEEP_TEST_DIRS")) return;
      std::error_code ec;
      for (const auto& d : dirs) fs::remove_all(d, ec);
    }
  };
  static Cleanup cleanup;
  const fs::path d = fs::path(::testing::TempDir()) / ("dmbd_codegen_" + tag + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  cleanup.dirs.push_back(d);
  return d.string();
}

inline std::string read_text(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// Run the dmbd command line with `args` (already quoted); exit status and the
// combined stdout + stderr.
struct CliResult {
  int status = -1;
  std::string output;
};
inline CliResult run_cli(const std::string& args, const std::string& dir) {
  const std::string log = dir + "/cli.log";
  const int rc = std::system((std::string("'") + DMBD_EXE + "' " + args + " > '" + log + "' 2>&1").c_str());
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, read_text(log)};
}

// Generated code without its // comments (it has no string literals).
inline std::string code_only(const std::string& text) {
  std::istringstream s(text);
  std::string line, out;
  while (std::getline(s, line)) {
    const auto c = line.find("//");
    out += (c == std::string::npos ? line : line.substr(0, c)) + "\n";
  }
  return out;
}

inline std::vector<std::string> lines(const std::string& text) {
  std::istringstream s(text);
  std::vector<std::string> out;
  std::string line;
  while (std::getline(s, line)) out.push_back(line);
  return out;
}

// Generated code (C++ header or C source) comments its statements: every block path
// appears in a comment as "path (type...", and every assignment of step(), from
// "// ---- outputs ----" to the line containing `end`, comes after a comment naming
// its block or carries its own comment (the writes of y excepted).
inline void expect_commented_statements(const LoopProgram& p, const std::string& text, const std::string& end) {
  const auto ls = lines(text);
  for (const BlockInfo& b : p.blocks) {
    bool found = false;
    for (const std::string& l : ls) {
      const auto c = l.find("//");
      if (c == std::string::npos) continue;
      const auto at = l.find_first_not_of(' ', c + 2);
      if (at != std::string::npos && l.compare(at, b.path.size() + 2, b.path + " (") == 0) found = true;
    }
    EXPECT_TRUE(found) << "block " << b.path << " is in no comment";
  }
  bool in_step = false, under_block = false;
  for (const std::string& l : ls) {
    if (l.find("// ---- outputs ----") != std::string::npos) in_step = true, under_block = false;
    if (!in_step) continue;
    if (l.find(end) != std::string::npos) break;
    const auto c = l.find("//");
    const std::string stmt = c == std::string::npos ? l : l.substr(0, c);
    if (c != std::string::npos && stmt.find_first_not_of(' ') == std::string::npos) {
      // A comment line: a block header if it names a block.
      for (const BlockInfo& b : p.blocks)
        if (l.find("// " + b.path + " (") != std::string::npos) under_block = true;
      continue;
    }
    const bool assignment = std::regex_search(stmt, std::regex("[A-Za-z_][A-Za-z0-9_]* [-+]?= "));
    const bool output_write = std::regex_search(stmt, std::regex("^\\s*y\\[[0-9]+\\] = "));
    if (assignment && !output_write) {
      EXPECT_TRUE(under_block || c != std::string::npos) << "uncommented statement: " << l;
    }
  }
}

// Float code: every floating literal of `code` between `begin` and `end` carries the f
// suffix (no silent promotion to double).
inline void expect_float_literals(const std::string& code, const std::string& begin, const std::string& end) {
  const auto b = code.find(begin), e = code.find(end);
  ASSERT_TRUE(b != std::string::npos && e != std::string::npos && b < e) << begin << " ... " << end;
  const std::string body = code.substr(b, e - b);
  const std::regex lit("[0-9]\\.[0-9]*(e[-+]?[0-9]+)?f?|[0-9]e[-+]?[0-9]+f?");
  for (auto it = std::sregex_iterator(body.begin(), body.end(), lit); it != std::sregex_iterator(); ++it)
    EXPECT_EQ(it->str().back(), 'f') << "double literal " << it->str() << " in float code";
}

inline const std::vector<std::string>& example_diagrams() {
  static const std::vector<std::string> names{"force_dob", "position_encoder", "position_encoder_force",
                                              "position_potentiometer", "rfsea_plant"};
  return names;
}

// The direct form I difference equation of a discrete TF, in long double:
// y[k] = sum_j b_j u[k-j] - sum_{j>=1} a_j y[k-j], with b_j, a_j the coefficients of
// z^{n-j} of the (monic) numerator and denominator as c2d delivers them.
inline std::vector<long double> direct_form_1(const TransferFunction& gd, const std::vector<double>& u) {
  const int n = gd.den().degree();
  std::vector<long double> b(static_cast<size_t>(n + 1)), a(static_cast<size_t>(n + 1));
  for (int j = 0; j <= n; ++j) {
    b[static_cast<size_t>(j)] = gd.num()[n - j];
    a[static_cast<size_t>(j)] = gd.den()[n - j];
  }
  std::vector<long double> y(u.size());
  for (size_t k = 0; k < u.size(); ++k) {
    long double acc = 0.0L;
    for (int j = 0; j <= n && static_cast<size_t>(j) <= k; ++j) acc += b[static_cast<size_t>(j)] * u[k - static_cast<size_t>(j)];
    for (int j = 1; j <= n && static_cast<size_t>(j) <= k; ++j) acc -= a[static_cast<size_t>(j)] * y[k - static_cast<size_t>(j)];
    y[k] = acc / a[0];
  }
  return y;
}

// Run a program's interpreter over an input sequence; [sample][output].
template <class T>
Sequence interpret(const LoopProgram& p, const Sequence& u) {
  Interpreter<T> it(p);
  std::vector<T> ui(p.inputs.size()), yo(p.outputs.size());
  Sequence out;
  out.reserve(u.size());
  for (const auto& row : u) {
    for (size_t j = 0; j < ui.size(); ++j) ui[j] = static_cast<T>(row[j]);
    it.step(ui.data(), yo.data());
    out.emplace_back(yo.begin(), yo.end());
  }
  return out;
}

// Single-channel convenience.
inline std::vector<double> interpret_siso(const LoopProgram& p, const std::vector<double>& u) {
  Sequence in;
  for (double v : u) in.push_back({v});
  std::vector<double> y;
  for (const auto& r : interpret<double>(p, in)) y.push_back(r[0]);
  return y;
}

inline std::vector<double> step_input(int n, double amplitude = 1.0) { return std::vector<double>(static_cast<size_t>(n), amplitude); }

// Linear chirp sin(pi (f1 - f0)/T t^2 + 2 pi f0 t) over n samples at rate_hz.
inline std::vector<double> chirp(int n, double rate_hz, double f0_hz, double f1_hz, double amplitude = 1.0) {
  std::vector<double> u(static_cast<size_t>(n));
  const double T = n / rate_hz;
  for (int k = 0; k < n; ++k) {
    const double t = k / rate_hz;
    u[static_cast<size_t>(k)] = amplitude * std::sin(2.0 * M_PI * (f0_hz * t + 0.5 * (f1_hz - f0_hz) / T * t * t));
  }
  return u;
}

// max_k |got_k - want_k| <= tol * max(scale, max_k |want_k|) (scale: a floor for the
// reference's size, e.g. the input amplitude for a response that starts at zero).
template <class G, class W>
::testing::AssertionResult sequences_near(const std::vector<G>& got, const std::vector<W>& want, double rel_tol,
                                          double scale_floor = 0.0) {
  if (got.size() != want.size())
    return ::testing::AssertionFailure() << "length " << got.size() << " vs " << want.size();
  long double scale = scale_floor;
  for (const W& w : want) scale = std::max(scale, std::abs(static_cast<long double>(w)));
  long double worst = 0.0L;
  size_t at = 0;
  for (size_t k = 0; k < got.size(); ++k) {
    const long double e = std::abs(static_cast<long double>(got[k]) - static_cast<long double>(want[k]));
    if (e > worst || std::isnan(static_cast<double>(e))) worst = e, at = k;
  }
  if (!(worst <= rel_tol * scale))
    return ::testing::AssertionFailure() << "max |error| " << static_cast<double>(worst) << " at sample " << at
                                         << " (got " << static_cast<double>(got[at]) << ", want "
                                         << static_cast<double>(want[at]) << ") > " << rel_tol << " x scale "
                                         << static_cast<double>(scale);
  return ::testing::AssertionSuccess();
}

// Pseudo-random but reproducible numbers (no <random> distribution differences between
// standard libraries): xorshift64*, uniform in [lo, hi).
struct Rng {
  unsigned long long s = 0x9E3779B97F4A7C15ULL;
  explicit Rng(unsigned long long seed) : s(seed ? seed : 1) {}
  unsigned long long next() {
    s ^= s >> 12;
    s ^= s << 25;
    s ^= s >> 27;
    return s * 2685821657736338717ULL;
  }
  double uniform(double lo, double hi) { return lo + (hi - lo) * static_cast<double>(next() >> 11) / 9007199254740992.0; }
};

// An independent discrete simulation of a diagram: every atomic block discretised on
// its own as a state-space model (c2d of the block's linear model with the block's
// method; a delay as an exact shift register of round(T rate) samples; a saturation
// as the identity, with a check that its input stays in range), all of them stacked,
// and the interconnection u_b = M y_b + N w solved every sample as one linear system
// (I - D M) y_b = C x + D N w in long double. Tustin commutes with interconnection
// (it is a change of variable s -> z), so this equals the lowering's realisation
// (sections block by block, loops that become algebraic merged into a group and
// discretised as a whole) up to rounding: a different formulation of the same model.
class DiscreteSimulation {
 public:
  DiscreteSimulation(const diagrams::Diagram& d, double rate_hz, C2dMethod method,
                     const std::vector<std::pair<std::string, C2dMethod>>& block_methods = {})
      : f_(d) {
    const double ts = 1.0 / rate_hz;
    const auto& F = f_;
    for (const auto& s : d.inputs()) nw_ += s.size;
    // Each block's discrete model.
    std::vector<blocks::StateSpace> m;
    for (size_t i = 0; i < F.atomic.size(); ++i) {
      const diagrams::Block& bl = *F.atomic[i];
      C2dMethod mth = bl.method.value_or(method);
      for (const auto& [name, bm] : block_methods)
        if (name == F.atomic_name[i]) mth = bm;
      if (bl.type == diagrams::BlockType::Delay) {
        const int n = d.is_discrete() ? bl.delay_samples : static_cast<int>(std::lround(bl.delay_s * rate_hz));
        blocks::Matrix A = blocks::Matrix::Zero(n, n), B = blocks::Matrix::Zero(n, 1), C = blocks::Matrix::Zero(1, n),
                       D = blocks::Matrix::Zero(1, 1);
        if (n == 0) {
          D(0, 0) = 1.0;
        } else {
          B(0, 0) = 1.0;
          for (int k = 1; k < n; ++k) A(k, k - 1) = 1.0;
          C(0, n - 1) = 1.0;
        }
        m.emplace_back(A, B, C, D, ts);
      } else if (bl.type == diagrams::BlockType::Saturation) {
        m.push_back(blocks::StateSpace::gain(blocks::Matrix::Identity(1, 1), ts));
        saturations_.push_back({static_cast<int>(i), bl.lower, bl.upper});
      } else if (bl.model.is_discrete() || bl.model.num_states() == 0) {
        m.push_back(bl.model);
      } else {
        m.push_back(blocks::c2d(bl.model, ts, mth));
      }
    }
    // Stack.
    int nx = 0, nu = 0, ny = 0;
    for (const auto& s : m) nx += s.num_states(), nu += s.num_inputs(), ny += s.num_outputs();
    A_ = LMatrix::Zero(nx, nx), B_ = LMatrix::Zero(nx, nu), C_ = LMatrix::Zero(ny, nx), D_ = LMatrix::Zero(ny, nu);
    int xo = 0, uo = 0, yo = 0;
    for (size_t i = 0; i < m.size(); ++i) {
      const auto& s = m[i];
      u_off_.push_back(uo);
      A_.block(xo, xo, s.num_states(), s.num_states()) = s.a().cast<long double>();
      B_.block(xo, uo, s.num_states(), s.num_inputs()) = s.b().cast<long double>();
      C_.block(yo, xo, s.num_outputs(), s.num_states()) = s.c().cast<long double>();
      D_.block(yo, uo, s.num_outputs(), s.num_inputs()) = s.d().cast<long double>();
      xo += s.num_states(), uo += s.num_inputs(), yo += s.num_outputs();
    }
    // Interconnection: a signal is a top input (offset into w) or a block output
    // (offset into y_b = the signal's offset in the stacked atomic outputs).
    std::vector<int> w_off;
    {
      int o = 0;
      for (const auto& s : d.inputs()) w_off.push_back(o), o += s.size;
    }
    M_ = LMatrix::Zero(nu, ny), N_ = LMatrix::Zero(nu, nw_);
    auto route = [&](const diagrams::FlatDiagram::Signal& sg, int sig, LMatrix& rowM, LMatrix& rowN, int row, int w) {
      if (sg.top_input)
        rowN.block(row, w_off[static_cast<size_t>(sig)], w, w) = LMatrix::Identity(w, w);
      else
        rowM.block(row, sg.offset, w, w) = LMatrix::Identity(w, w);
    };
    for (size_t i = 0; i < F.atomic.size(); ++i)
      for (size_t k = 0; k < F.atomic[i]->inputs.size(); ++k) {
        const auto& r = F.readers[static_cast<size_t>(F.reader_base[i]) + k];
        route(F.signals[static_cast<size_t>(r.route.signal)], r.route.signal, M_, N_, r.offset, r.size);
      }
    // Top outputs: y = P y_b + Q w.
    for (const auto& s : d.outputs()) nout_ += s.size;
    P_ = LMatrix::Zero(nout_, ny), Q_ = LMatrix::Zero(nout_, nw_);
    {
      int o = 0;
      for (size_t j = 0; j < d.outputs().size(); ++j) {
        const auto& r = F.readers[static_cast<size_t>(F.first_top_output) + j];
        route(F.signals[static_cast<size_t>(r.route.signal)], r.route.signal, P_, Q_, o, r.size);
        o += r.size;
      }
    }
    lu_ = Eigen::FullPivLU<LMatrix>(LMatrix::Identity(ny, ny) - D_ * M_);
    x_ = LVector::Zero(nx);
  }

  // One sample: outputs of the diagram. Records the largest |saturation input| / limit.
  std::vector<long double> step(const std::vector<double>& w_in) {
    LVector w(nw_);
    for (int k = 0; k < nw_; ++k) w(k) = w_in[static_cast<size_t>(k)];
    const LVector yb = lu_.solve(C_ * x_ + D_ * (N_ * w));
    const LVector ub = M_ * yb + N_ * w;
    for (const auto& s : saturations_) {
      const long double v = ub(u_off_[static_cast<size_t>(s.block)]);
      if (v < s.lo || v > s.hi) saturated_ = true;
    }
    const LVector y = P_ * yb + Q_ * w;
    x_ = A_ * x_ + B_ * ub;
    return std::vector<long double>(y.data(), y.data() + y.size());
  }
  // Whether any saturation's input left its range (the linear model is then invalid).
  bool saturated() const { return saturated_; }
  int num_states() const { return static_cast<int>(x_.size()); }

 private:
  struct Sat {
    int block;
    double lo, hi;
  };
  diagrams::FlatDiagram f_;
  int nw_ = 0, nout_ = 0;
  LMatrix A_, B_, C_, D_, M_, N_, P_, Q_;
  Eigen::FullPivLU<LMatrix> lu_;
  LVector x_;
  std::vector<int> u_off_;
  std::vector<Sat> saturations_;
  bool saturated_ = false;
};

}  // namespace dmbd::codegen::test
