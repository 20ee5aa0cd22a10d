#pragma once
// A diagram's structure apart from its parameter values: the file (and its subsystems'
// files) read and parsed once, evaluated at any parameter values without reading or
// parsing again. Tuning (tune.hpp) and `dmbd analyze --sweep` evaluate one source many
// times; Diagram::load is DiagramSource::load(path)->evaluate(overrides).
#include <memory>
#include <string>

#include "dmbd/diagrams/diagram.hpp"

namespace dmbd::diagrams {

struct ParsedDiagram;  // the YAML tree, its expressions and subsystem sources (src/)

// One diagram file (and its subsystems' files) read and parsed: made by load() or parse(),
// held as std::shared_ptr<const DiagramSource>, evaluated any number of times.
class DiagramSource {
 public:
  // Reads and parses the file and, recursively, the files of its subsystems. Throws
  // DiagramError when the file cannot be read (the system's reason), is not text or is
  // not YAML; problems in a subsystem's file are reported by evaluate(), at the block.
  static std::shared_ptr<const DiagramSource> load(const std::string& path);
  // The same from YAML text; `path` names it in messages and resolves subsystem files.
  static std::shared_ptr<const DiagramSource> parse(const std::string& yaml, const std::string& path);

  // The evaluated and validated diagram at these parameter values (every name must be
  // a parameter of the diagram). Throws DiagramError listing every problem found. Reads
  // no file and parses no text: the source is not changed.
  std::shared_ptr<const Diagram> evaluate(const blocks::ParameterMap& overrides = {}) const;

  // The path as given to load() (or the `path` of parse()): Diagram::file() of evaluate().
  const std::string& file() const;
  // The parsed tree (an opaque type outside diagrams/src: for the loader).
  const ParsedDiagram& parsed() const { return *parsed_; }

  // Wraps a parsed tree; load() and parse() make sources this way (ParsedDiagram is
  // private to diagrams/src, so other code cannot).
  explicit DiagramSource(std::shared_ptr<const ParsedDiagram> parsed) : parsed_(std::move(parsed)) {}

 private:
  std::shared_ptr<const ParsedDiagram> parsed_;
};

}  // namespace dmbd::diagrams
