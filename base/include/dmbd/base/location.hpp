#pragma once
// A place in a user's file and a problem found there: what every reader of user files
// (diagrams, scenarios, the actuator table) reports. Lines and columns are 1-based, 0
// when unknown.
#include <string>
#include <vector>

namespace dmbd {

struct Location {
  std::string file;
  int line = 0, column = 0;
  std::string str() const;  // "file:line:column"; "file" when the line is unknown
};

struct Diagnostic {
  Location where;
  std::string message;
  std::string str() const;  // "file:line:column: error: message"
};

// One diagnostic a line, each "file:line:column: message" (without the word "error").
std::string join_plain(const std::vector<Diagnostic>& diagnostics);

}  // namespace dmbd
