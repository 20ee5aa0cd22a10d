#pragma once
// The files a scenario reads, so that it can be copied whole to run elsewhere (`dmbd
// sweep plan`, docs/sweeps.md).
#include <string>
#include <vector>

#include "dmbd/scenario/scenario.hpp"

namespace dmbd::scenario {

// Every file s reads: the scenario file first, then each variant's controller diagrams
// and, recursively, their subsystems' files, its robot folder's robot.yaml, the URDF
// with the mesh files it loads and the actuator file. Each once, as absolute normalised
// paths. The files of dmbd's own robot folders (installed, or the source tree's robots/)
// are not listed: every dmbd has them. Throws what loading them throws (a diagram or
// URDF that no longer loads).
std::vector<std::string> scenario_files(const Scenario& s);

}  // namespace dmbd::scenario
