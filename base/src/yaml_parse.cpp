// Reader::parse: bytes to a YAML tree, with the messages a user can act on.
#include <algorithm>

#include "dmbd/base/text.hpp"
#include "dmbd/base/yaml_reader.hpp"

namespace dmbd::yaml {

namespace {

// The first tab in the indentation of lines 1..last_line (1-based line and column), if any.
std::optional<std::pair<int, int>> indentation_tab(const std::string& text, int last_line) {
  int line = 1;
  std::size_t start = 0;
  while (start < text.size() && line <= last_line) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::size_t indent_end = std::min(text.find_first_not_of(" \t", start), end);
    const std::size_t tab = text.find('\t', start);
    if (tab < indent_end) return std::make_pair(line, static_cast<int>(tab - start) + 1);
    start = end + 1;
    line += 1;
  }
  return std::nullopt;
}

}  // namespace

YAML::Node Reader::parse(const std::string& bytes) {
  if (const auto d = not_text(bytes, file_)) fail(d->where, d->message);
  try {
    return YAML::Load(bytes);
  } catch (const YAML::Exception& e) {
    fail_parse(e, bytes);
  }
}

// yaml-cpp says "illegal map value" or "illegal tab when looking for indentation" for a
// tab in the indentation: name the tab, at its place, when one comes before the error.
void Reader::fail_parse(const YAML::Exception& e, const std::string& bytes) {
  const int line = e.mark.is_null() ? 0 : e.mark.line + 1;
  const auto tab = indentation_tab(bytes, std::max(line, 1));
  if (tab) fail(Location{file_, tab->first, tab->second}, "tabs are not allowed in YAML indentation (indent with spaces)");
  if (line == 0) fail(Location{file_, 0, 0}, "malformed YAML: " + e.msg);
  fail(Location{file_, line, e.mark.column + 1}, "malformed YAML: " + e.msg);
}

}  // namespace dmbd::yaml
