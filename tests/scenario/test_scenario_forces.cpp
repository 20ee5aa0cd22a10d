// Forces started by a bus event (`forces[].trigger`, docs/scenario-format.md): the
// source runs from the signal's occurrence-th change plus after_s, exactly as the same
// force written at that absolute time; the start is logged; a signal that is not on the
// bus is a located error naming the closest.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "dmbd/base/error.hpp"
#include "dmbd/scenario/scenario.hpp"
#include "sim_test_support.hpp"

namespace {

namespace sc = dmbd::scenario;
using dmbd::sim::test::TempDir;
using dmbd::sim::test::write_text;

// DRACO on the table, the left knee free (no actuator, no controller), a 20 N upward
// push on the left foot for 0.25 s; `gate` changes at 0.3 s and 0.5 s.
std::string scenario(const std::string& force) {
  return "name: pushed\n"
         "robot: {name: draco, base: fixed, base_pose: {xyz: [0, 0, 1.3]}, moving: [l_knee], initial: {l_knee: 1.0}}\n"
         "integration: {mode: fixed, step_s: 0.0005}\n"
         "duration_s: 1.2\n"
         "log_rate_hz: 1000\n"
         "references: {gate: {type: steps, steps: [[0.3, 1], [0.5, 2]]}}\n"
         "forces:\n" + force;
}

dmbd::sim::VariantResult run(const std::string& path, const std::string& yaml) {
  write_text(path, yaml);
  const sc::Scenario s = sc::load_scenario(path);
  return sc::run_variant(s, s.variants.front(), {});
}

}  // namespace

TEST(TriggeredForce, StartsAtTheSecondChangePlusItsDelayAsTheSameForceAtThatTime) {
  TempDir dir;
  const auto triggered = run(dir.file("t.yaml"), scenario("  - {link: l_foot, direction: [0, 0, 1], source: {type: steps, steps: [[0, 20], [0.25, 0]]},\n"
                                                          "     trigger: {signal: gate, occurrence: 2, after_s: 0.25}}\n"));
  const auto timed = run(dir.file("a.yaml"), scenario("  - {link: l_foot, direction: [0, 0, 1], source: {type: steps, steps: [[0.75, 20], [1.0, 0]]}}\n"));
  const auto& start = triggered.log.column("forces.0.start_s");
  EXPECT_TRUE(std::isnan(start.front()));  // not known before the trigger
  EXPECT_EQ(start.back(), 0.75);
  const auto& q_t = triggered.log.column("l_knee.q");
  const auto& q_a = timed.log.column("l_knee.q");
  EXPECT_EQ(q_t, q_a);  // bit for bit
  // The push moved the knee (its path departs from the unpushed one after 0.75 s).
  const auto free = run(dir.file("f.yaml"), scenario("  - {link: l_foot, source: 0}\n"));
  const std::size_t k = 1000;  // t = 1.0 s
  EXPECT_EQ(q_t[700], free.log.column("l_knee.q")[700]);
  EXPECT_GT(std::abs(q_t[k] - free.log.column("l_knee.q")[k]), 1e-3);
}

// A trigger whose signal changes fewer times than its occurrence never fires: the run
// says so, once, naming the force and how many changes it saw.
TEST(TriggeredForce, OneThatNeverFiresIsAWarning) {
  TempDir dir;
  const auto r = run(dir.file("n.yaml"), scenario("  - {link: l_foot, source: 1, trigger: {signal: gate, occurrence: 3}}\n"));
  EXPECT_TRUE(std::isnan(r.log.column("forces.0.start_s").back()));
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("variant 'base': " + dir.file("n.yaml") +
                               ":8:12: force 0 on link 'l_foot': its trigger 'gate' changed 2 time(s), never reaching occurrence 3: the force was not applied"),
            std::string::npos)
      << r.warnings[0];
}

TEST(TriggeredForce, ASignalNotOnTheBusIsALocatedError) {
  TempDir dir;
  const std::string path = dir.file("e.yaml");
  try {
    run(path, scenario("  - {link: l_foot, source: 1, trigger: {signal: gaet}}\n"));
    FAIL() << "no error";
  } catch (const dmbd::InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path + ":8:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("force on link 'l_foot': trigger signal 'gaet' is not on the bus (the closest: 'gate')"), std::string::npos) << msg;
  }
  for (const auto& [bad, what] : {std::pair<std::string, std::string>{"occurrence: 0", "force.trigger.occurrence"},
                                  {"after_s: -1", "force.trigger.after_s"}, {"sginal: gate", "unknown key 'sginal'"}}) {
    write_text(path, scenario("  - {link: l_foot, source: 1, trigger: {signal: gate, " + bad + "}}\n"));
    try {
      sc::load_scenario(path);
      ADD_FAILURE() << bad;
    } catch (const dmbd::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path + ":8:"), std::string::npos) << e.what();
    }
  }
}
