#pragma once
// `dmbd simulate SCENARIO.yaml --out DIR [--no-frames] [--duration S]`: runs a scenario
// (docs/scenario-format.md), writing the run directory (log.csv, metrics.json: sim),
// then its report (plots/, frames/, video.mp4, report.html: report/) into DIR. A bad
// scenario or a diverging simulation: one line on stderr, exit code 2.
#include <CLI/CLI.hpp>

#include <optional>
#include <string>

#include "dmbd/report/report.hpp"

namespace dmbd::apps {

// The files a report wrote, one line each (frames as one line), and the page; its
// warnings on stderr.
void print_report(const report::ReportResult& r, const std::string& out);
// --duration: a finite positive number of seconds, else InputError.
double parse_duration(const std::string& text);

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
  std::string duration_text_;
};

}  // namespace dmbd::apps
