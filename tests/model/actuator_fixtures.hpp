#pragma once
// The actuator-file tests' shared helpers: a fixture's path (tests/model/data/actuators/),
// a file's text, and a text with one piece replaced (a mistake written into a valid table).
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace dmbd::model::testing {

inline std::string actuator_fixture(const std::string& name) { return std::string(DMBD_MODEL_TEST_DATA) + "/actuators/" + name; }

inline std::string text_of(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// `text` with the first `from` replaced by `to`; std::logic_error when there is none.
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  if (at == std::string::npos) throw std::logic_error("no '" + from + "'");
  return text.replace(at, from.size(), to);
}

}  // namespace dmbd::model::testing
