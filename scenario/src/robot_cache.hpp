#pragma once
// Internal to scenario/: a URDF read once per process (with its meshes), however many
// variants, notes and frames ask for it: loading DRACO's meshes costs more than a second
// of its simulation. Keyed by the file's path, size and modification time, so an edited
// file is read again. Thread-safe.
#include <memory>
#include <string>

#include "dmbd/model/robot_description.hpp"

namespace dmbd::scenario::detail {

// model::load_urdf(path), read once; throws what it throws (and reads it again next time).
std::shared_ptr<const model::RobotDescription> cached_urdf(const std::string& path);

}  // namespace dmbd::scenario::detail
