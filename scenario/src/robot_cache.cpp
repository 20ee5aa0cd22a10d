// A URDF read once per process (robot_cache.hpp).
#include "robot_cache.hpp"

#include <filesystem>
#include <map>
#include <mutex>

namespace dmbd::scenario::detail {

namespace {

// The path with the file's size and modification time ("" parts when they cannot be read:
// loading then reports why).
std::string key_of(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto size = fs::file_size(path, ec);
  const auto time = fs::last_write_time(path, ec);
  return path + "\n" + std::to_string(ec ? 0 : size) + "\n" + std::to_string(ec ? 0 : time.time_since_epoch().count());
}

}  // namespace

std::shared_ptr<const model::RobotDescription> cached_urdf(const std::string& path) {
  static std::mutex mutex;
  static std::map<std::string, std::shared_ptr<const model::RobotDescription>> cache;
  const std::string key = key_of(path);
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (const auto it = cache.find(key); it != cache.end()) return it->second;
  }
  auto robot = std::make_shared<const model::RobotDescription>(model::load_urdf(path));
  const std::lock_guard<std::mutex> lock(mutex);
  return cache.emplace(key, std::move(robot)).first->second;
}

}  // namespace dmbd::scenario::detail
