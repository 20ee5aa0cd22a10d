#pragma once
// Running the built `dmbd` binary from CLI tests: shell quoting, capture of exit code,
// stdout and stderr. DMBD_EXE is set by tests/apps/CMakeLists.txt.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace dmbd::cli_testing {

namespace fs = std::filesystem;

struct Result {
  int code = -1;
  std::string out, err;
};

inline std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

inline std::string quote(const std::string& a) {
  std::string q = "'";
  for (char c : a) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// A CSV line's cells (no quoting: dmbd's logs have none) and back.
inline std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells(1);
  for (char c : line) {
    if (c == ',') cells.emplace_back();
    else cells.back() += c;
  }
  return cells;
}

inline std::string join(const std::vector<std::string>& cells) {
  std::string line;
  for (std::size_t k = 0; k < cells.size(); ++k) line += (k ? "," : "") + cells[k];
  return line;
}

// Runs dmbd with `args` (in `cwd` when given), stdout and stderr captured through files
// in `scratch`, which are removed again.
inline Result run_dmbd(const std::vector<std::string>& args, const fs::path& scratch, const fs::path& cwd = {}) {
  std::string cmd = cwd.empty() ? std::string() : "cd " + quote(cwd.string()) + " && ";
  cmd += quote(DMBD_EXE);
  for (const auto& a : args) cmd += " " + quote(a);
  cmd += " >" + quote((scratch / "stdout").string()) + " 2>" + quote((scratch / "stderr").string()) + " </dev/null";
  const int status = std::system(cmd.c_str());
  Result r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(scratch / "stdout");
  r.err = slurp(scratch / "stderr");
  fs::remove(scratch / "stdout");
  fs::remove(scratch / "stderr");
  return r;
}

}  // namespace dmbd::cli_testing
