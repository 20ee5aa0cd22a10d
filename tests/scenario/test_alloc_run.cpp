// No heap allocation in a running simulation after its first moments: the whole loop
// of `dmbd simulate` (sim::Simulation::run: the plant's fixed steps, sensors with their
// noise, references, loop programs and bus controllers, thermals, the log) over the
// shipped standing.yaml and balance.yaml. The C allocator is interposed in this
// executable to count (as in tests/model/test_alloc_steps.cpp); skipped under
// AddressSanitizer. Counted between the progress reports at 30 % and at the end (the log
// is reserved for the whole run; the first ticks size what they keep).
#include <gtest/gtest.h>

#include "malloc_counter.hpp"

#include <string>

#include "dmbd/scenario/scenario.hpp"

using dmbd::test::g_allocations;

namespace dmbd::scenario {
namespace {

long allocations_while_running(const std::string& name, double duration_s) {
  const Scenario s = load_scenario(std::string(DMBD_SOURCE_DIR) + "/examples/scenarios/" + name + ".yaml");
  long at_start = -1, at_end = -1;
  RunOptions o;
  o.duration_s = duration_s;
  o.on_progress = [&](double f) {
    if (f >= 0.3 && at_start < 0) at_start = g_allocations.load();
    if (f >= 0.3) at_end = g_allocations.load();
  };
  run_variant(s, s.variants[0], o);
  EXPECT_GE(at_start, 0) << name << ": no progress report past 30 %";
  return at_end - at_start;
}

TEST(NoAllocation, StandingScenarioRunning) {
  DMBD_SKIP_UNDER_ASAN();
  EXPECT_EQ(allocations_while_running("standing", 2.0), 0) << "allocations in 1.4 s of standing.yaml";
}

TEST(NoAllocation, BalanceScenarioRunning) {
  DMBD_SKIP_UNDER_ASAN();
  EXPECT_EQ(allocations_while_running("balance", 4.0), 0) << "allocations in 2.8 s of balance.yaml";
}

}  // namespace
}  // namespace dmbd::scenario
