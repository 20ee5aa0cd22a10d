#pragma once
// Internal to scenario/: a scenario's controller built for its run: the diagram loaded with
// the controller's parameters, lowered at its rate, in its scalar type, run by the
// interpreter or as its generated code (sil_controller.hpp), its ports bound to bus
// signals (errors named where the scenario wrote them), and in fixed point the
// predicted error bound of each output over the run.
#include <memory>
#include <vector>

#include "engine_names.hpp"
#include "dmbd/sim/generated_controller.hpp"

#include "dmbd/control/bus_controller.hpp"
#include "dmbd/scenario/scenario.hpp"

namespace dmbd::scenario {

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

// A bus controller of a variant: its options and the controller built from them.
struct BusControllerRun {
  std::shared_ptr<const control::BusControllerOptions> options;
  std::shared_ptr<control::BusController> controller;
};
// The variant's bus controllers (VariantSetup::bus_controllers), each built by its type
// (control/registry.hpp) for the robot as simulated, the plant's actuators and the
// variant's initial angles, with storage for every tick's wall time over duration_s.
std::vector<BusControllerRun> bus_controllers(const VariantSetup& v, const VariantPlant& vp, const model::Plant& plant, double duration_s);
// A controller whose ports are bound to the bus signals they are named after, with its
// options' name, delay and where they were written.
sim::ControllerSpec bus_controller_spec(const control::BusControllerOptions& o, std::shared_ptr<sim::Controller> c);
// The median and largest of a controller's tick times: timing_us[prefix + "_tick_us_median"]
// and [prefix + "_tick_us_max"].
void tick_timing(const std::vector<double>& times_us, const std::string& prefix, VariantResult& r);

// The URDF limits the run met: the ideal torques the plant clamped to a joint's effort
// limit, the joints beyond their velocity limit (a warning each).
void record_limits(const Simulation& sim, const model::Plant& plant, VariantResult& r);

// A warning on the run for every fixed-point output whose bound exceeds its range, and
// for saturations of a fixed-point controller (its bound does not hold past them).
void fixed_point_warnings(VariantResult& r);

}  // namespace dmbd::scenario
