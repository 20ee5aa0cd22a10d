// Fuzz target: the URDF loader (model/src/urdf_loader.cpp, parse_urdf) on XML text.
// Meshes are not loaded (load_meshes = false): that is assimp on files, not parsing.
// Any exception other than dmbd::model::ModelError, a crash or a sanitizer report is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "dmbd/model/error.hpp"
#include "dmbd/model/robot_description.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string base_dir = std::string(DMBD_SOURCE_DIR) + "/fuzz";
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    dmbd::model::UrdfOptions options;
    options.load_meshes = false;
    (void)dmbd::model::parse_urdf(text, base_dir, "fuzz.urdf", options);
  } catch (const dmbd::model::ModelError&) {
  }
  return 0;
}
