#pragma once
// `dmbd model workspace`: a link's workspace by sampling the joint space (the paper's
// Fig. 2; docs/model.md section 8).
//   dmbd model workspace [URDF] --link LINK --out DIR [--relative-to LINK] [--samples N]
//                        [--seed S] [--cell M]
// writes DIR/workspace_xz.png and DIR/workspace_yz.png (density maps in the sagittal and
// frontal planes), DIR/range_of_motion.png (each joint of the chain at both limits) and
// DIR/workspace.json, and prints one line per file, the extents and the sampling.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

namespace dmbd::apps {

class ModelWorkspace {
 public:
  // Adds the `workspace` subcommand to `model`.
  explicit ModelWorkspace(CLI::App& model);
  bool selected() const { return cmd_->parsed(); }
  int run();

 private:
  CLI::App* cmd_ = nullptr;
  std::string urdf_, robot_, link_, relative_to_, out_, samples_ = "100000", cell_ = "0.02";
  std::uint64_t seed_ = 1;
};

}  // namespace dmbd::apps
