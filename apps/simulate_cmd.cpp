#include "simulate_cmd.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <iostream>

#include <fmt/format.h>

#include "dmbd/base/progress.hpp"
#include "dmbd/blocks/error.hpp"
#include "dmbd/model/error.hpp"
#include "dmbd/report/report.hpp"
#include "dmbd/scenario/run_directory.hpp"
#include "dmbd/scenario/run_parts.hpp"
#include "simulate_jobs.hpp"

namespace dmbd::apps {

void print_report(const report::ReportResult& r, const std::string& out) {
  for (const auto& w : r.warnings) std::cerr << "dmbd: warning: " << w << "\n";
  for (const auto& f : r.files)
    if (f.rfind("frames/", 0) != 0) std::cout << "wrote " << out << "/" << f << "\n";
  if (r.frames > 0) std::cout << fmt::format("wrote {}/frames/ ({} frames, rendered at {:.0f} frames/s)\n", out, r.frames, r.render_fps);
  std::cout << "report: " << r.page << "\n";
}

void print_run(const sim::VariantResult& run) {
  std::cout << fmt::format("{}: {:.3g} s simulated in {:.3g} s (real-time factor {:.3g})\n", run.name,
                           run.log.time().empty() ? 0.0 : run.log.time().back(), run.wall_s, run.real_time_factor);
}

void print_run_directory(const scenario::ScenarioRun& r, const std::string& out) {
  for (const auto& run : r.runs) print_run(run);
  for (const auto& f : r.files) std::cout << "wrote " << out << "/" << f << "\n";
}

double parse_duration(const std::string& text) {
  char* end = nullptr;
  const double d = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(d) || !(d > 0))
    throw InputError("--duration '" + text + "': expected a positive number of seconds");
  return d;
}

namespace {

// A progress bar on stderr when it is a terminal, once the run has taken more than a
// second, with the time elapsed and the time remaining; its line is ended when the run
// ends, also by an error.
class ProgressBar {
 public:
  ProgressBar() : tty_(isatty(STDERR_FILENO) != 0), start_(std::chrono::steady_clock::now()) {}
  ~ProgressBar() {
    if (drawn_) std::fprintf(stderr, "\n");
  }
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // The bar with the time elapsed and the time remaining (dmbd::progress_line).
  void show(double f, const std::string& variant) {
    if (!tty_) return;
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (el < 1.0 && f < 1.0) return;
    std::fprintf(stderr, "\r%s\033[K", progress_line(f, variant, el).c_str());  // \033[K: clear the rest of the line
    drawn_ = true;
  }

 private:
  bool tty_, drawn_ = false;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace

SimulateCommand::SimulateCommand(CLI::App& app)
    : Command(app, "simulate",
              "Run a scenario against a robot's model and write a log, metrics, plots, frames, a video and an HTML "
              "report") {
  cmd_->add_option("scenario", scenario_, "A scenario file (YAML, docs/scenario-format.md)")->required();
  cmd_->add_option("--out", out_, "Output folder (created if missing)")->required();
  cmd_->add_flag("--no-frames", no_frames_, "Do not render frames or the video");
  cmd_->add_option("--duration", duration_text_, "Simulated time of every variant (s), instead of the scenario's");
  cmd_->add_option("--jobs", jobs_, "Run the variants in this many processes at once (default 1)");
  cmd_->add_option("--variant", variant_,
                   "Run only this variant and write it as a part of a sweep (log.bin, part.json; no experiment, no report)");
}

int SimulateCommand::run() {
  scenario::ScenarioRunOptions o;
  if (!duration_text_.empty()) o.duration_s = parse_duration(duration_text_);
  if (jobs_ < 1 || jobs_ > 1024) throw InputError(fmt::format("--jobs {}: expected a number of processes from 1 to 1024", jobs_));
  if (!variant_.empty() && jobs_ != 1) throw InputError("--variant runs one variant in this process: --jobs does not apply");
  const scenario::Scenario s = scenario::load_scenario(scenario_);
  for (const auto& line : scenario::scenario_notes(s)) std::cerr << "dmbd: " << line << "\n";
  if (!variant_.empty()) return run_part(s, o);
  const scenario::ScenarioRun r = [&] {
    ProgressBar bar;
    o.on_progress = [&bar](double f, const std::string& variant) { bar.show(f, variant); };
    if (jobs_ == 1 || s.variants.size() == 1) return scenario::run_scenario(s, out_, o);
    return scenario::write_run(s, run_variants_in_processes(s, o, jobs_), out_);
  }();
  print_run_directory(r, out_);
  report::ReportOptions ro;
  ro.frames = !no_frames_;
  print_report(report::write_report(r, out_, ro), out_);
  return 0;
}

int SimulateCommand::run_part(const scenario::Scenario& s, const scenario::ScenarioRunOptions& o) const {
  const sim::VariantResult run = scenario::run_scenario_variant(s, scenario::find_variant(s, variant_), o);
  scenario::write_part(s, run, out_);
  print_run(run);
  std::cout << "wrote " << out_ << "/log.bin\nwrote " << out_ << "/part.json\n";
  return 0;
}

}  // namespace dmbd::apps
