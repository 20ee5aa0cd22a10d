#pragma once
// `dmbd sweep collect`: the parts a plan's jobs wrote merged into one run directory.
#include <string>

#include "dmbd/scenario/run_directory.hpp"

namespace dmbd::apps {

// Reads DIR's plan, reloads its copy of the scenario, reads every job's part in the
// scenario's variant order and writes them into OUT as one run directory (log.csv,
// metrics.json with the experiment evaluated over every variant: scenario::write_run).
// Throws InputError before writing anything when a job did not finish, naming every
// such job (its line in jobs.txt, its variant, its part), when the plan's jobs are not
// the scenario's variants, or when a part is malformed.
scenario::ScenarioRun collect_sweep(const std::string& dir, const std::string& out);

}  // namespace dmbd::apps
