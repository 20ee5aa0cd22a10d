#pragma once
// `dmbd report RUN_DIR [--no-frames] [--size WxH] [--camera X,Y,Z:X,Y,Z]`: redraws a run
// directory's report (plots/, frames/, video.mp4, report.html) from its log.csv and
// metrics.json, without simulating; with the run's own settings the files are those
// `dmbd simulate` wrote, pixel for pixel.
#include <string>

#include "command.hpp"

namespace dmbd::apps {

class ReportCommand : public Command {
 public:
  explicit ReportCommand(CLI::App& app);
  int run() override;

 private:
  std::string dir_, size_, camera_;
  bool no_frames_ = false;
};

}  // namespace dmbd::apps
