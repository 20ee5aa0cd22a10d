#pragma once
// Where a condition holds over a swept parameter, said of the sampled values only (a
// sweep plot's lines, the damping replay's scales): between a sample where it holds and
// the next where it fails, the edge is not located.
#include <vector>

#include <nlohmann/json.hpp>

namespace dmbd::experiments {

// x ascending, holds[k] the condition at x[k] (same length). Returns
//   holds_at     the x where it holds
//   verdict      a sentence: "holds at no sampled value", or "holds at the sampled values
//                A to B[ (not at every sampled value between)][; fails at C[ and D]]
//                [ (the edge lies between the samples)]"
// and, when it holds somewhere: holds_from, holds_to (first and last x where it holds),
// contiguous (it holds at every sample between them), fails_below, fails_above (the
// samples just outside them, or null).
nlohmann::json sampled_interval(const std::vector<double>& x, const std::vector<bool>& holds);

}  // namespace dmbd::experiments
