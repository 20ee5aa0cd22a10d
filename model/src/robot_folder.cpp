// Robot folders: the search path and robot.yaml (robot_folder.hpp).
#include "dmbd/model/robot_folder.hpp"

#include <cstdlib>
#include <filesystem>

#include "dmbd/base/file.hpp"
#include "dmbd/base/strings.hpp"
#include "dmbd/base/yaml_fields.hpp"
#include "dmbd/base/yaml_reader.hpp"
#include "dmbd/model/error.hpp"

namespace dmbd::model {

namespace fs = std::filesystem;

namespace {

std::string normal(const fs::path& p) { return fs::absolute(p).lexically_normal().string(); }


// A file the folder names: it must exist.
std::string folder_file(const yaml::Fields& f, const YAML::Node& n, const std::string& dir, const std::string& what) {
  const std::string p = normal(fs::path(dir) / f.text(n, what));
  std::error_code ec;
  if (!fs::is_regular_file(p, ec)) f.fail(n, what + ": file '" + p + "' does not exist");
  return p;
}

void read_robot_yaml(yaml::Reader& rd, const YAML::Node& root, RobotFolder& r) {
  const yaml::Fields f(rd);
  f.keys(root, "robot.yaml", {"format", "name", "description", "urdf", "actuators", "controllers"});
  const long long format = f.integer(f.required(root, "format", "robot.yaml"), "format", 1, 1000);
  if (format != 1) f.fail(root["format"], "format: version " + std::to_string(format) + " is not known (this dmbd reads format 1)");
  f.optional(root, "name", [&](const YAML::Node& n) { r.display_name = f.text(n, "name"); });
  r.urdf = folder_file(f, f.required(root, "urdf", "robot.yaml"), r.dir, "urdf");
  f.optional(root, "actuators", [&](const YAML::Node& n) { r.actuators = folder_file(f, n, r.dir, "actuators"); });
  f.optional(root, "controllers", [&](const YAML::Node& n) {
    if (!n.IsMap()) f.fail(n, "controllers: expected a map of controller type: options");
    r.controllers = n;
  });
}

}  // namespace

std::vector<std::string> robot_search_path(const std::vector<std::string>& first) {
  std::vector<std::string> dirs = first;
  if (const char* env = std::getenv("DMBD_ROBOT_PATH"); env != nullptr) {
    std::string s(env), part;
    for (char c : s + ":") {
      if (c != ':') {
        part += c;
      } else if (!part.empty()) {
        dirs.push_back(part);
        part.clear();
      }
    }
  }
  dirs.emplace_back(DMBD_ROBOTS_INSTALL_DIR);
  dirs.emplace_back(DMBD_ROBOTS_SOURCE_DIR);
  return dirs;
}

RobotFolder load_robot_folder(const std::string& dir) {
  RobotFolder r;
  r.dir = normal(dir);
  r.name = fs::path(r.dir).filename().string();
  r.display_name = r.name;
  r.file = r.dir + "/robot.yaml";
  std::string bytes;
  if (const auto reason = try_read_text_file(r.file, bytes)) throw ModelError(r.file + ": cannot read the robot file: " + *reason);
  yaml::Reader rd(r.file);
  rd.guard([&] { read_robot_yaml(rd, rd.parse(bytes), r); });
  if (rd.failed()) throw ModelError(join_plain(rd.diagnostics()));
  return r;
}

RobotFolder find_robot(const std::string& name, const std::vector<std::string>& first) {
  const std::vector<std::string> dirs = robot_search_path(first);
  if (name.empty() || name.find('/') != std::string::npos || name == "." || name == "..")
    throw ModelError("robot '" + name + "': a robot's name is a folder's name (no '/')");
  for (const auto& d : dirs) {
    std::error_code ec;
    if (fs::is_regular_file(fs::path(d) / name / "robot.yaml", ec)) return load_robot_folder((fs::path(d) / name).string());
  }
  throw ModelError("robot '" + name + "' not found (searched: " + join(dirs) + "; a robot is a folder NAME/ with a robot.yaml)");
}

bool is_builtin_robot_dir(const std::string& dir) {
  const fs::path d = normal(dir);
  for (const char* root : {DMBD_ROBOTS_INSTALL_DIR, DMBD_ROBOTS_SOURCE_DIR})
    if (d.parent_path() == fs::path(normal(root))) return true;
  return false;
}

}  // namespace dmbd::model
