#pragma once
// Values given on the command line: numbers (any constant expression), counts, lists,
// --param overrides, output files. Each error names the option and the text given.
#include <string>
#include <vector>

#include "dmbd/blocks/expression.hpp"

namespace dmbd::apps {

// Any constant expression (`1e-3`, `2*pi*60`), which may use `params`.
double parse_number(const std::string& text, const std::string& option, const blocks::ParameterMap& params = {});
// A whole number from 1 to 10^7.
int parse_count(const std::string& text, const std::string& option);
// "a,b,,c" -> {"a", "b", "", "c"}.
std::vector<std::string> split(const std::string& s, char sep);
// --param NAME=VALUE, in order: each VALUE may use the parameters before it.
blocks::ParameterMap parse_params(const std::vector<std::string>& list);
// An output file the command will write, checked before any work: `option 'PATH': ...`
// when its folder is missing or not writable, a directory stands at the path, or its
// name does not end in `extension` (when given, e.g. ".png"). Throws OutputError.
void check_output_file(const std::string& path, const std::string& option, const std::string& extension = "");
// An output folder that must exist and be writable. Throws OutputError.
void check_output_folder(const std::string& path, const std::string& option);
// The URDF a model command reads: the file given, else robot NAME's (--robot, found on
// the robot search path). InputError when both or neither are given, or the robot is
// not found.
std::string urdf_path(const std::string& urdf, const std::string& robot);

}  // namespace dmbd::apps
