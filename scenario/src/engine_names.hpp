#pragma once
// Internal to scenario/: the engine's names (dmbd::sim) its sources use unqualified.
#include "dmbd/sim/controller.hpp"
#include "dmbd/sim/event_grid.hpp"
#include "dmbd/sim/generated_controller.hpp"
#include "dmbd/sim/log.hpp"
#include "dmbd/sim/run_result.hpp"
#include "dmbd/sim/shared_object.hpp"
#include "dmbd/sim/signals.hpp"
#include "dmbd/sim/simulation.hpp"

namespace dmbd::scenario {

using sim::build_shared_objects;
using sim::Controller;
using sim::ControllerSpec;
using sim::Cooling;
using sim::DivergenceError;
using sim::EndOnFall;
using sim::FixedPointFacts;
using sim::ForceSpec;
using sim::generated_controller;
using sim::GeneratedController;
using sim::GeneratedSource;
using sim::kMaxDurationS;
using sim::Log;
using sim::loop_program_controller;
using sim::rate_problem;
using sim::ReferenceSpec;
using sim::Scalar;
using sim::SharedObjectBuild;
using sim::SharedObjectSource;
using sim::sil_source;
using sim::SilController;
using sim::SilFacts;
using sim::Simulation;
using sim::SimulationSpec;
using sim::Source;
using sim::SupportSpec;
using sim::VariantResult;

}  // namespace dmbd::scenario
