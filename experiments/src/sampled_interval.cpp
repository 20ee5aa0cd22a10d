// Where a condition holds over sampled values (sampled_interval.hpp).
#include "dmbd/experiments/sampled_interval.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace dmbd::experiments {

nlohmann::json sampled_interval(const std::vector<double>& x, const std::vector<bool>& holds) {
  nlohmann::json out;
  std::vector<double> at;
  for (std::size_t k = 0; k < x.size(); ++k)
    if (holds[k]) at.push_back(x[k]);
  out["holds_at"] = at;
  if (at.empty()) {
    out["verdict"] = "holds at no sampled value";
    return out;
  }
  const auto first = std::find(holds.begin(), holds.end(), true) - holds.begin();
  const auto last = holds.rend() - std::find(holds.rbegin(), holds.rend(), true) - 1;
  const bool contiguous = std::all_of(holds.begin() + first, holds.begin() + last + 1, [](bool b) { return b; });
  out["contiguous"] = contiguous;
  out["holds_from"] = x[static_cast<std::size_t>(first)];
  out["holds_to"] = x[static_cast<std::size_t>(last)];
  out["fails_below"] = first > 0 ? nlohmann::json(x[static_cast<std::size_t>(first - 1)]) : nlohmann::json();
  out["fails_above"] = last + 1 < static_cast<long>(x.size()) ? nlohmann::json(x[static_cast<std::size_t>(last + 1)]) : nlohmann::json();
  std::string v = fmt::format("holds at the sampled values {:g} to {:g}", at.front(), at.back());
  if (!contiguous) v += " (not at every sampled value between)";
  if (first > 0) v += fmt::format("; fails at {:g}", x[static_cast<std::size_t>(first - 1)]);
  if (last + 1 < static_cast<long>(x.size())) v += fmt::format("{} {:g}", first > 0 ? " and" : "; fails at", x[static_cast<std::size_t>(last + 1)]);
  out["verdict"] = v + (first > 0 || last + 1 < static_cast<long>(x.size()) ? " (the edge lies between the samples)" : "");
  return out;
}

}  // namespace dmbd::experiments
