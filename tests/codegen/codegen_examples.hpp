#pragma once
// The diagrams of examples/diagrams that code generation takes, by name (file stem),
// sorted: every one but those with a sampled plant (a continuous plant inside a
// discrete diagram), which are for analysis only and which code generation refuses
// (tests/apps/test_analyze_sampled_cli.cpp checks that refusal).
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "dmbd/diagrams/diagram.hpp"

namespace dmbd::test {

inline std::vector<std::string> codegen_example_names(const std::string& examples_dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(examples_dir + "/diagrams")) {
    if (e.path().extension() != ".yaml") continue;
    const auto d = diagrams::Diagram::load(e.path().string());
    const auto& bl = d->blocks();
    if (std::none_of(bl.begin(), bl.end(), [](const diagrams::Block& b) { return b.sampled; }))
      names.push_back(e.path().stem().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace dmbd::test
