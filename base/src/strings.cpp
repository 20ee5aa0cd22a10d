#include "dmbd/base/strings.hpp"

#include <algorithm>

namespace dmbd {

std::string join(const std::vector<std::string>& names, const std::string& separator) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : separator) + n;
  return s;
}

// Written here: one row of the dynamic-programming table (no library in the project has it).
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> d(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) d[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t prev = d[0];
    d[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cur = d[j];
      d[j] = std::min({d[j] + 1, d[j - 1] + 1, prev + (a[i - 1] == b[j - 1] ? 0 : 1)});
      prev = cur;
    }
  }
  return d[b.size()];
}

std::string closest_name(const std::string& name, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t d = std::string::npos;
  for (const auto& c : candidates)
    if (const std::size_t x = edit_distance(name, c); x < d) d = x, best = c;
  return best;
}

}  // namespace dmbd
