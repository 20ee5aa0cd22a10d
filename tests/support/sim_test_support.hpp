#pragma once
// Shared by the co-simulation and scenario tests: temporary folders and text files.
#include <fstream>
#include <sstream>
#include <string>

#include "../viz/viz_test_support.hpp"

namespace dmbd::sim::test {

// A fresh folder under the system temp dir, removed with everything in it (the viz
// tests' own), with file(name) for a path inside it.
struct TempDir : viz::test::TempDir {
  TempDir() : viz::test::TempDir("dmbd_test_sim") {}
  std::string file(const std::string& name) const { return *this / name; }
};

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
}

inline std::string read_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

}  // namespace dmbd::sim::test
