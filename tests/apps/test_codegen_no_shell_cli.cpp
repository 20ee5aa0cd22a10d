// Issue 28 row 16: `dmbd codegen --verify` starts the compiler and the verification
// harness without a shell (an argument vector), so an output folder named like a shell
// command ("gen'; touch PWNED2; echo '") is only a name: the code is verified in it and
// no command in the name runs. C++ and C alike.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "cli_support.hpp"

namespace {

namespace fs = std::filesystem;
using dmbd::cli_testing::run_dmbd;

class CodegenNoShell : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dmbd_codegen_no_shell_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_P(CodegenNoShell, AnOutputFolderNamedLikeACommandIsOnlyAName) {
  const std::string out = "gen'; touch PWNED2; echo '$(touch PWNED3)`touch PWNED4`";
  fs::create_directories(dir_ / out);
  const std::string diagram = std::string(DMBD_SOURCE_DIR) + "/examples/diagrams/dob_controller.yaml";
  const auto r = run_dmbd({"codegen", diagram, "--rate", "2000", "--language", GetParam(), "--out", out, "--verify"}, dir_, dir_);
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("max |generated - interpreter| = 0 "), std::string::npos) << r.out;
  for (const char* pwned : {"PWNED2", "PWNED3", "PWNED4"}) {
    EXPECT_FALSE(fs::exists(dir_ / pwned)) << pwned;
    EXPECT_FALSE(fs::exists(dir_ / out / pwned)) << pwned;
  }
  EXPECT_TRUE(fs::exists(dir_ / out / (std::string(GetParam()) == "c" ? "dob_controller.c" : "dob_controller.hpp")));
}

INSTANTIATE_TEST_SUITE_P(Language, CodegenNoShell, ::testing::Values("cpp", "c"),
                         [](const ::testing::TestParamInfo<const char*>& i) { return std::string(i.param); });

}  // namespace
