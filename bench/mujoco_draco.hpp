#pragma once
// DRACO in MuJoCo (2.2, Debian's libmujoco-dev; bench only): the anchor of the whole-robot
// speed benchmark. The MuJoCo model is generated from the project's own RobotDescription
// (and actuator table), never from a hand-written MJCF, so both engines simulate the same
// links, joints and feet. No MuJoCo type appears here: without MuJoCo (DMBD_HAVE_MUJOCO
// undefined) this still compiles, draco_mjcf still works and run_mujoco_standing throws.

#include "standing_task.hpp"

#include "dmbd/model/actuator.hpp"
#include "dmbd/model/robot_description.hpp"

#include <string>
#include <vector>

namespace dmbd::bench {

// The line bench_standing prints instead of running the comparison.
inline constexpr const char* kMujocoMissing = "MuJoCo not found: comparison skipped";

bool mujoco_available();        // built with MuJoCo
std::string mujoco_version();   // "2.2.2", or "" without MuJoCo

// MJCF text of the robot standing as in `task` (root height, timestep, integrator, gravity,
// friction). actuators_or_null == nullptr: ideal joint torques (one motor of gear 1 per
// 1-dof joint, control = N m). Otherwise each listed actuator becomes an elastic joint
// (rotor hinge + spring tendon, control = current in A; see mujoco_draco.cpp).
std::string draco_mjcf(const dmbd::model::RobotDescription& robot,
                       const std::vector<dmbd::model::ActuatorParams>* actuators_or_null,
                       const StandingTask& task);

// Compiles draco_mjcf, places the robot, runs the standing task and returns its real-time
// factor (stepping loop only) and outcome. Throws std::runtime_error with the MuJoCo
// compiler's message, or kMujocoMissing without MuJoCo.
StandingResult run_mujoco_standing(const dmbd::model::RobotDescription& robot,
                                   const std::vector<dmbd::model::ActuatorParams>* actuators_or_null,
                                   const StandingTask& task);

}  // namespace dmbd::bench
