// Reading and parsing a diagram once (DiagramSource); evaluating it is load.cpp's.
#include "dmbd/diagrams/diagram_source.hpp"

#include <algorithm>
#include <filesystem>

#include "dmbd/base/file.hpp"
#include "dmbd/base/yaml_reader.hpp"
#include "parsed_diagram.hpp"

namespace dmbd::diagrams {

namespace b = dmbd::blocks;
namespace fs = std::filesystem;

b::Expression ParsedDiagram::expression(const std::string& text) const {
  const auto it = expressions.find(text);
  return it != expressions.end() ? it->second : b::Expression::parse(text);
}

namespace {

std::string canonical_key(const fs::path& path) {
  std::error_code ec;
  const fs::path c = fs::weakly_canonical(path, ec);
  return ec ? path.string() : c.string();
}

// Every scalar value of the tree that parses as an expression (names, numbers,
// formulas), parsed once. An explicit stack: a deeply nested file must not overflow.
void parse_expressions(const YAML::Node& root, ParsedDiagram& p) {
  std::vector<YAML::Node> stack{root};
  while (!stack.empty()) {
    const YAML::Node n = stack.back();
    stack.pop_back();
    if (n.IsScalar()) {
      if (p.expressions.count(n.Scalar())) continue;
      try {
        p.expressions.emplace(n.Scalar(), b::Expression::parse(n.Scalar()));
      } catch (const InputError&) {
        // not an expression: reported where a number is expected
      }
    } else if (n.IsSequence()) {
      for (const auto& e : n) stack.push_back(e);
    } else if (n.IsMap()) {
      for (const auto& kv : n) stack.push_back(kv.second);
    }
  }
}

std::shared_ptr<const DiagramSource> make_source(const std::string& bytes, const std::string& path,
                                                 std::vector<std::string> chain);

// The subsystem a block of type subsystem names in `file`, read and parsed (unless its
// file is one of `chain`: evaluation reports that cycle).
void add_subsystem(const std::string& name, const YAML::Node& file, ParsedDiagram& p, const std::vector<std::string>& chain) {
  yaml::Reader rd(p.path);
  const fs::path path = fs::path(p.path).parent_path() / file.Scalar();
  const std::string key = canonical_key(path);
  if (std::find(chain.begin(), chain.end(), key) != chain.end()) return;
  ParsedDiagram::Subsystem& sub = p.subsystems[name];
  std::string bytes;
  if (const auto reason = try_read_text_file(path.string(), bytes)) {
    sub.errors.push_back({rd.at(file), "subsystem '" + name + "': cannot read diagram file '" + path.string() + "': " + *reason});
    return;
  }
  std::vector<std::string> sub_chain = chain;
  sub_chain.push_back(key);
  try {
    sub.source = make_source(bytes, path.string(), sub_chain);
  } catch (const DiagramError& e) {
    sub.errors = e.diagnostics();
  }
}

void add_subsystems(ParsedDiagram& p, const std::vector<std::string>& chain) {
  const YAML::Node& root = p.root;  // const: a non-const operator[] would add the key
  const YAML::Node blocks = root.IsMap() ? root["blocks"] : YAML::Node();
  if (!blocks.IsDefined() || !blocks.IsMap()) return;
  for (const auto& kv : blocks) {
    const YAML::Node& blk = kv.second;
    if (!kv.first.IsScalar() || !blk.IsMap()) continue;
    const YAML::Node type = blk["type"], file = blk["file"];
    if (type.IsDefined() && type.IsScalar() && type.Scalar() == "subsystem" && file.IsDefined() && file.IsScalar())
      add_subsystem(kv.first.Scalar(), file, p, chain);
  }
}

// `chain` ends with this file's own canonical path.
std::shared_ptr<const DiagramSource> make_source(const std::string& bytes, const std::string& path,
                                                 std::vector<std::string> chain) {
  auto p = std::make_shared<ParsedDiagram>();
  p->path = path;
  p->key = chain.back();
  yaml::Reader rd(path);
  if (!rd.guard([&] { p->root = rd.parse(bytes); })) throw DiagramError(rd.diagnostics());
  parse_expressions(p->root, *p);
  add_subsystems(*p, chain);
  return std::make_shared<const DiagramSource>(std::move(p));
}

}  // namespace

std::shared_ptr<const DiagramSource> DiagramSource::parse(const std::string& yaml, const std::string& path) {
  return make_source(yaml, path, {canonical_key(path)});
}

std::shared_ptr<const DiagramSource> DiagramSource::load(const std::string& path) {
  std::string bytes;
  if (const auto reason = try_read_text_file(path, bytes))
    throw DiagramError({Diagnostic{Location{path, 0, 0}, "cannot read diagram file '" + path + "': " + *reason}});
  return parse(bytes, path);
}

std::shared_ptr<const Diagram> DiagramSource::evaluate(const b::ParameterMap& overrides) const {
  return evaluate_parsed(*parsed_, overrides, {}, {parsed_->key});
}

const std::string& DiagramSource::file() const { return parsed_->path; }

}  // namespace dmbd::diagrams
