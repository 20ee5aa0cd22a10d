// Software in the loop (docs/scenario-format.md, controllers: implementation): a
// scenario controller run as its generated code, compiled by the system compiler into a
// shared object while the test runs, gives the closed-loop log of the interpreter bit
// for bit, in double, float and fixed point, on the shipped scenarios; its key and a
// compiler that fails are located one-line errors.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include "dmbd/base/error.hpp"
#include "dmbd/scenario/run_directory.hpp"
#include "dmbd/control/balance_controller.hpp"
#include "dmbd/control/osc_controller.hpp"
#include "dmbd/scenario/evaluate.hpp"
#include "dmbd/scenario/scenario.hpp"
#include "sim_test_support.hpp"

namespace {

namespace fs = std::filesystem;
using dmbd::InputError;
using dmbd::scenario::Implementation;
using dmbd::sim::Scalar;
using dmbd::scenario::Scenario;
using dmbd::scenario::ScenarioRun;
using dmbd::sim::test::read_text;
using dmbd::sim::test::TempDir;
using dmbd::sim::test::write_text;

const std::string kSourceDir = DMBD_SOURCE_DIR;

// A shipped scenario with every controller in `scalar`, run by `implementation`, for
// `duration_s`, into dir/NAME.
ScenarioRun run(const TempDir& dir, const std::string& scenario, Scalar scalar, Implementation implementation, double duration_s,
                const std::string& name) {
  Scenario s = dmbd::scenario::load_scenario(kSourceDir + "/examples/scenarios/" + scenario + ".yaml");
  for (auto& v : s.variants)
    for (auto& c : v.controllers) {
      c.scalar = scalar;
      c.implementation = implementation;
    }
  dmbd::scenario::ScenarioRunOptions o;
  o.duration_s = duration_s;
  return dmbd::scenario::run_scenario(s, dir.file(name), o);
}

// Every column of every run the same, every value the same bits.
void expect_identical_logs(const ScenarioRun& a, const ScenarioRun& b) {
  ASSERT_EQ(a.runs.size(), b.runs.size());
  for (std::size_t r = 0; r < a.runs.size(); ++r) {
    const dmbd::sim::Log &x = a.runs[r].log, &y = b.runs[r].log;
    SCOPED_TRACE(a.runs[r].name);
    ASSERT_EQ(x.columns(), y.columns());
    ASSERT_EQ(x.rows(), y.rows());
    for (std::size_t c = 0; c < x.columns(); ++c) {
      const int k = static_cast<int>(c);
      ASSERT_EQ(x.name(k), y.name(k));
      const std::vector<double>&u = x.column(k), &v = y.column(k);
      std::size_t first = u.size();
      for (std::size_t i = 0; i < u.size() && first == u.size(); ++i)
        if (std::memcmp(&u[i], &v[i], sizeof(double)) != 0) first = i;
      EXPECT_EQ(first, u.size()) << x.name(k) << " differs first at t = " << x.time()[first] << " s: " << u[first] << " vs "
                                 << v[first];
    }
  }
}

// Whether two runs' logs differ anywhere (bit for bit).
bool logs_differ(const ScenarioRun& a, const ScenarioRun& b) {
  for (std::size_t r = 0; r < a.runs.size(); ++r)
    for (std::size_t c = 0; c < a.runs[r].log.columns(); ++c) {
      const auto &u = a.runs[r].log.column(static_cast<int>(c)), &v = b.runs[r].log.column(static_cast<int>(c));
      if (u.size() != v.size() || std::memcmp(u.data(), v.data(), u.size() * sizeof(double)) != 0) return true;
    }
  return false;
}

struct Shipped {
  const char* scenario;
  double duration_s;   // shortened: the runs compared are the same over any length
  std::size_t controllers;  // in all its variants
};

// position_controllers: the 0.3 rad step at 0.5 s inside the window; force_dob: the
// fade-in of its two sinusoids and beyond, at each of its eight variants.
const Shipped kShipped[] = {{"position_controllers", 0.6, 4}, {"force_dob", 0.25, 8}};

// A scalar type as the test's parameter, printed by name.
struct ScalarCase {
  Scalar scalar;
  const char* name;
};
void PrintTo(const ScalarCase& c, std::ostream* os) { *os << c.name; }

class SimSilShipped : public ::testing::TestWithParam<ScalarCase> {};

// The test: SIL runs of position_controllers.yaml and force_dob.yaml produce the
// interpreter's logs, bit for bit. The metrics name the compiler, and the generated
// controllers' clamp events are not counted (null), those of the interpreter are.
TEST_P(SimSilShipped, GeneratedCodeGivesTheInterpretersLogBitForBit) {
  const Scalar scalar = GetParam().scalar;
  TempDir dir;
  std::set<std::string> objects;
  for (const Shipped& sh : kShipped) {
    SCOPED_TRACE(sh.scenario);
    const ScenarioRun interpreted = run(dir, sh.scenario, scalar, Implementation::Interpreter, sh.duration_s, "i");
    const auto t0 = std::chrono::steady_clock::now();
    const ScenarioRun generated = run(dir, sh.scenario, scalar, Implementation::Generated, sh.duration_s, "g");
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    expect_identical_logs(interpreted, generated);

    std::size_t n = 0;
    double compile_s = 0;
    std::set<std::string> here;
    for (std::size_t r = 0; r < generated.runs.size(); ++r) {
      const auto& g = generated.runs[r];
      ASSERT_TRUE(g.sil.has_value()) << g.name;
      EXPECT_FALSE(interpreted.runs[r].sil.has_value());
      EXPECT_NE(g.sil->flags.find("-ffp-contract=off"), std::string::npos) << g.sil->flags;
      EXPECT_FALSE(g.sil->compiler.empty());
      for (const auto& c : g.sil->controllers) {
        EXPECT_EQ(c.scalar, GetParam().name);
        EXPECT_EQ(c.saturations.has_value(), scalar == Scalar::Fixed);
        EXPECT_EQ(c.object.size(), 16u);
        if (here.insert(c.object).second) compile_s += c.compile_s;
        objects.insert(c.object);
        ++n;
      }
      ASSERT_EQ(g.clamp_events.size(), interpreted.runs[r].clamp_events.size());
      for (std::size_t k = 0; k < g.clamp_events.size(); ++k) {
        EXPECT_FALSE(g.clamp_events[k].has_value());
        EXPECT_TRUE(interpreted.runs[r].clamp_events[k].has_value());
      }
      // The metrics written: runs.RUN.sil, the clamp events null.
      const auto& m = generated.metrics["runs"][g.name];
      EXPECT_EQ(m["sil"]["compiler"], g.sil->compiler);
      EXPECT_EQ(m["sil"]["controllers"].size(), g.sil->controllers.size());
      EXPECT_TRUE(m["controller_clamp_events"][0].is_null());
    }
    EXPECT_EQ(n, sh.controllers);
    // Identical controllers share one object: force_dob's two diagrams over four loads.
    EXPECT_EQ(here.size(), std::string(sh.scenario) == "force_dob" ? 2u : 4u);
    std::printf("%s, %s: %zu generated controllers, %zu objects compiled in %.2f s (sum), generated run %.2f s, logs identical\n",
                sh.scenario, generated.runs[0].sil->controllers[0].scalar.c_str(), n, here.size(), compile_s, wall);

    // read_run gives the sil facts back.
    const ScenarioRun back = dmbd::scenario::read_run(dir.file("g"));
    ASSERT_TRUE(back.runs[0].sil.has_value());
    EXPECT_EQ(back.runs[0].sil->controllers.size(), generated.runs[0].sil->controllers.size());
    EXPECT_EQ(back.runs[0].sil->controllers[0].object, generated.runs[0].sil->controllers[0].object);
    EXPECT_FALSE(back.runs[0].clamp_events[0].has_value());
  }
  // position_controllers' force loop has other parameters than force_dob's: its own object.
  EXPECT_EQ(objects.size(), 6u);
}

INSTANTIATE_TEST_SUITE_P(Scalars, SimSilShipped,
                         ::testing::Values(ScalarCase{Scalar::Double, "double"}, ScalarCase{Scalar::Float, "float"},
                                           ScalarCase{Scalar::Fixed, "fixed32"}),
                         [](const auto& info) { return std::string(info.param.name); });

// The comparison above can fail: float's log is not double's.
TEST(SimSil, FloatAndDoubleLogsDiffer) {
  TempDir dir;
  const auto d = run(dir, "force_dob", Scalar::Double, Implementation::Generated, 0.05, "d");
  const auto f = run(dir, "force_dob", Scalar::Float, Implementation::Generated, 0.05, "f");
  EXPECT_TRUE(logs_differ(d, f));
}

// ------------------------------------------------------------------------- errors

// A knee held by the encoder PD, its controller run as `implementation`.
std::string knee_scenario(const std::string& implementation) {
  return "name: knee_hold\n"
         "robot:\n"
         "  name: draco\n"
         "  base: fixed\n"
         "  base_pose: {xyz: [0, 0, 1.3]}\n"
         "  moving: [l_knee]\n"
         "  actuators: [l_knee]\n"
         "  initial: {l_knee: 1.0}\n"
         "duration_s: 0.02\n"
         "references:\n"
         "  q_d: {type: steps, offset: 1.0, steps: [[0.01, 0.05]]}\n"
         "controllers:\n"
         "  - name: position\n"
         "    diagram: " + kSourceDir + "/examples/diagrams/position_encoder_controller.yaml\n"
         "    implementation: " + implementation + "\n"
         "    inputs: {q_d: q_d, q_m: l_knee.q_enc}\n"
         "    outputs: {i: l_knee.current}\n";
}

TEST(SimSil, AnImplementationThatIsNeitherIsALocatedError) {
  TempDir dir;
  const std::string path = dir.file("s.yaml");
  write_text(path, knee_scenario("compiled"));
  try {
    (void)dmbd::scenario::load_scenario(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ":15:21: controller.implementation: expected interpreter or generated, got 'compiled'");
  }
  write_text(path, knee_scenario("[generated]"));
  try {
    (void)dmbd::scenario::load_scenario(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind(path + ":15:21: controller.implementation: ", 0), 0u) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
  write_text(path, knee_scenario("interpreter"));
  EXPECT_EQ(dmbd::scenario::load_scenario(path).variants[0].controllers[0].implementation, Implementation::Interpreter);
  write_text(path, knee_scenario("generated"));
  EXPECT_EQ(dmbd::scenario::load_scenario(path).variants[0].controllers[0].implementation, Implementation::Generated);
}

// $CXX for the life of the object.
class CompilerOverride {
 public:
  explicit CompilerOverride(const std::string& cxx) {
    if (const char* old = std::getenv("CXX")) old_ = old;
    ::setenv("CXX", cxx.c_str(), 1);
  }
  ~CompilerOverride() {
    if (old_.empty()) ::unsetenv("CXX");
    else ::setenv("CXX", old_.c_str(), 1);
  }
  CompilerOverride(const CompilerOverride&) = delete;
  CompilerOverride& operator=(const CompilerOverride&) = delete;

 private:
  std::string old_;
};

// The folder a failed build kept ("full log: DIR/compile.log)" in the message), removed.
void remove_failed_build(const std::string& message) {
  const auto at = message.find("full log: ");
  if (at == std::string::npos) return;
  const fs::path log = message.substr(at + 10, message.rfind(')') - at - 10);
  if (log.filename() == "compile.log" && log.parent_path().filename().string().rfind("dmbd-sil-", 0) == 0) fs::remove_all(log.parent_path());
}

// A compiler that refuses the code: the error names the scenario, the variant, the
// controller's line and the compiler's first error line; nothing is run or written.
TEST(SimSil, ACompilerThatFailsIsALocatedOneLineError) {
  TempDir dir;
  const std::string path = dir.file("s.yaml"), header = dir.file("refuse.h");
  write_text(path, knee_scenario("generated"));
  write_text(header, "#error this compiler refuses the generated code\n");
  const Scenario s = dmbd::scenario::load_scenario(path);
  for (const std::string& cxx : {"c++ -include " + header, dir.file("no_such_compiler")}) {
    SCOPED_TRACE(cxx);
    const CompilerOverride o(cxx);
    try {
      (void)dmbd::scenario::run_scenario(s, dir.file("out"));
      FAIL() << "no error";
    } catch (const InputError& e) {
      const std::string m = e.what();
      remove_failed_build(m);
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
      EXPECT_EQ(m.rfind(path + ": variant 'base': " + path + ":13:11: controller 'position': the generated code does not compile (" + cxx +
                            "): ",
                        0),
                0u)
          << m;
      EXPECT_NE(m.find(cxx == dir.file("no_such_compiler") ? "No such file or directory" : "#error this compiler refuses the generated code"),
                std::string::npos)
          << m;
    }
    EXPECT_FALSE(fs::exists(dir.file("out")));
  }
}

// $TMPDIR for the life of the object.
class TempFolderOverride {
 public:
  explicit TempFolderOverride(const std::string& dir) {
    if (const char* old = std::getenv("TMPDIR")) old_ = old;
    ::setenv("TMPDIR", dir.c_str(), 1);
  }
  ~TempFolderOverride() {
    if (old_.empty()) ::unsetenv("TMPDIR");
    else ::setenv("TMPDIR", old_.c_str(), 1);
  }
  TempFolderOverride(const TempFolderOverride&) = delete;
  TempFolderOverride& operator=(const TempFolderOverride&) = delete;

 private:
  std::string old_;
};

// Issue 28 row 16: the build folder's path (under $TMPDIR) holds quotes and a command;
// the compiler is started without a shell, so the controller builds and runs and the
// command never runs. (A define of its own in $CXX: a build this process has not cached.)
TEST(SimSil, ABuildFolderOfAnyNameCompilesAndRunsNoCommand) {
  TempDir dir;
  const std::string path = dir.file("s.yaml"), pwned = dir.file("PWNED_SIL"), pwned2 = dir.file("PWNED_SIL2");
  const std::string tmp = dir.file("t'; touch " + pwned + "; echo '$(touch " + pwned2 + ")");
  fs::create_directories(tmp);
  write_text(path, knee_scenario("generated"));
  const Scenario s = dmbd::scenario::load_scenario(path);
  {
    const CompilerOverride o("c++ -DDMBD_ISSUE28_NO_SHELL=1");
    const TempFolderOverride t(tmp);
    const ScenarioRun r = dmbd::scenario::run_scenario(s, dir.file("out"));
    EXPECT_TRUE(r.runs.size() == 1 && r.runs[0].log.rows() > 10u);
  }
  EXPECT_FALSE(fs::exists(pwned));
  EXPECT_FALSE(fs::exists(pwned2));
  EXPECT_TRUE(fs::exists(dir.file("out/log.csv")));
}

// The command line: exit status 2, the one line on stderr, no run directory.
TEST(SimSil, TheCommandLineExits2OnACompilerError) {
  const fs::path dmbd = fs::read_symlink("/proc/self/exe").parent_path().parent_path().parent_path() / "apps" / "dmbd";
  if (!fs::exists(dmbd)) GTEST_SKIP() << dmbd << " is not built (target dmbd)";
  TempDir dir;
  const std::string path = dir.file("s.yaml"), header = dir.file("refuse.h"), out = dir.file("out");
  write_text(path, knee_scenario("generated"));
  write_text(header, "#error this compiler refuses the generated code\n");
  const int rc = std::system(("CXX='c++ -include " + header + "' '" + dmbd.string() + "' simulate '" + path + "' --out '" + out +
                              "' --no-frames > '" + dir.file("stdout") + "' 2> '" + dir.file("stderr") + "' < /dev/null")
                                 .c_str());
  ASSERT_TRUE(WIFEXITED(rc));
  EXPECT_EQ(WEXITSTATUS(rc), 2);
  const std::string err = read_text(dir.file("stderr"));
  remove_failed_build(err);
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_EQ(err.rfind("dmbd: error: " + path + ": variant 'base': " + path + ":13:11: controller 'position': the generated code does not compile", 0),
            0u)
      << err;
  EXPECT_NE(err.find("#error this compiler refuses the generated code"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
