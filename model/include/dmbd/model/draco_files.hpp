#pragma once
// Where DRACO's robot files are (draco.urdf, actuators.yaml, meshes/): the folder named
// by the environment variable DMBD_DRACO_DIR when it is set; else the installed copy
// (<prefix>/share/dmbd/draco, `cmake --install`) when it exists; else the source tree's
// model/draco of the build the library came from.
#include <string>

namespace dmbd::model {

std::string draco_dir();

}  // namespace dmbd::model
