// User mistakes: a rate that is not a positive number, a discrete diagram or TF at
// another rate, an improper TF, and delays that are not a whole number of samples.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "dmbd/codegen/loop_program.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "test_support.hpp"

namespace dmbd::codegen {
namespace {

using namespace test;
using diagrams::Diagram;

// The message of the InputError that f throws ("" and a failure if none).
template <class F>
std::string input_error(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InputError: " << e.what();
    return "";
  }
  ADD_FAILURE() << "no exception";
  return "";
}

TEST(BadInput, RateNotPositive) {
  const auto d = Diagram::load(kData + "/pd_delay_loop.yaml");
  const TransferFunction g = TransferFunction::parse("1/(s + 1)");
  for (double r : {0.0, -1000.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    SCOPED_TRACE(r);
    EXPECT_NE(input_error([&] { lower(*d, at(r)); }).find("rate"), std::string::npos);
    EXPECT_NE(input_error([&] { lower(g, "g", at(r)); }).find("rate"), std::string::npos);
  }
}

TEST(BadInput, DiscreteDiagramAtAnotherRate) {
  const auto d = Diagram::load(kData + "/discrete_loop.yaml");  // sample_time 0.01
  const std::string msg = input_error([&] { lower(*d, at(1000.0)); });
  EXPECT_NE(msg.find("discrete_loop"), std::string::npos) << msg;
  EXPECT_NE(msg.find("100"), std::string::npos) << msg;  // names its own rate
  EXPECT_NO_THROW(lower(*d, at(100.0)));
}

TEST(BadInput, DiscreteTfAtAnotherRate) {
  const TransferFunction g = TransferFunction::parse("0.5/(z - 0.5)", {}, 0.01);
  EXPECT_NE(input_error([&] { lower(g, "g", at(1000.0)); }).find("100"), std::string::npos);
  EXPECT_NO_THROW(lower(g, "g", at(100.0)));
}

TEST(BadInput, ImproperTf) {
  const std::string msg = input_error([&] { lower(TransferFunction::parse("(s^2 + 1)/(s + 1)"), "g", at(1000.0)); });
  EXPECT_NE(msg.find("improper"), std::string::npos) << msg;
  // A pure differentiator too.
  EXPECT_NE(input_error([&] { lower(TransferFunction::parse("s"), "g", at(1000.0)); }).find("improper"), std::string::npos);
}

std::shared_ptr<const Diagram> delay_diagram(const std::string& seconds) {
  return parse("name: dly\ninputs: {u: {}}\noutputs: {y: {}}\nblocks:\n  D: {type: delay, seconds: " + seconds +
               "}\nconnections:\n  - u -> D\n  - D -> y\n");
}

// 1.3 ms at 2 kHz is 2.6 samples: rounded to 3 with a warning naming the block, the
// delay, the rate and the rounding; the output is then the input exactly 3 samples late.
TEST(BadInput, DelayNotAWholeNumberOfSamplesWarns) {
  const LoopProgram p = lower(*delay_diagram("0.0013"), at(2000.0));
  ASSERT_EQ(p.warnings.size(), 1u);
  const std::string& w = p.warnings[0];
  EXPECT_NE(w.find("'D'"), std::string::npos) << w;
  EXPECT_NE(w.find("0.0013"), std::string::npos) << w;
  EXPECT_NE(w.find("2.6"), std::string::npos) << w;
  EXPECT_NE(w.find("rounded to 3"), std::string::npos) << w;
  Sequence in;
  for (int i = 0; i < 10; ++i) in.push_back({1.0 + i});
  const Sequence y = interpret<double>(p, in);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(y[static_cast<size_t>(i)][0], i >= 3 ? 1.0 + (i - 3) : 0.0);
  // Whole numbers of samples (up to the rounding of T x rate) do not warn: the force
  // loop's 0.5 ms delay at 2 kHz, 3 ms at 1 kHz.
  EXPECT_TRUE(lower(*delay_diagram("0.0005"), at(2000.0)).warnings.empty());
  EXPECT_TRUE(lower(*delay_diagram("0.003"), at(1000.0)).warnings.empty());
  // force_dob's 0.5 ms feedback delay at 1 kHz is half a sample: a warning.
  const auto dob = Diagram::load(kExamples + "/diagrams/force_dob.yaml");
  bool warned = false;
  for (const auto& s : lower(*dob, at(1000.0)).warnings) warned = warned || s.find("delay_F") != std::string::npos;
  EXPECT_TRUE(warned);
}

// loop_program.hpp: lower() throws "InputError for ... a delay shorter than half a
// sample that is not zero" (rounding it to no delay at all would remove a delay the
// diagram has). 0.2 ms at 2 kHz is 0.4 samples.
// (Fixed: lower() now throws; longer delays are rounded with a warning.)
TEST(BadInput, DelayShorterThanHalfASampleIsAnInputError) {
  EXPECT_NE(input_error([&] { lower(*delay_diagram("0.0002"), at(2000.0)); }).find("D"), std::string::npos);
  // A zero delay is fine (a wire).
  EXPECT_NO_THROW(lower(*delay_diagram("0"), at(2000.0)));
}

// The command line reports these on one line with exit status 2.
TEST(BadInput, CommandLineExitsWithStatus2) {
  const std::string dir = fresh_dir("bad_cli");
  for (const std::string& args : {std::string("codegen --tf '1/(s + 1)' --rate 0 --out '") + dir + "'",
                                  std::string("codegen --tf '(s^2 + 1)/(s + 1)' --rate 1000 --out '") + dir + "'",
                                  std::string("codegen '") + kData + "/discrete_loop.yaml' --rate 1000 --out '" + dir + "'",
                                  std::string("codegen --tf '1/(s + 1)' --rate 1000 --method magic --out '") + dir + "'"}) {
    SCOPED_TRACE(args);
    const CliResult r = run_cli(args, dir);
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("error"), std::string::npos) << r.output;
    EXPECT_LE(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  }
}

}  // namespace
}  // namespace dmbd::codegen
