#pragma once
// `dmbd model ...`: commands on robot descriptions (URDF).
//   dmbd model info [URDF] [--json] [--package-path DIR ...] [--strict]
// prints a summary of a URDF (DRACO's when no file is given): links, degrees of
// freedom, joint counts, mass, height, meshes, every joint with its type, limits and
// axis, and the loader's warnings.
//   dmbd model workspace ... (model_workspace_cmd.hpp)
#include <memory>
#include <string>
#include <vector>

#include "command.hpp"
#include "model_workspace_cmd.hpp"

namespace dmbd::apps {

class ModelCommand : public Command {
 public:
  // Adds the `model` subcommand (and `model info`) to `app`.
  explicit ModelCommand(CLI::App& app);
  int run() override;

 private:
  CLI::App* info_ = nullptr;
  std::string urdf_, robot_;
  std::vector<std::string> package_paths_;
  bool json_ = false;
  bool strict_ = false;
  std::unique_ptr<ModelWorkspace> workspace_;
};

}  // namespace dmbd::apps
