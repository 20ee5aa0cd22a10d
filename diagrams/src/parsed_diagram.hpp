#pragma once
// What DiagramSource holds (private to diagrams/src): the parsed file, every scalar of
// it that is an expression already parsed, and its subsystems' sources.
#include <yaml-cpp/yaml.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "dmbd/base/location.hpp"
#include "dmbd/blocks/expression.hpp"
#include "dmbd/diagrams/diagram_source.hpp"

namespace dmbd::diagrams {

struct ParsedDiagram {
  std::string path;  // as given: messages name it
  std::string key;   // canonical: subsystem cycles are found by it
  YAML::Node root;
  std::map<std::string, blocks::Expression, std::less<>> expressions;  // by their text
  // A subsystem block's diagram (by block name), or why it has none (cannot be read,
  // not YAML). Neither for a block that would include a file of its own chain.
  struct Subsystem {
    std::shared_ptr<const DiagramSource> source;
    std::vector<Diagnostic> errors;
  };
  std::map<std::string, Subsystem> subsystems;

  // The parsed expression of `text` (parsed now if it failed to parse at load; throws
  // ExpressionError then).
  blocks::Expression expression(const std::string& text) const;
};

// Evaluates a parsed diagram (load.cpp). `chain`: the canonical paths of the diagrams
// that include this one, itself last.
std::shared_ptr<const Diagram> evaluate_parsed(const ParsedDiagram& parsed, const blocks::ParameterMap& overrides,
                                               const std::map<std::string, Location>& override_where,
                                               const std::vector<std::string>& chain);

}  // namespace dmbd::diagrams
