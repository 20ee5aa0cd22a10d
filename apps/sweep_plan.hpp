#pragma once
// `dmbd sweep plan`: a scenario's variants as self-contained jobs for GNU parallel or a
// Slurm job array (docs/sweeps.md), and the plan `dmbd sweep collect` reads back.
#include <optional>
#include <string>
#include <vector>

#include "dmbd/scenario/scenario.hpp"

namespace dmbd::apps {

// One job: a variant, and where it writes its part (relative to the plan's folder).
struct SweepJob {
  std::string variant;  // the variant's name
  std::string part;     // "parts/K", K its line in jobs.txt (from 1)
};

// A plan folder's plan.json.
struct SweepPlan {
  std::string scenario;        // the copied scenario file, relative to the folder
  std::vector<SweepJob> jobs;  // in the scenario's variant order
};

// Writes the plan of s into DIR: scenario/ (s and every file it reads, copied with their
// relative places kept), jobs.txt (one shell command per variant, run from DIR: `DMBD
// simulate scenario/... --variant V --out parts/K [--duration S]`), slurm.sbatch,
// README.txt, plan.json and an empty parts/. DIR must not exist or be empty; everything
// is written into DIR.tmp and renamed, so a failure leaves no half plan. Throws
// OutputError for a folder that cannot be written or a DIR that is not empty.
SweepPlan write_sweep_plan(const scenario::Scenario& s, const std::string& dir, const std::string& dmbd,
                           const std::string& duration_text);

// DIR/plan.json read back. Throws InputError naming the file when it is missing or
// malformed (expected a folder written by dmbd sweep plan).
SweepPlan read_sweep_plan(const std::string& dir);

}  // namespace dmbd::apps
