#pragma once
// DRACO in DART (6.12, Debian's libdart-dev and libdart-utils-urdf-dev, plus
// libdart-collision-ode-dev for the ODE collision detector; bench only): a second anchor of
// the whole-robot speed benchmark next to MuJoCo. The skeleton is read from the same URDF
// the project loads (RobotDescription::source) by DART's own URDF loader
// (dart::utils::DartLoader), with a floating base (FreeJoint root), and runs exactly the
// StandingTask (standing_task.hpp):
//   - placed as the task says (torso upright at standing_root_height_m, every joint at 0),
//     gravity, DART's step = the task's timestep (1 ms);
//   - the task's ideal joint PD torques, computed every control period from the state at
//     that instant and held until the next (zero-order hold), applied as joint forces
//     without limits (as MuJoCo's motors: no ctrllimited);
//   - the URDF's joint position limits enforced (DART's joint limit constraint; MuJoCo's
//     and the project's plant enforce them too);
//   - collision only between the foot contact spheres (the URDF's collision shapes: four
//     spheres of r = 0.03 m per foot) and a ground box 10 x 10 x 0.1 m whose top face is
//     z = 0; any non-sphere collision shape of the URDF is left out of collision, as the
//     MuJoCo model has sphere geoms only; the robot's self-collision check is off, so the
//     spheres never collide with one another (MuJoCo: contype 0 on the spheres);
//   - Coulomb friction of the task (0.8) on the spheres and the ground (DART combines
//     the two coefficients by their minimum), restitution 0;
//   - DART's default constraint solver (boxed LCP, Dantzig with PGS fallback) and contact
//     parameters, untuned; the collision detector is FCL (DartFcl, FCLCollisionDetector as
//     created: primitives as meshes, DART's contact points) or ODE (DartOde,
//     OdeCollisionDetector).
// Variants: only ideal_euler. DART's integrator is its own fixed one (semi-implicit Euler:
// velocities, then positions with the new velocities), so "ideal_implicit" is skipped for
// DART; the VLCAs (elastic actuators) are not modelled in DART, so "elastic_euler" is
// skipped too.
//
// No DART type appears here: without DART (DMBD_HAVE_DART undefined) this still compiles,
// dart_available() returns false and the runners throw kDartMissing. DartOde needs DART's
// collision-ode component (DMBD_HAVE_DART_ODE); without it dart_ode_available() is false
// and run_dart_ode_standing throws.

#include "standing_task.hpp"

#include "dmbd/model/actuator.hpp"
#include "dmbd/model/robot_description.hpp"

#include <string>
#include <vector>

namespace dmbd::bench {

// The lines bench_standing prints instead of running DART (or DART with ODE).
inline constexpr const char* kDartMissing = "DART not found: comparison skipped";
inline constexpr const char* kDartOdeMissing =
    "DART's ODE collision detector not found (libdart-collision-ode-dev): DartOde skipped";

bool dart_available();       // built with DART (the FCL collision detector comes with it)
bool dart_ode_available();   // built with DART's ODE collision detector
std::string dart_version();  // "6.12.1", or "" without DART

// Whether the DART engines run this variant: ideal torques (actuators == nullptr) with
// the Euler integrator only (see above).
bool dart_supports(bool elastic, Integrator integrator);

// Loads robot.source with DartLoader (once per file; each run works on a clone), builds
// the world, places the robot, runs the standing task and returns its real-time factor
// (stepping loop only: the world build is not timed) and outcome. Throws
// std::invalid_argument for a variant dart_supports refuses, std::runtime_error when the
// URDF cannot be loaded, or kDartMissing / kDartOdeMissing without DART / its ODE detector.
StandingResult run_dart_fcl_standing(const dmbd::model::RobotDescription& robot,
                                     const std::vector<dmbd::model::ActuatorParams>* actuators_or_null,
                                     const StandingTask& task);
StandingResult run_dart_ode_standing(const dmbd::model::RobotDescription& robot,
                                     const std::vector<dmbd::model::ActuatorParams>* actuators_or_null,
                                     const StandingTask& task);

}  // namespace dmbd::bench
