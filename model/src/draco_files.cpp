// Where DRACO's robot files are (draco_files.hpp).
#include "dmbd/model/draco_files.hpp"

#include <cstdlib>
#include <filesystem>

namespace dmbd::model {

std::string draco_dir() {
  if (const char* env = std::getenv("DMBD_DRACO_DIR"); env != nullptr && *env != '\0') return env;
  std::error_code ec;
  if (std::filesystem::is_regular_file(DMBD_DRACO_INSTALL_DIR "/draco.urdf", ec)) return DMBD_DRACO_INSTALL_DIR;
  return DMBD_DRACO_SOURCE_DIR;
}

}  // namespace dmbd::model
