#pragma once
// Internal to experiments/: what the balance experiments (balance_experiment.cpp,
// push_map.cpp) read of a balancing run's log, found once: where stepping starts, the
// fall, the touch-downs and landings, and the pushes it took with their outcome and the
// pendulum's verdict (push_capture.hpp).
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "experiment_support.hpp"
#include "push_capture.hpp"

namespace dmbd::experiments::detail {

// A push was survived when the robot did not fall within this long of its end (and the
// run lasted that long).
constexpr double kSurviveAfterPushS = 3.0;

// The balance experiments' keys as read (balance_experiment.cpp documents them).
struct BalanceParams {
  std::string leg;
  double start_s, fall_height_m, fall_tilt_rad;
  std::string prefix;                        // the balancing controller's signals: its name and "."
  std::vector<std::string> winding_joints;   // whose winding temperatures are reported (`winding_joints`)
  // Fig. 7d's contrast (`winding_cooled_below_C`, `winding_uncooled_above_C`): the cooled
  // windings' peak must stay below the first, the uncooled ones' must pass the second.
  std::optional<double> cooled_below_C, uncooled_above_C;
  std::optional<SwingLimits> reach;          // `swing_speed_max_m_s` and `swing_accel_max_m_s2`: the pushes' verdicts count the foot's reach
  const ExperimentSetup* setup = nullptr;    // its figure labels
};

// What the metrics and the figures share of one variant's log, found once.
struct BalanceRun {
  const VariantResult& r;
  const std::vector<double>& t;
  std::string prefix;                      // BalanceParams::prefix
  std::size_t start = 0;                   // first sample at or after start_s
  std::size_t fall = 0;                    // first sample past the fall limits, or rows
  std::vector<std::size_t> touch_downs{};  // samples where balance.touch_downs rose, before the fall
  std::vector<std::size_t> landings{};     // samples where balance.landings rose, before the fall
  bool fell() const { return fall < t.size(); }
  double end_s() const { return fell() ? t[fall] : t.back(); }
};

// The run's stepping start, fall (torso below fall_height_m or tilted beyond
// fall_tilt_rad at a log sample: the first), touch-downs and landings. InputError naming
// file for a signal it did not log.
BalanceRun analyse_run(const VariantResult& r, const BalanceParams& p, const std::string& file);

// The swing foot's largest horizontal speed and acceleration while it swings (phase
// Swing), from stepping's start to the fall: central differences of the logged
// balance.swing_x/y over ±1 sample (speed) and ±2 samples (acceleration), only where
// every sample of the stencil is in the same swing. What the foot did, not what it could
// do: a lower bound on its limits. NaN without a swing.
struct SwingPeaks {
  double speed_m_s, accel_m_s2;
};
SwingPeaks swing_peaks(const BalanceRun& run, const std::string& file);

// The keys read_balance_params reads besides the experiment's own: start_s, the fall
// limits and the swing's reach.
std::map<std::string, KeyKind> balance_keys();

// The keys every balance experiment shares (start_s, fall limits, the swing's reach; its
// controller's prefix from the variants); InputError naming the file for limits given
// alone or not positive.
BalanceParams read_balance_params(const ExperimentSetup& e, const std::vector<VariantFacts>& variants);

// The variant's pushes (each interval a force's source is nonzero, up to its duration,
// also those a fall ended the run before): [{start_s, duration_s, force_N, direction,
// survived, lipm}] in the order of their start (balance_experiment.cpp, metrics).
nlohmann::json push_metrics(const BalanceRun& run, const VariantFacts& v, const std::optional<SwingLimits>& reach, const std::string& file);

}  // namespace dmbd::experiments::detail
