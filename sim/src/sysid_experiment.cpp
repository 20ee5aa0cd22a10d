// The sysid_rfsea experiment (paper Fig. 5a). Being written: it needs the frequency-
// response estimation and the parameter fit of sysid.hpp, which are not committed yet.
#include "dmbd/blocks/error.hpp"
#include "dmbd/sim/experiments.hpp"
namespace dmbd::sim {
ExperimentResult sysid_rfsea(const Scenario& s, const std::vector<VariantResult>&) {
  throw InputError(s.file + ": experiment sysid_rfsea is not available in this build yet");
}
}  // namespace dmbd::sim
