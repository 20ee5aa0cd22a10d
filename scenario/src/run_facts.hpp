#pragma once
// Internal to scenario/: a variant's run facts (metrics.json runs.RUN: wall time, step
// counts, truth, generated-code facts ...) as JSON and back. metrics.json and a sweep's
// part.json hold the same entry, so read_run and read_part read it the same way.
#include <string>

#include <nlohmann/json.hpp>

#include "engine_names.hpp"
#include "dmbd/scenario/scenario.hpp"

namespace dmbd::scenario {

// runs.RUN of metrics.json (not yet through finite_json).
nlohmann::json run_json(const VariantResult& r);
// The facts of run_json read back into r (its name, axes and log are the caller's).
void read_run_json(const nlohmann::json& j, VariantResult& r);

}  // namespace dmbd::scenario
