#pragma once
// Internal to sim/: a scenario's controller built for its run: the diagram loaded with
// the controller's parameters, lowered at its rate, in its scalar type, its ports bound
// to bus signals (errors named where the scenario wrote them), and in fixed point the
// predicted error bound of each output over the run.
#include <vector>

#include "dmbd/sim/scenario.hpp"

namespace dmbd::sim {

struct VariantController {
  ControllerSpec spec;
  std::vector<FixedPointFacts> fixed_point;
};

VariantController variant_controller(const Scenario& s, const ControllerSetup& c, double duration_s);

// A warning on the run for every fixed-point output whose bound exceeds its range, and
// for saturations of a fixed-point controller (its bound does not hold past them).
void fixed_point_warnings(VariantResult& r);

}  // namespace dmbd::sim
