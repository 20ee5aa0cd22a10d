#pragma once
// `dmbd sweep plan SCENARIO --out DIR [--dmbd PATH] [--duration S]`: a scenario's
// variants as self-contained jobs for GNU parallel or a Slurm job array;
// `dmbd sweep collect DIR [--out OUT] [--no-frames]`: their parts merged into one run
// directory and its report, as `dmbd simulate` writes them (docs/sweeps.md).
#include <string>

#include "command.hpp"

namespace dmbd::apps {

class SweepCommand : public Command {
 public:
  explicit SweepCommand(CLI::App& app);
  int run() override;

 private:
  int plan() const;
  int collect() const;

  CLI::App* plan_ = nullptr;
  CLI::App* collect_ = nullptr;
  std::string scenario_, plan_out_, dmbd_, duration_text_;  // plan
  std::string dir_, collect_out_;                           // collect
  bool no_frames_ = false;
};

}  // namespace dmbd::apps
