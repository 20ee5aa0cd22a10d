// `log_only` (docs/scenario-format.md): the log keeps the signals its patterns match (and
// time), each the same values as in the full log; a pattern that matches nothing is an
// error at its line naming the closest signal.
#include <gtest/gtest.h>

#include <string>

#include "dmbd/base/error.hpp"
#include "dmbd/scenario/scenario.hpp"
#include "sim_test_support.hpp"

namespace {

namespace sc = dmbd::scenario;
using dmbd::sim::test::TempDir;
using dmbd::sim::test::write_text;

// The left knee on its actuator on the table, a current step, 50 ms.
std::string scenario(const std::string& extra) {
  return "name: logged\n"
         "robot: {name: draco, base: fixed, base_pose: {xyz: [0, 0, 1.3]}, moving: [l_knee], actuators: [l_knee], initial: {l_knee: 1.0}}\n"
         "duration_s: 0.05\n"
         "references: {l_knee.current: {type: steps, steps: [[0.01, 2.0]]}}\n" + extra;
}

dmbd::sim::VariantResult run(const std::string& path, const std::string& yaml) {
  write_text(path, yaml);
  const sc::Scenario s = sc::load_scenario(path);
  return sc::run_variant(s, s.variants.front(), {});
}

}  // namespace

TEST(LogOnly, KeepsTheMatchingSignalsWithTheSameValues) {
  TempDir dir;
  const auto full = run(dir.file("full.yaml"), scenario(""));
  const auto some = run(dir.file("some.yaml"), scenario("log_only: [l_knee.q, 'l_knee.current*']\n"));
  ASSERT_EQ(some.log.columns(), 4u);  // time, l_knee.q, l_knee.current, l_knee.current_applied
  EXPECT_EQ(some.log.name(1), "l_knee.q");
  EXPECT_EQ(some.log.name(2), "l_knee.current");
  EXPECT_EQ(some.log.name(3), "l_knee.current_applied");
  EXPECT_GT(full.log.columns(), 10u);
  EXPECT_EQ(some.log.time(), full.log.time());
  for (int c = 1; c < 4; ++c) {
    EXPECT_EQ(some.log.column(c), full.log.column(some.log.name(c))) << some.log.name(c);
    EXPECT_EQ(some.log.unit(c), full.log.unit(full.log.find(some.log.name(c))));
  }
}

TEST(LogOnly, APatternThatMatchesNothingIsALocatedError) {
  TempDir dir;
  const std::string path = dir.file("e.yaml");
  try {
    run(path, scenario("log_only:\n  - l_knee.q\n  - l_kne.force\n"));
    FAIL() << "no error";
  } catch (const dmbd::InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path + ":7:5: log_only: 'l_kne.force' matches no signal (the closest: 'l_knee.force')"), std::string::npos) << msg;
  }
}
