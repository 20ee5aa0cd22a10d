#include "sweep_cmd.hpp"

#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "dmbd/report/report.hpp"
#include "simulate_cmd.hpp"
#include "sweep_collect.hpp"
#include "sweep_plan.hpp"

namespace dmbd::apps {

namespace fs = std::filesystem;

SweepCommand::SweepCommand(CLI::App& app)
    : Command(app, "sweep", "Run a scenario's variants on many machines: plan them as jobs for GNU parallel or Slurm, collect their results") {
  cmd_->require_subcommand(1);
  plan_ = cmd_->add_subcommand("plan", "Write one self-contained job per variant (jobs.txt, slurm.sbatch) with a copy of the scenario");
  plan_->add_option("scenario", scenario_, "A scenario file (YAML, docs/scenario-format.md)")->required();
  plan_->add_option("--out", plan_out_, "The plan's folder (new or empty)")->required();
  plan_->add_option("--dmbd", dmbd_, "The dmbd the jobs run (default: this one, by its absolute path)");
  plan_->add_option("--duration", duration_text_, "Simulated time of every variant (s), instead of the scenario's");
  collect_ = cmd_->add_subcommand("collect", "Merge the jobs' parts into one run directory (log.csv, metrics.json) and its report");
  collect_->add_option("dir", dir_, "A folder written by dmbd sweep plan, its jobs run")->required();
  collect_->add_option("--out", collect_out_, "Output folder (default: DIR/run)");
  collect_->add_flag("--no-frames", no_frames_, "Do not render frames or the video");
}

int SweepCommand::run() { return plan_->parsed() ? plan() : collect(); }

int SweepCommand::plan() const {
  if (!duration_text_.empty()) parse_duration(duration_text_);
  const std::string dmbd = dmbd_.empty() ? fs::read_symlink("/proc/self/exe").string() : dmbd_;
  const scenario::Scenario s = scenario::load_scenario(scenario_);
  const SweepPlan p = write_sweep_plan(s, plan_out_, dmbd, duration_text_);
  const std::string& d = plan_out_;
  std::cout << fmt::format("planned {} jobs of {} in {} (one per variant; each runs {})\n", p.jobs.size(), s.file, d, dmbd);
  for (const char* f : {"scenario/", "jobs.txt", "slurm.sbatch", "README.txt", "plan.json"}) std::cout << "wrote " << d << "/" << f << "\n";
  std::cout << fmt::format("run them:  cd {0} && parallel :::: jobs.txt    (GNU parallel; more machines: {0}/README.txt)\n"
                           "      or:  cd {0} && sbatch slurm.sbatch     (a Slurm job array)\n"
                           "then:      dmbd sweep collect {0}\n",
                           d);
  return 0;
}

int SweepCommand::collect() const {
  const std::string out = collect_out_.empty() ? (fs::path(dir_) / "run").string() : collect_out_;
  const scenario::ScenarioRun r = collect_sweep(dir_, out);
  print_run_directory(r, out);
  report::ReportOptions ro;
  ro.frames = !no_frames_;
  print_report(report::write_report(r, out, ro), out);
  return 0;
}

}  // namespace dmbd::apps
