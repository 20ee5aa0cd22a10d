#pragma once
// `dmbd model ...`: commands on robot descriptions (URDF).
//   dmbd model info [URDF] [--json] [--package-path DIR ...] [--strict]
// prints a summary of a URDF (DRACO's when no file is given): links, degrees of
// freedom, joint counts, mass, height, meshes, every joint with its type, limits and
// axis, and the loader's warnings. A bad file: one line on stderr, exit code 2.
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace dmbd::apps {

class ModelCommand {
 public:
  // Adds the `model` subcommand (and `model info`) to `app`.
  explicit ModelCommand(CLI::App& app);
  ModelCommand(const ModelCommand&) = delete;  // CLI11 holds pointers to the members
  ModelCommand& operator=(const ModelCommand&) = delete;
  // Whether the command line chose `dmbd model ...` (valid after app.parse).
  bool selected() const;
  // Runs the chosen command; returns the exit code (0, or 2 for a bad file). Errors
  // are printed here, on one line of stderr.
  int run() const;

 private:
  CLI::App* model_ = nullptr;
  CLI::App* info_ = nullptr;
  std::string urdf_;
  std::vector<std::string> package_paths_;
  bool json_ = false;
  bool strict_ = false;
};

}  // namespace dmbd::apps
