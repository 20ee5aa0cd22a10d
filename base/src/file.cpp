#include "dmbd/base/file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "dmbd/base/error.hpp"
#include "dmbd/base/temporaries.hpp"
#include "dmbd/base/text.hpp"

namespace dmbd {

namespace {

[[noreturn]] void fail(const std::string& path, int err) {
  throw OutputError("cannot write '" + path + "': " + std::strerror(err));
}

}  // namespace

void write_file_atomic(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw OutputError("cannot write '" + path + "': a directory is in the way");
  const std::string tmp = path + ".tmp";
  const TemporaryPath removed_on_signal(tmp);
  std::FILE* file = std::fopen(tmp.c_str(), "wb");
  if (file == nullptr) fail(path, errno);
  const bool written = std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
  const int write_errno = errno;
  const bool closed = std::fclose(file) == 0;
  if (!written || !closed) {
    const int err = !written ? write_errno : errno;
    std::remove(tmp.c_str());
    fail(path, err);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    std::remove(tmp.c_str());
    fail(path, err);
  }
}

void write_file_atomic(const std::string& path, const std::string& text) {
  write_file_atomic(path, std::vector<unsigned char>(text.begin(), text.end()));
}

namespace {

// Reads `path` in chunks into `bytes`, stopping past `limit` and, with `text`, at the
// first byte that is not text (then `bytes` ends with it); the reason it failed, if it did.
std::optional<std::string> read_bounded(const std::string& path, std::string& bytes, std::size_t limit, bool text) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return std::string("it is a directory");
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) return std::string(std::strerror(errno));
  bytes.clear();
  TextScan scan;
  std::optional<std::string> reason;
  char buffer[65536];
  std::size_t n = 0;
  while (!reason && !scan.bad && (n = std::fread(buffer, 1, sizeof buffer, file)) > 0) {
    bytes.append(buffer, n);
    if (bytes.size() > limit) reason = "larger than the limit of " + std::to_string(limit) + " bytes";
    else if (text && scan_text(bytes, false, scan)) bytes.resize(*scan.bad + 1);
  }
  const int err = !reason && !scan.bad && std::ferror(file) ? errno : 0;
  std::fclose(file);
  if (err != 0) return std::string(std::strerror(err));
  return reason;
}

}  // namespace

std::optional<std::string> try_read_file(const std::string& path, std::string& bytes, std::size_t limit) {
  return read_bounded(path, bytes, limit, false);
}

std::optional<std::string> try_read_text_file(const std::string& path, std::string& text, std::size_t limit) {
  return read_bounded(path, text, limit, true);
}

std::string read_file(const std::string& path, std::size_t limit) {
  std::string bytes;
  if (const auto reason = try_read_file(path, bytes, limit)) throw InputError(path + ": cannot read: " + *reason);
  return bytes;
}

std::string read_text_file(const std::string& path, std::size_t limit) {
  std::string text;
  if (const auto reason = try_read_text_file(path, text, limit)) throw InputError(path + ": cannot read: " + *reason);
  if (const auto d = not_text(text, path)) throw InputError(d->where.str() + ": " + d->message);
  return text;
}

}  // namespace dmbd
