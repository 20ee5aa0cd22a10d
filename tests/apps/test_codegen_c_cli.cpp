// `dmbd codegen --language c|cpp` (issue 16, item 4): C writes <name>.h and <name>.c (and
// no .hpp), `--verify` compiles them as C99 and finds them bit-identical to the
// interpreter, the default stays C++; a bad value, or an output in the way, is one line
// on stderr and exit 2, with nothing written.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_support.hpp"

namespace {

namespace fs = std::filesystem;
using dmbd::cli_testing::run_dmbd;
using dmbd::cli_testing::slurp;

class CodegenLanguage : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dmbd_codegen_language_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::vector<std::string> lag(const std::vector<std::string>& more) const {
    std::vector<std::string> a{"codegen", "--tf", "1/(s/(2*pi*60) + 1)", "--rate", "1000", "--name", "lag", "--out", dir_.string()};
    a.insert(a.end(), more.begin(), more.end());
    return a;
  }
  fs::path dir_;
};

TEST_F(CodegenLanguage, CWritesHeaderAndSourceAndVerifiesThemAsC99) {
  const auto r = run_dmbd(lag({"--language", "c", "--verify"}), dir_);
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "lag.h"));
  EXPECT_TRUE(fs::exists(dir_ / "lag.c"));
  EXPECT_FALSE(fs::exists(dir_ / "lag.hpp"));
  EXPECT_NE(r.out.find("wrote " + (dir_ / "lag.h").string() + " and " + (dir_ / "lag.c").string()), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("max |generated - interpreter| = 0 "), std::string::npos) << r.out;
  EXPECT_NE(slurp(dir_ / "lag.h").find("void lag_step(lag_state* self, const lag_input* u, lag_output* y);"), std::string::npos);
  const auto report = nlohmann::json::parse(slurp(dir_ / "lag.report.json"));
  EXPECT_EQ(report["language"], "c");
  EXPECT_EQ(report["verification"]["compiler"].get<std::string>().rfind("cc -std=c99 ", 0), 0u) << report["verification"]["compiler"];
  EXPECT_NE(slurp(dir_ / "lag.report.md").find("C99 code"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir_ / ".verify_lag"));  // the harness is removed
}

TEST_F(CodegenLanguage, FixedPointCVerifies) {
  const std::string diagram = std::string(DMBD_SOURCE_DIR) + "/examples/diagrams/force_pd_controller.yaml";
  const auto r = run_dmbd({"codegen", diagram, "--rate", "2000", "--scalar", "fixed", "--word", "16", "--language", "c",
                           "--out", dir_.string(), "--verify"},
                          dir_);
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("max |generated - interpreter| = 0 "), std::string::npos) << r.out;
  EXPECT_NE(slurp(dir_ / "force_pd_controller.h").find("uint32_t force_pd_controller_saturations("), std::string::npos);
}

TEST_F(CodegenLanguage, CppIsTheDefault) {
  for (const std::vector<std::string>& more : {std::vector<std::string>{}, std::vector<std::string>{"--language", "cpp"}}) {
    const auto r = run_dmbd(lag(more), dir_);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir_ / "lag.hpp"));
    EXPECT_FALSE(fs::exists(dir_ / "lag.h"));
    EXPECT_FALSE(fs::exists(dir_ / "lag.c"));
    EXPECT_EQ(nlohmann::json::parse(slurp(dir_ / "lag.report.json"))["language"], "cpp");
    fs::remove(dir_ / "lag.hpp");
  }
}

TEST_F(CodegenLanguage, BadValuesAreOneLineErrorsAndWriteNothing) {
  auto expect_one_line_error = [&](const std::vector<std::string>& args, const std::string& needle) {
    const auto r = run_dmbd(args, dir_);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
    for (const char* f : {"lag.h", "lag.c", "lag.hpp", "lag.report.json", "lag.report.md"})
      EXPECT_FALSE(fs::is_regular_file(dir_ / f)) << f;
  };
  for (const char* bad : {"fortran", "C", "c99", ""})
    expect_one_line_error(lag({"--language", bad}), "--language '" + std::string(bad) + "': expected c or cpp");
  // The source cannot be written (a directory in its way): neither is the header.
  fs::create_directories(dir_ / "lag.c");
  expect_one_line_error(lag({"--language", "c"}), "lag.c");
}

}  // namespace
