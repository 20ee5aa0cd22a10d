// Programs started by argument vector (base/process.hpp, issue 28 row 16): every word
// reaches the program as it is spelt, none is read by a shell; output goes where asked.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "dmbd/base/process.hpp"

namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

TEST(Process, WordsReachTheProgramAsSpeltAndNoShellReadsThem) {
  const fs::path dir = fs::temp_directory_path() / ("dmbd_process_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string hostile = "a'; touch " + (dir / "PWNED").string() + "; echo '$(id)`id` \"b\"";
  const fs::path out = dir / "out file'.txt";
  const dmbd::ProgramRun r = dmbd::run_program({"printf", "%s|", hostile, "second word"}, out.string(), out.string());
  EXPECT_TRUE(r.ok()) << r.why;
  EXPECT_EQ(slurp(out), hostile + "|second word|");
  EXPECT_FALSE(fs::exists(dir / "PWNED"));
  fs::remove_all(dir);
}

TEST(Process, ExitStatusAndAProgramThatCannotStart) {
  EXPECT_EQ(dmbd::run_program({"sh", "-c", "exit 3"}, "", "").exit_code, 3);
  const dmbd::ProgramRun missing = dmbd::run_program({"/nonexistent/dmbd-cc"}, "", "");
  EXPECT_EQ(missing.exit_code, -1);
  EXPECT_EQ(missing.why, "cannot start '/nonexistent/dmbd-cc': No such file or directory");
}

TEST(Process, OutputCapturedAndBounded) {
  EXPECT_EQ(dmbd::program_output({"printf", "one\ntwo"}), "one\ntwo");
  EXPECT_EQ(dmbd::program_output({"printf", "abcdef"}, 3), "abc");
  EXPECT_EQ(dmbd::program_output({"/nonexistent/dmbd-cc", "--version"}), "");
}

TEST(Process, CommandWordsAndShellLine) {
  EXPECT_EQ(dmbd::command_words("  c++\t-include  x.h "), (std::vector<std::string>{"c++", "-include", "x.h"}));
  EXPECT_EQ(dmbd::shell_line({"cc", "-o", "a b", "it's"}), "cc -o 'a b' 'it'\\''s'");
}

}  // namespace
