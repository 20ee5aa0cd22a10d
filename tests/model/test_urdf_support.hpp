#pragma once
// Helpers of the URDF tests: fixture paths, file text, the line of a marker in a
// fixture (so expected line numbers come from the file, not from the test), the sum
// of the <mass> values found by a regular expression (independent of the loader),
// and structural checks every loaded robot must pass.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "dmbd/model/error.hpp"
#include "dmbd/model/robot_description.hpp"

namespace dmbd::model::test {

inline std::string urdf_data(const std::string& rel) { return std::string(DMBD_MODEL_TEST_DATA) + "/urdf/" + rel; }

inline std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// 1-based line of the first occurrence of `needle` in `text` (0 when absent).
inline int line_of(const std::string& text, const std::string& needle) {
  const auto at = text.find(needle);
  if (at == std::string::npos) return 0;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

// Sum of every <mass value="..."> in the text, by a regular expression.
inline double sum_of_mass_elements(const std::string& text, int* count = nullptr) {
  static const std::regex re(R"re(<mass\s+value\s*=\s*"([^"]*)")re");
  double sum = 0;
  int n = 0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator(); ++it) {
    sum += std::stod((*it)[1].str());
    ++n;
  }
  if (count) *count = n;
  return sum;
}

// links[0] is the root (no parent joint); every other link has exactly one parent
// joint; each joint's parent link comes before its child, and the joints are in
// order (a joint's parent link is the root or the child of an earlier joint).
inline void expect_tree_order(const RobotDescription& r) {
  ASSERT_FALSE(r.links.empty());
  EXPECT_EQ(r.parent_joint_of_link(0), -1);
  EXPECT_EQ(r.joints.size() + 1, r.links.size());
  std::map<std::string, int> seen_child;
  for (std::size_t j = 0; j < r.joints.size(); ++j) {
    const int p = r.link_index(r.joints[j].parent), c = r.link_index(r.joints[j].child);
    ASSERT_GE(p, 0) << r.joints[j].name;
    ASSERT_GE(c, 0) << r.joints[j].name;
    EXPECT_LT(p, c) << r.joints[j].name;
    EXPECT_TRUE(seen_child.emplace(r.joints[j].child, static_cast<int>(j)).second) << r.joints[j].child;
    if (p != 0) {
      const int pj = r.parent_joint_of_link(p);
      EXPECT_GE(pj, 0);
      EXPECT_LT(pj, static_cast<int>(j)) << r.joints[j].name << " comes before the joint of its parent link";
    }
  }
  for (std::size_t l = 1; l < r.links.size(); ++l) EXPECT_GE(r.parent_joint_of_link(static_cast<int>(l)), 0);
}

// The ModelError thrown by `f`, with every fragment in its one-line message.
template <class F>
std::string expect_model_error(F&& f, const std::vector<std::string>& fragments) {
  try {
    f();
  } catch (const ModelError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    for (const auto& fr : fragments) EXPECT_NE(msg.find(fr), std::string::npos) << "missing '" << fr << "' in: " << msg;
    return msg;
  }
  ADD_FAILURE() << "no ModelError";
  return {};
}

}  // namespace dmbd::model::test
