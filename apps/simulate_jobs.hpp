#pragma once
// `dmbd simulate --jobs N`: a scenario's variants run in N worker processes on this
// machine (docs/sweeps.md). Each worker is a fork of this process, made after the
// scenario was loaded and its generated controllers compiled, that runs one variant and
// writes it as a part (sim/run_parts.hpp) into a temporary folder; the parent reads the
// parts back in the scenario's order. No scheduler beyond "at most N at a time".
#include <functional>
#include <string>
#include <vector>

#include "dmbd/scenario/run_directory.hpp"

namespace dmbd::apps {

// The runs of every variant of s, in the scenario's order, at most `jobs` at a time.
// o.on_progress is called in this process as variants finish. When a worker fails, no
// further one starts, the running ones are waited for, and the error of the first
// failed variant in the scenario's order is thrown again here: an InputError with the
// worker's message (the one a single process would print), anything else as an internal
// error. The temporary folder is removed in every case.
std::vector<sim::VariantResult> run_variants_in_processes(const scenario::Scenario& s, const scenario::ScenarioRunOptions& o, int jobs);

}  // namespace dmbd::apps
