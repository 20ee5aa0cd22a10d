#pragma once
// A scenario's runs turned into metrics and figures: its experiment (found in the
// registry, experiments/registry.hpp) and its own `plots:`; and what the frames of a
// variant draw over the robot (its bus controllers' and its experiment's overlays).
#include <vector>

#include "dmbd/experiments/experiment.hpp"
#include "dmbd/scenario/scenario.hpp"
#include "dmbd/sim/overlay.hpp"
#include "dmbd/sim/run_result.hpp"

namespace dmbd::scenario {

// What the experiment knows of variant v.
experiments::VariantFacts variant_facts(const VariantSetup& v);

// The scenario's experiment (if any) and its `plots:`, from the runs' logs (and truth,
// timing_us), runs in the scenario's variant order. Throws InputError naming the
// scenario file: a signal that is not in a run's log, a plot's variant that does not
// exist, or runs that do not fit the experiment.
experiments::ExperimentResult evaluate_experiment(const Scenario& s, const std::vector<sim::VariantResult>& runs);

// The overlays of variant v's frames: each bus controller's (by its type), then the
// experiment's.
std::vector<sim::Overlay> variant_overlays(const Scenario& s, const VariantSetup& v);

}  // namespace dmbd::scenario
