#pragma once
// `dmbd report RUN_DIR [--no-frames] [--size WxH] [--camera X,Y,Z:X,Y,Z]`: redraws a run
// directory's report (plots/, frames/, video.mp4, report.html) from its log.csv and
// metrics.json, without simulating; with the run's own settings the files are those
// `dmbd simulate` wrote, pixel for pixel. A missing or malformed run: one line on
// stderr, exit code 2.
#include <CLI/CLI.hpp>

#include <string>

namespace dmbd::apps {

class ReportCommand {
 public:
  explicit ReportCommand(CLI::App& app);
  ReportCommand(const ReportCommand&) = delete;
  ReportCommand& operator=(const ReportCommand&) = delete;
  bool selected() const;
  int run() const;

 private:
  CLI::App* cmd_ = nullptr;
  std::string dir_, size_, camera_;
  bool no_frames_ = false;
};

}  // namespace dmbd::apps
