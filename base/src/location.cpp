#include "dmbd/base/location.hpp"

namespace dmbd {

std::string Location::str() const {
  std::string s = file.empty() ? std::string("<text>") : file;
  if (line > 0) s += ":" + std::to_string(line) + ":" + std::to_string(column);
  return s;
}

std::string Diagnostic::str() const { return where.str() + ": error: " + message; }

std::string join_plain(const std::vector<Diagnostic>& diagnostics) {
  std::string s;
  for (const Diagnostic& d : diagnostics) s += (s.empty() ? "" : "\n") + d.where.str() + ": " + d.message;
  return s;
}

}  // namespace dmbd
