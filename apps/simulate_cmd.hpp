#pragma once
// `dmbd simulate SCENARIO.yaml --out DIR [--no-frames] [--duration S]`: runs a scenario
// (docs/scenario-format.md), writing the run directory (log.csv, metrics.json: sim),
// then its report (plots/, frames/, video.mp4, report.html: report/) into DIR.
#include <optional>
#include <string>

#include "command.hpp"
#include "dmbd/report/report.hpp"

namespace dmbd::apps {

// The files a report wrote, one line each (frames as one line), and the page; its
// warnings on stderr.
void print_report(const report::ReportResult& r, const std::string& out);
// --duration: a finite positive number of seconds, else InputError.
double parse_duration(const std::string& text);

class SimulateCommand : public Command {
 public:
  explicit SimulateCommand(CLI::App& app);
  int run() override;

 private:
  std::string scenario_, out_;
  bool no_frames_ = false;
  std::string duration_text_;
};

}  // namespace dmbd::apps
