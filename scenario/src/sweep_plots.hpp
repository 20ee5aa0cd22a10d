#pragma once
// The scenario's `sweep_plots` from its metrics (sweep_plots.cpp). Internal to scenario/.
#include "dmbd/experiments/experiment.hpp"
#include "dmbd/scenario/scenario.hpp"

namespace dmbd::scenario::detail {

// Adds each sweep plot's figure, its metrics.json `sweeps.STEM` entry and a note per
// line of runs to `res`, reading the curves' values from res.metrics. Throws InputError
// naming the scenario file and the entry's line when a curve's pointer finds no number
// for a run.
void add_sweep_plots(const Scenario& s, experiments::ExperimentResult& res);

}  // namespace dmbd::scenario::detail
