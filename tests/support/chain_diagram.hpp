#pragma once
// A diagram of n copies of one block in a chain from input u to output y, as YAML text
// (b0 … b{n-1}): the large diagrams of the analysis tests and bench_analysis (issue 13,
// item 11). `block` is a block's YAML map, e.g. "{type: tf, expr: \"10/(s+10)\"}".
#include <string>

namespace dmbd::test {

inline std::string chain_diagram(int n, const std::string& block) {
  std::string y = "name: chain\ninputs: {u: {}}\noutputs: {y: {}}\nblocks:\n";
  for (int i = 0; i < n; ++i) y += "  b" + std::to_string(i) + ": " + block + "\n";
  y += "connections:\n  - u -> b0\n";
  for (int i = 1; i < n; ++i) y += "  - b" + std::to_string(i - 1) + " -> b" + std::to_string(i) + "\n";
  return y + "  - b" + std::to_string(n - 1) + " -> y\n";
}

}  // namespace dmbd::test
