#pragma once
// The files a scenario reads, so that it can be copied whole to run elsewhere (`dmbd
// sweep plan`, docs/sweeps.md).
#include <string>
#include <vector>

#include "dmbd/sim/scenario.hpp"

namespace dmbd::sim {

// Every file s reads: the scenario file first, then each variant's controller diagrams
// and, recursively, their subsystems' files, and a URDF other than DRACO's built-in one
// with the mesh files it loads. Each once, as absolute normalised paths. DRACO's own
// files (model/draco) are not listed: every dmbd has them. Throws what loading them
// throws (a diagram or URDF that no longer loads).
std::vector<std::string> scenario_files(const Scenario& s);

}  // namespace dmbd::sim
