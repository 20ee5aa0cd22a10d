#pragma once
// Shared by the viz tests that write files and open them in a browser.
#include <stdlib.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string>

namespace dmbd::viz::test {

// A fresh directory under the system temp dir, removed with everything in it.
class TempDir {
 public:
  explicit TempDir(const std::string& prefix = "dmbd_test") {
    std::string tmpl = (std::filesystem::temp_directory_path() / (prefix + "_XXXXXX")).string();
    if (mkdtemp(tmpl.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

// The Chromium binary on PATH ("" when none): scripts/setup installs Debian's.
inline std::string find_chromium() {
  const char* env_path = std::getenv("PATH");
  std::stringstream dirs(env_path ? env_path : "/usr/bin:/bin");
  std::string d;
  while (std::getline(dirs, d, ':'))
    for (const char* name : {"chromium", "chromium-browser"})
      if (!d.empty() && std::filesystem::exists(std::filesystem::path(d) / name))
        return (std::filesystem::path(d) / name).string();
  return {};
}

}  // namespace dmbd::viz::test
