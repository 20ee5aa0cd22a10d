// Fuzz target: a run directory's log.csv read back (scenario::split_csv, as read_run and
// `dmbd report` read it), then the experiment evaluated on the logs it gave (as read_run
// does: the path of issue 28's crash in step_metrics). The scenario is
// examples/scenarios/position_controllers.yaml, loaded once; the input's first byte picks
// which of its three variants the run holds (as metrics.json would list them), the rest
// is log.csv. Any exception other than dmbd::InputError, a crash or a sanitizer report
// is a bug.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "dmbd/base/error.hpp"
#include "dmbd/scenario/evaluate.hpp"
#include "dmbd/scenario/run_directory.hpp"
#include "dmbd/scenario/scenario.hpp"

namespace {

const dmbd::scenario::Scenario& scenario() {
  static const dmbd::scenario::Scenario s =
      dmbd::scenario::load_scenario(std::string(DMBD_SOURCE_DIR) + "/examples/scenarios/position_controllers.yaml");
  return s;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const dmbd::scenario::Scenario& s = scenario();
  if (size == 0) return 0;
  std::vector<std::string> names;
  for (std::size_t k = 0; k < s.variants.size() && k < 8; ++k)
    if (data[0] & (1u << k)) names.push_back(s.variants[k].name);
  if (names.empty()) names.push_back(s.variants.front().name);
  const std::string csv(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    std::vector<dmbd::sim::Log> logs = dmbd::scenario::split_csv(csv, names, "log.csv");
    std::vector<dmbd::sim::VariantResult> runs(names.size());
    for (std::size_t k = 0; k < names.size(); ++k) {
      runs[k].name = names[k];
      runs[k].log = std::move(logs[k]);
    }
    (void)dmbd::scenario::evaluate_experiment(s, runs);
  } catch (const dmbd::InputError&) {
  }
  return 0;
}
