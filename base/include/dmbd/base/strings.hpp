#pragma once
// Small helpers on names for messages: a list joined, and the closest of some names.
#include <string>
#include <vector>

namespace dmbd {

// "a, b, c" (the separator between each two).
std::string join(const std::vector<std::string>& names, const std::string& separator = ", ");

// The Levenshtein distance between two names (insertions, deletions, substitutions).
std::size_t edit_distance(const std::string& a, const std::string& b);

// The name among `candidates` closest to `name` by edit_distance (the first of equals;
// "" when there is none).
std::string closest_name(const std::string& name, const std::vector<std::string>& candidates);

}  // namespace dmbd
