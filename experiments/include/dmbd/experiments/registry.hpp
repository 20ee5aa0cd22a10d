#pragma once
// The experiment types a scenario can name (`experiment: {type: T, ...}`): one registry,
// the built-in ones (the paper's) listed in registry.cpp, one line each, and types
// registered at run time (a test's, a user's).
#include <memory>
#include <string>
#include <vector>

#include "dmbd/experiments/experiment.hpp"

namespace dmbd::experiments {

// Registers (or replaces) a type under `type`. Not thread-safe against concurrent lookups.
void register_experiment(const std::string& type, std::shared_ptr<const Experiment> e);
// The type registered under `type`, or null.
const Experiment* find_experiment(const std::string& type);
// Every registered type's name, sorted.
std::vector<std::string> experiment_types();

}  // namespace dmbd::experiments
