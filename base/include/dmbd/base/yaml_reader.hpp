#pragma once
// The located YAML reader: every YAML file a user writes (diagrams, scenarios, the
// actuator table) is read through one, so that every problem is reported the same way:
// at its file:line:column, saying what was expected, and all of them rather than the
// first (docs/architecture.md, "The located YAML reader").
//
// A Reader collects diagnostics. Its value functions (number, integer, text, ...) return
// the value, or record a diagnostic and throw Skip, which abandons that one value: the
// caller wraps what depends on it in guard() and reading goes on. When the file has
// been read, diagnostics() holds every problem, and the module throws them as its own
// kind of InputError (DiagramError, ModelError, ...).
//
// Numbers go through the reader's NumberParser (number_parser.hpp): plain numbers by
// default; expressions (`2*1000`, `pi/4`) where the module above base supplies them.
#include <yaml-cpp/yaml.h>

#include <set>
#include <string>
#include <vector>

#include "dmbd/base/location.hpp"
#include "dmbd/base/number_parser.hpp"

namespace dmbd::yaml {

// Thrown after a problem has been recorded: abandons the value being read. A
// NumberParser may throw it too, for a number whose problem is reported already.
struct Skip {};

class Reader {
 public:
  explicit Reader(std::string file, NumberParser numbers = plain_number);

  const std::string& file() const { return file_; }
  const std::vector<Diagnostic>& diagnostics() const { return diagnostics_; }
  bool failed() const { return !diagnostics_.empty(); }

  // The YAML tree of a file's bytes. Records (then Skip) a file that is not text, tabs
  // in indentation and malformed YAML, each at its line and column.
  YAML::Node parse(const std::string& bytes);

  // Where n is written (`offset` columns further on); the file alone (line 0) for a
  // node that is not in the file, such as a missing key.
  Location at(const YAML::Node& n, int offset = 0) const;
  // Records a problem (once: the same message at the same place again is dropped).
  void error(const Location& where, const std::string& message);
  void error(const YAML::Node& n, const std::string& message) { error(at(n), message); }
  [[noreturn]] void fail(const Location& where, const std::string& message);
  [[noreturn]] void fail(const YAML::Node& n, const std::string& message) { fail(at(n), message); }
  // f() with its Skip caught: false when it was thrown.
  template <class F>
  bool guard(F&& f) {
    try {
      f();
      return true;
    } catch (const Skip&) {
      return false;
    }
  }

  // ---- maps. `context` starts each message ("controller: ..."), when not empty.
  // A key that is a name, not a list, a map or empty.
  std::string key(const YAML::Node& k, const std::string& context);
  // n must be a map (else Skip); every key that is not a name, not in `allowed` or
  // given twice is recorded: "unknown NOUN 'k' (expected one of: ...)". False if any.
  bool keys(const YAML::Node& n, const std::vector<std::string>& allowed, const std::string& context,
            const std::string& noun = "key");
  // The list map[key] (an empty value is reported at its key's place).
  YAML::Node list(const YAML::Node& map, const std::string& key, const std::string& what);

  // ---- values. `what` names the value in messages ("controller.rate_hz").
  double number(const YAML::Node& n, const std::string& what);  // finite
  double positive(const YAML::Node& n, const std::string& what);
  // A number within [lo, hi] (`unit` in the message, e.g. "s").
  double number_in(const YAML::Node& n, const std::string& what, double lo, double hi, const std::string& unit = "");
  // A whole number within [lo, hi], checked before it is converted.
  long long integer(const YAML::Node& n, const std::string& what, long long lo, long long hi);
  std::string text(const YAML::Node& n, const std::string& what);
  bool boolean(const YAML::Node& n, const std::string& what);

 private:
  [[noreturn]] void fail_parse(const YAML::Exception& e, const std::string& bytes);

  std::string file_;
  NumberParser numbers_;
  std::vector<Diagnostic> diagnostics_;
  std::set<std::string> seen_;  // diagnostics_ as text: each is recorded once
};

// A scalar's text for a message: quoted, and cut short past 60 characters.
std::string quoted(const std::string& text);

}  // namespace dmbd::yaml
