#pragma once
// The output damping replayed (damping_replay.cpp): a run's logged actuator motion and
// current, with each joint's output-side damping B_l changed to s times the run's own,
// turned into the motor current that motion would then take and the winding
// temperatures that current gives over a longer time (the logged segment repeated).
// No controller is in this loop: the motion is the run's. Internal to experiments/.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dmbd/base/figure.hpp"
#include "dmbd/experiments/experiment.hpp"

namespace dmbd::experiments::detail {

struct ReplayParams {
  std::vector<std::string> joints;         // the windings replayed (`winding_joints`)
  std::vector<double> scales;              // `replay_scales`: B_l' = s x the run's B_l, s >= 0
  double duration_s = 600;                 // `replay_duration_s`: the time replayed, the segment repeated
  double from_s = 0;                       // `replay_from_s`: the segment runs from here to the run's end
  std::optional<double> cooled_below_C;    // `replay_cooled_below_C`: the cooled peak must stay below
  std::optional<double> uncooled_above_C;  // `replay_uncooled_above_C`: the uncooled peak must pass
};

// The parameters the replay needs of each joint's actuator, into the run's truth
// ("JOINT.B_l", "JOINT.N_m", "JOINT.k_tau", "JOINT.efficiency", "JOINT.current_limit_A",
// "JOINT.thermal.KEY"); a joint without an actuator records nothing.
void record_replay(const std::vector<std::string>& joints, const RecordContext& c, std::map<std::string, double>& truth);

struct ReplayOutcome {
  nlohmann::json metrics;   // per scale and joint: current RMS, time over the current limit, winding peaks
  plot::Figure figure;      // the peaks against s, the thresholds dashed
  std::string note;         // the verdict, one line
};
// The replay of run r, or nothing when r has no actuator on the joints (no truth
// recorded for them). Throws InputError naming `file` for a segment with fewer than 3
// samples or a missing actuator signal.
std::optional<ReplayOutcome> replay_damping(const sim::VariantResult& r, const ReplayParams& p, const std::string& file);

}  // namespace dmbd::experiments::detail
