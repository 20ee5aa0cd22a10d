// Reading a user's file (try_read_file, read_file) and telling text from binary
// (not_text): the system's reason for a file that cannot be read, and the place of the
// first byte that is not text, never the byte itself.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "dmbd/base/error.hpp"
#include "dmbd/base/file.hpp"
#include "dmbd/base/text.hpp"

namespace {

namespace fs = std::filesystem;

class Files : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dmbd_test_file_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& bytes) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << bytes;
    return p.string();
  }
  fs::path dir_;
};

bool printable(const std::string& s) {
  return std::all_of(s.begin(), s.end(), [](char c) { return static_cast<unsigned char>(c) >= 0x20 && c != 0x7f; });
}

TEST_F(Files, ReadsTheWholeFile) {
  const std::string bytes = std::string("a: 1\n") + std::string(100000, 'x');
  std::string got;
  EXPECT_FALSE(dmbd::try_read_file(write("f.yaml", bytes), got));
  EXPECT_EQ(got, bytes);
}

TEST_F(Files, GivesTheSystemsReason) {
  std::string got;
  EXPECT_EQ(dmbd::try_read_file((dir_ / "missing.yaml").string(), got).value_or(""), "No such file or directory");
  EXPECT_EQ(dmbd::try_read_file(dir_.string(), got).value_or(""), "it is a directory");
  try {
    (void)dmbd::read_file((dir_ / "missing.yaml").string());
    ADD_FAILURE() << "no error";
  } catch (const dmbd::InputError& e) {
    EXPECT_EQ(std::string(e.what()), (dir_ / "missing.yaml").string() + ": cannot read: No such file or directory");
  }
}

TEST(NotText, TextPassesWhateverItsScript) {
  EXPECT_FALSE(dmbd::not_text("name: Gr\xc3\xb6\xc3\x9f" "e\r\n\tk: \xe2\x84\xa6 \xf0\x9f\x99\x82\n", "f"));
  EXPECT_FALSE(dmbd::not_text("", "f"));
}

TEST(NotText, AControlByteIsNamedByPlaceNotPrinted) {
  const auto d = dmbd::not_text("a: 1\nbb: \x01\x02\n", "f.yaml");
  ASSERT_TRUE(d);
  EXPECT_EQ(d->where.str(), "f.yaml:2:5");
  EXPECT_NE(d->message.find("the file is not text"), std::string::npos) << d->message;
  EXPECT_NE(d->message.find("byte 10 is 0x01"), std::string::npos) << d->message;
  EXPECT_TRUE(printable(d->message)) << d->message;
}

TEST(NotText, BytesThatAreNotUtf8AreNamed) {
  for (const std::string bad : {"\xff", "\xc3", "\xc0\x80", "\xed\xa0\x80", "\xc2\x85", "\x7f"}) {
    const auto d = dmbd::not_text("k: v" + bad + "\n", "f");
    ASSERT_TRUE(d) << "accepted: " << bad.size() << " bytes";
    EXPECT_EQ(d->where.column, 5);
    EXPECT_TRUE(printable(d->message)) << d->message;
  }
}

}  // namespace

// Issue 28 row 8: reading is bounded. A device that never ends stops at its first byte
// that is not text (/dev/zero, /dev/urandom: at once), a text file larger than the limit
// stops one chunk past it, and a pipe or /dev/stdin is read like a file.
namespace bounded {

TEST_F(Files, AnEndlessDeviceStopsAtItsFirstByteThatIsNotText) {
  std::string text;
  EXPECT_FALSE(dmbd::try_read_text_file("/dev/zero", text).has_value());
  ASSERT_EQ(text, std::string(1, '\0'));  // read up to the first byte that is not text, for not_text to name
  const auto d = dmbd::not_text(text, "/dev/zero");
  ASSERT_TRUE(d.has_value());
  EXPECT_EQ(d->where.str() + ": " + d->message,
            "/dev/zero:1:1: the file is not text: byte 1 is 0x00, a control character (expected a UTF-8 text file)");
  try {
    (void)dmbd::read_text_file("/dev/urandom");
    FAIL() << "no error";
  } catch (const dmbd::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/urandom:1:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("the file is not text: byte "), std::string::npos) << e.what();
  }
}

TEST_F(Files, AFileLargerThanTheLimitIsRefused) {
  const std::string path = write("big.yaml", std::string(200000, 'a'));
  std::string text;
  const auto reason = dmbd::try_read_text_file(path, text, 100000);
  ASSERT_TRUE(reason.has_value());
  EXPECT_EQ(*reason, "larger than the limit of 100000 bytes");
  EXPECT_LE(text.size(), 100000u + 65536u);  // one chunk past the limit at most
  EXPECT_FALSE(dmbd::try_read_file(path, text, 200000).has_value());
  EXPECT_EQ(text.size(), 200000u);
  EXPECT_THROW((void)dmbd::read_file("/dev/zero", 1 << 20), dmbd::InputError);  // binary: only the limit
}

TEST_F(Files, UTF8CutBetweenChunksIsText) {
  // A three-byte character across the 64 KiB chunk boundary, then a control byte.
  std::string bytes(65535, 'a');
  bytes += "\xe2\x82\xac";
  bytes += "b";
  const std::string path = write("utf8.txt", bytes);
  std::string text;
  EXPECT_FALSE(dmbd::try_read_text_file(path, text).has_value());
  EXPECT_EQ(text, bytes);
  EXPECT_FALSE(dmbd::not_text(text, path).has_value());
  const std::string bad = write("bad.txt", bytes + std::string(100000, 'c') + '\x01' + std::string(100000, 'd'));
  EXPECT_FALSE(dmbd::try_read_text_file(bad, text).has_value());
  EXPECT_EQ(text.size(), bytes.size() + 100001);  // stopped at the control byte
}

TEST_F(Files, APipeIsReadLikeAFile) {
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  const std::string yaml = "blocks: {}\n";
  ASSERT_EQ(::write(fds[1], yaml.data(), yaml.size()), static_cast<ssize_t>(yaml.size()));
  ::close(fds[1]);
  EXPECT_EQ(dmbd::read_text_file("/dev/fd/" + std::to_string(fds[0])), yaml);
  ::close(fds[0]);
}

}  // namespace bounded
