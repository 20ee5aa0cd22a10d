#pragma once
// `dmbd simulate SCENARIO.yaml --out DIR [--no-frames] [--duration S]`: runs a scenario
// (docs/scenario-format.md) and writes log.csv, metrics.json, plots/, frames/,
// video.mp4 and report.html into DIR. A bad scenario or a diverging simulation: one
// line on stderr, exit code 2.
#include <CLI/CLI.hpp>

#include <optional>
#include <string>

namespace dmbd::apps {

class SimulateCommand {
 public:
  explicit SimulateCommand(CLI::App& app);
  SimulateCommand(const SimulateCommand&) = delete;
  SimulateCommand& operator=(const SimulateCommand&) = delete;
  bool selected() const;
  int run() const;

 private:
  CLI::App* cmd_ = nullptr;
  std::string scenario_, out_;
  bool no_frames_ = false;
  double duration_ = 0;
};

}  // namespace dmbd::apps
