#pragma once
// The project's errors: one hierarchy for every module (docs/architecture.md).
//
// InputError is a mistake in what the user gave: a file, an expression, an option, a
// parameter, a model that diverges. Its message is one line naming where (file:line:col,
// option, signal) and what was expected; the command line prints it and exits with
// status 2. Modules derive their own kinds from it (ModelError, DiagramError, ...) and
// let it travel up unwrapped: a caller that knows more of where it happened adds that
// to the same object (prepend, append) and rethrows it (`throw;`), keeping its type.
// Internal invariants use assertions, not these.
#include <stdexcept>
#include <string>
#include <utility>

namespace dmbd {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message), message_(message) {}
  const char* what() const noexcept override { return message_.c_str(); }
  // "scenario.yaml: variant 'fast': " + the message.
  void prepend(const std::string& context) { message_ = context + message_; }
  // The message + " (l_knee q = 0.3 rad ...)".
  void append(const std::string& detail) { message_ += detail; }

 private:
  std::string message_;
};

// An output that cannot be written (a read-only folder, a directory where the file
// should go, a full disk): the message names the path and the system's reason.
class OutputError : public InputError {
 public:
  using InputError::InputError;
};

}  // namespace dmbd
