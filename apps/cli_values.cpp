#include "cli_values.hpp"

#include <unistd.h>

#include <cctype>
#include <cmath>
#include <filesystem>

#include "dmbd/base/error.hpp"
#include "dmbd/model/robot_folder.hpp"
#include "dmbd/blocks/error.hpp"

namespace dmbd::apps {

namespace b = dmbd::blocks;

double parse_number(const std::string& text, const std::string& option, const b::ParameterMap& params) {
  try {
    return b::Expression::parse(text).evaluate(params);
  } catch (const b::ExpressionError& e) {
    throw InputError(option + " '" + text + "': " + e.what());
  }
}

int parse_count(const std::string& text, const std::string& option) {
  const double v = parse_number(text, option);
  if (v != std::floor(v) || v < 1 || v > 1e7)
    throw InputError(option + " '" + text + "': expected a whole number of samples from 1 to 10^7");
  return static_cast<int>(v);
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out(1);
  for (char c : s) {
    if (c == sep) {
      out.emplace_back();
    } else {
      out.back().push_back(c);
    }
  }
  return out;
}

b::ParameterMap parse_params(const std::vector<std::string>& list) {
  b::ParameterMap params;
  for (const std::string& p : list) {
    const auto eq = p.find('=');
    if (eq == std::string::npos || eq == 0) throw InputError("--param '" + p + "': expected NAME=VALUE");
    const std::string name = p.substr(0, eq);
    for (char c : name)
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_') || std::isdigit(static_cast<unsigned char>(name[0])))
        throw InputError("--param '" + p + "': '" + name + "' is not a valid parameter name");
    if (name == "s" || name == "z") throw InputError("--param '" + p + "': s and z are the transfer-function variables");
    params[name] = parse_number(p.substr(eq + 1), "--param " + name, params);
  }
  return params;
}

void check_output_folder(const std::string& path, const std::string& option) {
  std::error_code ec;
  if (!std::filesystem::is_directory(path, ec))
    throw OutputError(option + " '" + path + "': the folder does not exist");
  if (access(path.c_str(), W_OK) != 0) throw OutputError(option + " '" + path + "': the folder is not writable");
}

void check_output_file(const std::string& path, const std::string& option, const std::string& extension) {
  const std::filesystem::path p(path);
  const std::string dir = p.has_parent_path() ? p.parent_path().string() : ".";
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    throw OutputError(option + " '" + path + "': folder '" + dir + "' does not exist");
  if (access(dir.c_str(), W_OK) != 0) throw OutputError(option + " '" + path + "': folder '" + dir + "' is not writable");
  if (std::filesystem::is_directory(p, ec)) throw OutputError(option + " '" + path + "': a directory is in the way");
  if (!extension.empty() && p.extension() != extension)
    throw OutputError(option + " '" + path + "': expected a file name ending in " + extension);
}

std::string urdf_path(const std::string& urdf, const std::string& robot) {
  if (!urdf.empty() && !robot.empty()) throw InputError("give a URDF file or --robot NAME, not both");
  if (!robot.empty()) {
    try {
      return model::find_robot(robot).urdf;
    } catch (InputError& e) {
      e.prepend("--robot: ");
      throw;
    }
  }
  if (urdf.empty()) throw InputError("give a URDF file or --robot NAME (a robot folder, docs/robot-folder.md)");
  return urdf;
}

}  // namespace dmbd::apps
