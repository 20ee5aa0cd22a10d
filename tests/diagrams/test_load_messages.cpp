// Messages of diagram loading that name the real problem (issue 13, item 4): one line
// for one wrong parameter, tabs named as tabs, a binary file named as not text (its
// bytes never printed), a directory as a directory, a missing file with the system's
// reason.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "dmbd/diagrams/diagram.hpp"

namespace {

using namespace dmbd::diagrams;  // NOLINT
namespace fs = std::filesystem;

class Messages : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dmbd_test_messages_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& bytes) {
    std::ofstream(dir_ / name, std::ios::binary) << bytes;
    return (dir_ / name).string();
  }
  // The diagnostics of loading `path` (none if it loads).
  static std::vector<Diagnostic> diagnostics(const std::string& path) {
    try {
      (void)Diagram::load(path);
    } catch (const DiagramError& e) {
      return e.diagnostics();
    }
    return {};
  }
  fs::path dir_;
};

const std::string kUsesKpp =
    "name: pd\n"
    "parameters:\n"
    "  Kpp: 1e\n"
    "  K2: 2*Kpp\n"
    "inputs: {u: {}}\n"
    "outputs: {y: {}}\n"
    "blocks:\n"
    "  k: {type: gain, k: Kpp}\n"
    "  g: {type: tf, expr: K2/(s+1)}\n"
    "  c: {type: pd, P: Kpp, D: 0}\n"
    "connections: [u -> k, k -> g, g -> c, c -> y]\n";

TEST_F(Messages, AWrongParameterIsOneLineNotOnePerUse) {
  const std::string path = write("kpp.yaml", kUsesKpp);
  const auto d = diagnostics(path);
  ASSERT_EQ(d.size(), 1u) << (d.size() > 1 ? d[1].str() : "");
  EXPECT_EQ(d[0].where.str(), path + ":3:8");
  EXPECT_NE(d[0].message.find("parameter 'Kpp': malformed number '1e'"), std::string::npos) << d[0].message;
}

TEST_F(Messages, TabsAreNamedAtTheirLine) {
  const std::string path = write("tabs.yaml", "name: t\nparameters:\n\tK: 1\ninputs: {u: {}}\n");
  const auto d = diagnostics(path);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].where.str(), path + ":3:1");
  EXPECT_NE(d[0].message.find("tabs are not allowed"), std::string::npos) << d[0].message;
}

TEST_F(Messages, ABinaryFileIsNotTextAndItsBytesAreNotPrinted) {
  const std::string path = write("bin.yaml", std::string("\x7f" "ELF\x02\x01\x01\0\0\0", 10));
  const auto d = diagnostics(path);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].where.str(), path + ":1:1");
  EXPECT_NE(d[0].message.find("the file is not text"), std::string::npos) << d[0].message;
  const std::string all = d[0].str();
  EXPECT_TRUE(std::all_of(all.begin(), all.end(), [](char c) { return static_cast<unsigned char>(c) >= 0x20 && c != 0x7f; }));
}

TEST_F(Messages, ADirectoryAndAMissingFileSayWhy) {
  auto d = diagnostics(dir_.string());
  ASSERT_EQ(d.size(), 1u);
  EXPECT_NE(d[0].message.find("it is a directory"), std::string::npos) << d[0].message;
  EXPECT_EQ(d[0].message.find("expected a map"), std::string::npos) << d[0].message;
  d = diagnostics((dir_ / "none.yaml").string());
  ASSERT_EQ(d.size(), 1u);
  EXPECT_NE(d[0].message.find("cannot read diagram file"), std::string::npos) << d[0].message;
  EXPECT_NE(d[0].message.find("No such file or directory"), std::string::npos) << d[0].message;
}

TEST_F(Messages, RepeatedKeysAreReported) {
  const std::string path = write("twice.yaml", "name: t\nname: u\ninputs: {u: {}}\noutputs: {y: {}}\nblocks: {}\nconnections: [u -> y]\n");
  const auto d = diagnostics(path);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].where.str(), path + ":2:1");
  EXPECT_NE(d[0].message.find("'name' is given twice"), std::string::npos) << d[0].message;
}

}  // namespace
