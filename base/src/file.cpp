#include "dmbd/base/file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "dmbd/base/error.hpp"

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

std::optional<std::string> try_read_file(const std::string& path, std::string& bytes) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return std::string("it is a directory");
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) return std::string(std::strerror(errno));
  bytes.clear();
  char buffer[65536];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, file)) > 0) bytes.append(buffer, n);
  const int err = std::ferror(file) ? errno : 0;
  std::fclose(file);
  if (err != 0) return std::string(std::strerror(err));
  return std::nullopt;
}

std::string read_file(const std::string& path) {
  std::string bytes;
  if (const auto reason = try_read_file(path, bytes)) throw InputError(path + ": cannot read: " + *reason);
  return bytes;
}

}  // namespace dmbd
