// The pid block's output limits and anti-windup (issue 28, row 13): the three modes
// against sequences computed by hand, states by structure, and the generated code
// against the interpreter bit for bit in double, float and fixed point.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "dmbd/codegen/emit.hpp"
#include "dmbd/codegen/emit_c.hpp"
#include "dmbd/codegen/fixed.hpp"
#include "dmbd/codegen/interpreter.hpp"
#include "dmbd/codegen/loop_program.hpp"
#include "dmbd/codegen/verify.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "test_support.hpp"

namespace dmbd::codegen {
namespace {

using namespace test;

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

std::string pid_diagram(const std::string& fields) {
  return "name: pid_limits\n"
         "parameters: {Ki: 0, Kd: 0}\n"
         "inputs:\n  e: {range: [-2, 2]}\n"
         "outputs:\n  u: {}\n"
         "blocks:\n  C: {type: pid, " + fields + "}\n"
         "connections:\n  - e -> C\n  - C -> u\n";
}

std::vector<double> run(const std::string& fields, double rate, const std::vector<double>& e) {
  const auto d = parse(pid_diagram(fields));
  return interpret_siso(lower(*d, at(rate)), e);
}

// P = 1, I = 25 1/s at 100 Hz by ZOH (the integrator I ts/(z - 1): the integral term is
// the state, the state advances by I ts e = 0.25 e), limits [-1, 1], e = 2 for four
// steps then -1. Worked by hand (docs/codegen.md, "PID blocks"), x the state:
//   none:  u = e + x, x' = x + 0.25 e: x = 0, .5, 1, 1.5, 2 -> u = 2, 2.5, 3, 3.5 (held
//          at 1), then 1, .75, .5, .25: the wound-up integrator holds the output at the
//          limit one step after the error has reversed, and unwinds slowly.
//   clamp: the integral term clamp(x, -1, 1): x = 0, .5, 1, 1.5 -> 1 then u = -1 + 1 = 0,
//          x' = 1 - .25 = .75, ... : the output leaves the limit at once.
//   back_calculation, Kt = 25 1/s (Kt ts = 0.25): x' = x + .25 e + .25 (y - u):
//          x = 0, .25, .4375, .578125, .68359375 (tending to 1, where the two inputs
//          of the integrator cancel); then u = -1 + .68359375 = -.31640625, ...
// Every value is a dyadic rational of a few bits, so each double operation is exact:
// the interpreter must give these numbers exactly (tolerance 0).
TEST(PidLimits, EachAntiWindupModeMatchesTheSequenceWorkedByHand) {
  const std::vector<double> e{2, 2, 2, 2, -1, -1, -1, -1};
  const std::string law = "P: 1, I: 25, output_limits: [-1, 1], discretization: zoh";
  EXPECT_EQ(run(law, 100.0, e), (std::vector<double>{1, 1, 1, 1, 1, 0.75, 0.5, 0.25}));
  EXPECT_EQ(run(law + ", anti_windup: none", 100.0, e), (std::vector<double>{1, 1, 1, 1, 1, 0.75, 0.5, 0.25}));
  EXPECT_EQ(run(law + ", anti_windup: clamp", 100.0, e), (std::vector<double>{1, 1, 1, 1, 0, -0.25, -0.5, -0.75}));
  EXPECT_EQ(run(law + ", anti_windup: back_calculation, Kt: 25", 100.0, e),
            (std::vector<double>{1, 1, 1, 1, -0.31640625, -0.56640625, -0.81640625, -1}));
}

// Without limits the term-by-term law is the transfer function's: with wide limits that
// never engage, the output equals the sections' realisation of P + I/s + D s/(tau s + 1)
// (Tustin) to rounding: 1e-12 of the largest output over a 2000-sample chirp.
TEST(PidLimits, IdleLimitsLeaveTheLinearLaw) {
  const std::vector<double> e = chirp(2000, 1000.0, 0.5, 200.0, 1.0);
  const std::string law = "P: 2, I: 30, D: 0.05, tau: 0.002";
  const std::vector<double> free = run(law, 1000.0, e);
  for (const char* mode : {"none", "clamp"}) {
    SCOPED_TRACE(mode);
    const std::vector<double> limited = run(law + ", output_limits: [-1e6, 1e6], anti_windup: " + mode, 1000.0, e);
    EXPECT_TRUE(sequences_near(limited, std::vector<long double>(free.begin(), free.end()), 1e-12));
  }
}

int states(const std::string& fields, bool limits) {
  const auto d = parse(pid_diagram(fields + (limits ? ", output_limits: [-5, 5]" : "")));
  const int model = d->blocks().front().model.num_states();
  const LoopProgram p = lower(*d, at(1000.0));
  EXPECT_EQ(static_cast<int>(p.states.size()), model) << fields << (limits ? " (limited)" : "");
  return model;
}

// States by structure: an absent term, or one written as a literal 0, carries no state;
// one given by a parameter keeps it at any value (Ki = Kd = 0 here), and lowering takes it.
TEST(PidLimits, StatesByStructure) {
  for (bool limits : {false, true}) {
    SCOPED_TRACE(limits ? "with output limits" : "without");
    EXPECT_EQ(states("P: 1", limits), 0);
    EXPECT_EQ(states("P: 1, I: 2", limits), 1);
    EXPECT_EQ(states("P: 1, D: 0.5, tau: 0.01", limits), 1);
    EXPECT_EQ(states("P: 1, I: 0, D: 0, tau: 0.01", limits), 0);
    EXPECT_EQ(states("P: 1, I: 0.0, D: 0.5, tau: 0.01", limits), 1);
    EXPECT_EQ(states("P: 1, I: 2, D: 0.5, tau: 0.01", limits), 2);
    EXPECT_EQ(states("P: 1, I: Ki, D: Kd, tau: 0.01", limits), 2);
    EXPECT_EQ(states("P: 1, I: Ki", limits), 1);
  }
}

// The generated code of every mode (Tustin, a derivative term, limits that engage on
// the verification input) equals the interpreter bit for bit: double, float, and 16-
// and 32-bit fixed point (verify(): max error exactly 0).
TEST(PidLimits, GeneratedCodeIsBitIdenticalToTheInterpreter) {
  const std::string law = "P: 2, I: 30, D: 0.05, tau: 0.002, output_limits: [-1.5, 1.5]";
  for (const std::string mode : {"none", "clamp", "back_calculation, Kt: 40"}) {
    const auto d = parse(pid_diagram(law + ", anti_windup: " + mode));
    const LoopProgram p = lower(*d, at(2000.0));
    const std::vector<std::pair<double, double>> ranges{{-2.0, 2.0}};
    for (int k = 0; k < 4; ++k) {  // double, float, fixed 32, fixed 16
      const Scalar s = k == 1 ? Scalar::Float : Scalar::Double;
      const int word = k == 2 ? 32 : 16;
      SCOPED_TRACE(mode + " " + (k < 2 ? std::string(to_string(s)) : "fixed " + std::to_string(word)));
      const std::string dir = fresh_dir("pid_" + std::to_string(k) + "_" + mode.substr(0, 4));
      const std::string header = dir + "/" + p.name + ".hpp";
      VerifyResult r;
      if (k >= 2) {
        const FixedProgram f = make_fixed(p, ranges, word);
        write(header, emit_fixed_header(p, f, {Scalar::Double, "test"}));
        ASSERT_NO_THROW(r = verify(p, s, header, dir + "/verify", ranges, &f));
      } else {
        write(header, emit_header(p, {s, "test"}));
        ASSERT_NO_THROW(r = verify(p, s, header, dir + "/verify", ranges));
      }
      EXPECT_EQ(r.max_abs_error, 0.0);
      EXPECT_GT(r.max_output, 1.0) << "the verification input did not drive the output towards its limits";
    }
  }
}

// The same in C (the C emitter prints the same statements): double and 16-bit fixed
// point, bit for bit with the interpreter.
TEST(PidLimits, GeneratedCIsBitIdenticalToTheInterpreter) {
  const std::string law = "P: 2, I: 30, D: 0.05, tau: 0.002, output_limits: [-1.5, 1.5]";
  for (const std::string mode : {"clamp", "back_calculation, Kt: 40"}) {
    const auto d = parse(pid_diagram(law + ", anti_windup: " + mode));
    const LoopProgram p = lower(*d, at(2000.0));
    const std::vector<std::pair<double, double>> ranges{{-2.0, 2.0}};
    for (bool fixed : {false, true}) {
      SCOPED_TRACE(mode + (fixed ? " fixed 16" : " double"));
      const std::string dir = fresh_dir(std::string("pid_c_") + (fixed ? "fx_" : "db_") + mode.substr(0, 4));
      const FixedProgram f = make_fixed(p, ranges, 16);
      const CFiles c = fixed ? emit_fixed_c(p, f, {Scalar::Double, "test"}) : emit_c(p, {Scalar::Double, "test"});
      write(dir + "/" + p.name + ".h", c.header);
      write(dir + "/" + p.name + ".c", c.source);
      VerifyResult r;
      ASSERT_NO_THROW(r = verify(p, Scalar::Double, dir + "/" + p.name + ".h", dir + "/verify", ranges, fixed ? &f : nullptr,
                                 Language::C));
      EXPECT_EQ(r.max_abs_error, 0.0);
      EXPECT_GT(r.max_output, 1.0);
    }
  }
}

}  // namespace
}  // namespace dmbd::codegen
