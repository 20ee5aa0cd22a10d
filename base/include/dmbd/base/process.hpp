#pragma once
// Programs started without a shell: an argument vector handed to posix_spawnp (the first
// word looked up on the PATH unless it holds a '/'), so that no file name, however it is
// spelt (quotes, ';', '$', spaces), is ever read as a command. Standard input is
// /dev/null; standard output and error go to files or are captured.
#include <string>
#include <vector>

namespace dmbd {

struct ProgramRun {
  int exit_code = -1;  // the program's exit status; -1 when it did not start or did not exit (a signal)
  std::string why;     // when exit_code is -1: "cannot start 'cc': No such file or directory", "killed by signal 9"
  bool ok() const { return exit_code == 0; }
};

// Runs `argv` (argv[0] the program) and waits for it. Its standard output goes to
// `out_path` and its standard error to `err_path` (created or truncated; "" = /dev/null;
// the same path for both = one file, as "> log 2>&1").
ProgramRun run_program(const std::vector<std::string>& argv, const std::string& out_path, const std::string& err_path);

// Runs `argv` and returns what it writes on standard output (standard error discarded),
// at most `max_bytes` of it; "" when it cannot be started.
std::string program_output(const std::vector<std::string>& argv, std::size_t max_bytes = 65536);

// A command as its words, split at blanks (spaces and tabs), as make splits $(CXX):
// "c++ -include x.h" -> {"c++", "-include", "x.h"}. No quoting is interpreted.
std::vector<std::string> command_words(const std::string& command);

// `argv` as one line a reader can paste into sh: each word in single quotes when it holds
// anything but letters, digits and "-_./=+:,@%" (for messages and reports only).
std::string shell_line(const std::vector<std::string>& argv);

}  // namespace dmbd
