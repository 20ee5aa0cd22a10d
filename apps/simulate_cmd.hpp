#pragma once
// `dmbd simulate SCENARIO.yaml --out DIR [--no-frames] [--duration S] [--jobs N]`: runs a
// scenario (docs/scenario-format.md), writing the run directory (log.csv, metrics.json:
// sim), then its report (plots/, frames/, video.mp4, report.html: report/) into DIR;
// with --jobs the variants run in N processes (docs/sweeps.md). `--variant NAME` runs
// one variant and writes it as a sweep's part into DIR (log.bin, part.json).
#include <optional>
#include <string>

#include "command.hpp"
#include "dmbd/report/report.hpp"
#include "dmbd/scenario/run_directory.hpp"

namespace dmbd::apps {

// The files a report wrote, one line each (frames as one line), and the page; its
// warnings on stderr.
void print_report(const report::ReportResult& r, const std::string& out);
// One run's line: "NAME: 2 s simulated in 1.59 s (real-time factor 1.26)".
void print_run(const sim::VariantResult& run);
// Each run's line, then "wrote DIR/FILE" per file of the run directory.
void print_run_directory(const scenario::ScenarioRun& r, const std::string& out);
// --duration: a finite positive number of seconds, else InputError.
double parse_duration(const std::string& text);

class SimulateCommand : public Command {
 public:
  explicit SimulateCommand(CLI::App& app);
  int run() override;

 private:
  // --variant: the one variant run and written as a part.
  int run_part(const scenario::Scenario& s, const scenario::ScenarioRunOptions& o) const;

  std::string scenario_, out_;
  bool no_frames_ = false;
  std::string duration_text_;
  int jobs_ = 1;
  std::string variant_;
};

}  // namespace dmbd::apps
