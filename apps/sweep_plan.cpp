#include "sweep_plan.hpp"

#include <cctype>
#include <filesystem>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "dmbd/base/error.hpp"
#include "dmbd/base/file.hpp"
#include "dmbd/scenario/scenario_files.hpp"

namespace dmbd::apps {

namespace {

namespace fs = std::filesystem;

std::string quote(const std::string& a) {
  std::string q = "'";
  for (char c : a) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// The deepest folder holding every file.
fs::path common_folder(const std::vector<std::string>& files) {
  fs::path root = fs::path(files.front()).parent_path();
  for (const auto& f : files)
    while (fs::path(f).lexically_relative(root).string().rfind("..", 0) == 0) root = root.parent_path();
  return root;
}

// The files copied under DIR/scenario/ with their places relative to their common folder
// kept (so relative references between them still hold); the scenario's copy returned.
std::string copy_scenario(const scenario::Scenario& s, const fs::path& dir) {
  const std::vector<std::string> files = scenario::scenario_files(s);
  const fs::path root = common_folder(files);
  for (const auto& f : files) {
    const fs::path to = dir / "scenario" / fs::path(f).lexically_relative(root);
    std::error_code ec;
    fs::create_directories(to.parent_path(), ec);
    if (ec) throw OutputError("cannot create the folder '" + to.parent_path().string() + "': " + ec.message());
    write_file_atomic(to.string(), read_file(f));
  }
  return (fs::path("scenario") / fs::path(files.front()).lexically_relative(root)).string();
}

std::string jobs_text(const SweepPlan& p, const std::string& dmbd, const std::string& duration_text) {
  std::string text;
  for (const auto& j : p.jobs)
    text += fmt::format("{} simulate {} --variant {} --out {}{}\n", quote(dmbd), quote(p.scenario), quote(j.variant), j.part,
                        duration_text.empty() ? "" : " --duration " + quote(duration_text));
  return text;
}

// The scenario's name as one word of a Slurm job name: sbatch splits an #SBATCH line at
// blanks (a name with a space is refused: "Invalid directive found in batch script"),
// and a line break would end the comment it is also written in.
std::string slurm_word(const std::string& name) {
  std::string w;
  for (char c : name) w += std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-' ? c : '_';
  return w;
}

// Task K runs line K of jobs.txt in the folder Slurm starts it in: the submission folder,
// or sbatch --chdir's.
std::string sbatch_text(const scenario::Scenario& s, std::size_t n) {
  return fmt::format(R"SH(#!/bin/bash
# A Slurm job array: task K runs line K of jobs.txt (one variant of {0}).
# Submit from this folder: sbatch slurm.sbatch (from elsewhere: sbatch --chdir=THIS_FOLDER
# THIS_FOLDER/slurm.sbatch); then: dmbd sweep collect THIS_FOLDER
#SBATCH --job-name=dmbd-{0}
#SBATCH --array=1-{1}
#SBATCH --ntasks=1
#SBATCH --cpus-per-task=1
#SBATCH --output=slurm-%A_%a.out
set -euo pipefail
if [ ! -f jobs.txt ]; then
  echo "slurm.sbatch: no jobs.txt in $PWD (submit from the plan's folder, or with --chdir=PLAN)" >&2
  exit 2
fi
job=$(sed -n "${{SLURM_ARRAY_TASK_ID}}p" jobs.txt)
eval "$job"
)SH",
                     slurm_word(s.name), n);
}

std::string readme_text(const scenario::Scenario& s, const SweepPlan& p, const std::string& dmbd) {
  return fmt::format(R"(A sweep of the scenario '{}': {} jobs, one per variant (dmbd sweep plan; docs/sweeps.md).

  scenario/     the scenario and every file it reads, copied (relative places kept)
  jobs.txt      one shell command per job, run from this folder; job K writes parts/K/
  slurm.sbatch  a Slurm job array: task K runs line K of jobs.txt
  plan.json     the jobs, for dmbd sweep collect
  parts/        the jobs' results: log.bin and part.json (written last) each

Every job runs {} (another: dmbd sweep plan --dmbd PATH).

On this machine, with GNU parallel (one job per core):
  cd THIS_FOLDER && parallel :::: jobs.txt
On several machines that see this folder at the same path (a shared file system) and have dmbd:
  cd THIS_FOLDER && parallel --sshlogin host1,host2,: --workdir "$PWD" :::: jobs.txt
Without a shared folder, GNU parallel can copy the scenario there and the parts back
(not tried in the project's tests, which have no ssh hosts):
  parallel --sshlogin host1,host2 --basefile scenario --workdir ... --return parts/{{#}} :::: jobs.txt
With Slurm (a job array; the folder on the cluster's shared file system; --wait: until all ended):
  cd THIS_FOLDER && sbatch [--wait] slurm.sbatch
  sbatch --chdir=THIS_FOLDER THIS_FOLDER/slurm.sbatch      (from another folder)
Then merge the parts into one run directory with its report (DIR/run by default):
  dmbd sweep collect THIS_FOLDER [--out OUT] [--no-frames]
A job that failed or did not run is named by collect; run its line of jobs.txt again.
)",
                     s.name, p.jobs.size(), dmbd);
}

nlohmann::json plan_json(const scenario::Scenario& s, const SweepPlan& p) {
  nlohmann::json j = {{"scenario", p.scenario}, {"scenario_name", s.name}, {"jobs", nlohmann::json::array()}};
  for (const auto& job : p.jobs) j["jobs"].push_back({{"variant", job.variant}, {"part", job.part}});
  return j;
}

void check_empty(const fs::path& dir) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) return;
  if (!fs::is_directory(dir, ec)) throw OutputError("--out '" + dir.string() + "': a file is in the way (expected a new folder)");
  if (!fs::is_empty(dir, ec)) throw OutputError("--out '" + dir.string() + "': the folder is not empty (a plan is written into a new folder)");
}

}  // namespace

SweepPlan write_sweep_plan(const scenario::Scenario& s, const std::string& dir, const std::string& dmbd, const std::string& duration_text) {
  const fs::path out = fs::path(dir).lexically_normal(), tmp = out.string() + ".tmp";
  check_empty(out);
  std::error_code ec;
  fs::remove_all(tmp, ec);
  fs::create_directories(tmp / "parts", ec);
  if (ec) throw OutputError("cannot create the folder '" + tmp.string() + "': " + ec.message());
  SweepPlan p;
  try {
    p.scenario = copy_scenario(s, tmp);
    for (std::size_t k = 0; k < s.variants.size(); ++k) p.jobs.push_back({s.variants[k].name, fmt::format("parts/{}", k + 1)});
    write_file_atomic((tmp / "jobs.txt").string(), jobs_text(p, dmbd, duration_text));
    write_file_atomic((tmp / "slurm.sbatch").string(), sbatch_text(s, p.jobs.size()));
    write_file_atomic((tmp / "README.txt").string(), readme_text(s, p, dmbd));
    write_file_atomic((tmp / "plan.json").string(), plan_json(s, p).dump(2) + "\n");
    fs::rename(tmp, out, ec);  // replaces an empty folder
    if (ec) throw OutputError("cannot rename '" + tmp.string() + "' to '" + out.string() + "': " + ec.message());
  } catch (...) {
    fs::remove_all(tmp, ec);
    throw;
  }
  return p;
}

SweepPlan read_sweep_plan(const std::string& dir) {
  const std::string file = (fs::path(dir) / "plan.json").string();
  std::string text;
  if (const auto reason = try_read_text_file(file, text))
    throw InputError(file + ": cannot read the plan: " + *reason + " (expected a folder written by dmbd sweep plan)");
  SweepPlan p;
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    p.scenario = j.at("scenario").get<std::string>();
    for (const auto& job : j.at("jobs")) p.jobs.push_back({job.at("variant").get<std::string>(), job.at("part").get<std::string>()});
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file + ": not a sweep plan (expected 'scenario' and 'jobs', written by dmbd sweep plan): " + e.what());
  }
  return p;
}

}  // namespace dmbd::apps
