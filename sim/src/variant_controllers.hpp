#pragma once
// Internal to sim/: a scenario's controller built for its run: the diagram loaded with
// the controller's parameters, lowered at its rate, in its scalar type, run by the
// interpreter or as its generated code (sil_controller.hpp), its ports bound to bus
// signals (errors named where the scenario wrote them), and in fixed point the
// predicted error bound of each output over the run.
#include <memory>
#include <vector>

#include "sil_controller.hpp"

#include "dmbd/sim/scenario.hpp"

namespace dmbd::sim {

struct VariantController {
  ControllerSpec spec;
  std::vector<FixedPointFacts> fixed_point;
  std::shared_ptr<GeneratedController> generated;  // the same as spec.controller, as its generated code
};

VariantController variant_controller(const Scenario& s, const ControllerSetup& c, double duration_s);

// Compiles the generated code of every controller of the scenario's variants that runs
// as its generated code (implementation: generated), several at once, before any
// variant runs; each later variant_controller() finds its object built. Throws
// InputError "FILE: variant 'V': FILE:LINE:COL: controller 'C': the generated code does
// not compile (c++): the compiler's first error line (full log: PATH)".
void build_generated_controllers(const Scenario& s);

// After the run of `spec`: the saturation blocks engaged per controller (none for one
// that does not count them), and the scenario's controllers that ran as their generated
// code, with their compiler (r.sil).
void record_controllers(const Simulation& sim, const SimulationSpec& spec, const std::vector<VariantController>& scenario_controllers,
                        VariantResult& r);

// The variant's operational space controller (VariantSetup::osc): the robot as
// simulated with its base fixed where the scenario fixed it, the plant's actuators, the
// variant's initial angles; storage for every tick's wall time over duration_s. Throws
// InputError at the osc map for a floating base.
std::shared_ptr<OscController> osc_controller(const Scenario& s, const VariantSetup& v, const VariantPlant& vp,
                                              const model::Plant& plant, double duration_s);
// A controller whose ports are bound to the bus signals they are named after (the
// operational space and balancing controllers), with its delay and where it was set up.
ControllerSpec bus_controller_spec(const std::string& name, double delay_s, const std::string& where,
                                   std::shared_ptr<Controller> c);
// The median and largest wall time of its evaluations into r.timing_us.
// The variant's balancing controller (VariantSetup::balance); throws InputError at the
// balance map for a fixed base or no contact.
std::shared_ptr<BalanceController> balance_controller(const Scenario& s, const VariantSetup& v, const VariantPlant& vp,
                                                      const model::Plant& plant, double duration_s);
// The median and largest of a controller's tick times: timing_us[prefix + "_tick_us_median"]
// and [prefix + "_tick_us_max"].
void tick_timing(const std::vector<double>& times_us, const std::string& prefix, VariantResult& r);

// A warning on the run for every fixed-point output whose bound exceeds its range, and
// for saturations of a fixed-point controller (its bound does not hold past them).
void fixed_point_warnings(VariantResult& r);

}  // namespace dmbd::sim
