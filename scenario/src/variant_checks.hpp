#pragma once
// Internal to scenario/: the mistakes a variant would otherwise run with in silence, each
// refused with one line at the place it was written (docs/scenario-format.md, "What is
// checked before a run").
#include <vector>

#include "engine_names.hpp"
#include "variant_controllers.hpp"

#include "dmbd/model/plant.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/scenario/scenario.hpp"

namespace dmbd::scenario {

// robot.initial and robot.lock within each named joint's limits (robot.freeze is checked
// where it is welded). `robot` is the URDF as loaded.
void check_joint_angles(const Scenario& s, const RobotSetup& r, const model::RobotDescription& robot);

// The experiment's joint and its keys that name joints or links name the robot's.
void check_experiment_names(const Scenario& s, const model::RobotDescription& robot);

// Every explicit output binding of a scenario controller drives a plant input or is read
// by something (a controller, a plot, the experiment, an overlay, the scenario's log:
// list); every bus controller's joint command reaches the plant (read by the joint's
// loop, or itself a plant input). InputError at the binding (naming the closest plant
// input) or at the bus controller.
void check_outputs_reach(const Scenario& s, const VariantSetup& v, const SimulationSpec& spec, const model::Plant& plant,
                         const std::vector<BusControllerRun>& bus);

}  // namespace dmbd::scenario
