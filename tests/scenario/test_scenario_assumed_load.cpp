// A bus controller's `assumed_load_set` (control/bus_controller.hpp): the controller computes
// with another load set of the actuator file than the plant runs on. On balance.yaml's
// actuated variant (the plant on DRACO's `robot` set), the balancing feedforward assuming
// the `stand` set (Table I's B_l, 5 times the robot's) changes the knee's current once the
// robot steps (5 s: the first steps), while the plant's B_l stays the robot's; a set the file
// lacks, or a plant without actuators, is one located error.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "dmbd/base/error.hpp"
#include "dmbd/control/balance_controller.hpp"
#include "dmbd/scenario/scenario.hpp"
#include "bus_options.hpp"
#include "sim_test_support.hpp"

namespace dmbd::scenario {
namespace {

Scenario shipped_balance() { return load_scenario(std::string(DMBD_SOURCE_DIR) + "/examples/scenarios/balance.yaml"); }

sim::VariantResult run_for(const Scenario& s, const VariantSetup& v, double duration_s) {
  RunOptions o;
  o.duration_s = duration_s;
  return run_variant(s, v, o);
}

double knee_b_l(const Scenario& s, const VariantSetup& v) {
  for (const auto& a : variant_plant(s, v).options.actuators)
    if (a.joint == "l_knee") return a.B_l_Ns_per_m;
  return NAN;
}

TEST(AssumedLoadSet, TheControllerComputesWithTheNamedSetThePlantKeepsItsOwn) {
  const Scenario s = shipped_balance();
  const VariantSetup& plain = s.variants.at(0);
  ASSERT_EQ(plain.name, "actuated");
  VariantSetup assumed = plain;
  dmbd::test::edit_bus_options<control::BalanceSetup>(assumed).assumed_load_set = "stand";
  EXPECT_EQ(knee_b_l(s, plain), 4.0e3);
  EXPECT_EQ(knee_b_l(s, assumed), 4.0e3);
  const sim::VariantResult a = run_for(s, plain, 5.0), b = run_for(s, assumed, 5.0);
  const auto& ia = a.log.column("l_knee.current"), & ib = b.log.column("l_knee.current");
  ASSERT_EQ(ia.size(), ib.size());
  double largest = 0.0;
  for (std::size_t k = 0; k < ia.size(); ++k) largest = std::max(largest, std::abs(ia[k] - ib[k]));
  RecordProperty("largest_current_difference_A", std::to_string(largest));
  EXPECT_GT(largest, 0.05);  // the swing knee's rate times 1.6e4 N s/m more damping, over N_m
}

TEST(AssumedLoadSet, AnUnknownSetOrAPlantWithoutActuatorsIsOneLocatedError) {
  const Scenario s = shipped_balance();
  VariantSetup unknown = s.variants.at(0);
  auto& o = dmbd::test::edit_bus_options<control::BalanceSetup>(unknown);
  o.assumed_load_set = "moon";
  o.assumed_load_set_where = "here.yaml:7:5";
  try {
    run_for(s, unknown, 0.01);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("here.yaml:7:5: balance.assumed_load_set: ", 0), 0u) << m;
    EXPECT_NE(m.find("no load set 'moon'"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
  VariantSetup ideal = s.variants.at(1);
  ASSERT_EQ(ideal.name, "ideal_joints");
  auto& p = dmbd::test::edit_bus_options<control::BalanceSetup>(ideal);
  p.assumed_load_set = "stand";
  p.assumed_load_set_where = "here.yaml:9:5";
  try {
    run_for(s, ideal, 0.01);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("here.yaml:9:5: balance.assumed_load_set: the plant has no actuators"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dmbd::scenario
