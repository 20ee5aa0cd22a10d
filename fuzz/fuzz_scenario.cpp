// Fuzz target: the scenario loader (sim/src/scenario_load.cpp, load_scenario) on a temporary
// file. The file sits in <tmp>/scenarios/ beside <tmp>/diagrams -> examples/diagrams,
// so the examples' relative paths (../diagrams/x.yaml) resolve as they do in the repo.
// Any exception other than dmbd::InputError, a crash or a sanitizer report is a bug.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "dmbd/blocks/error.hpp"
#include "dmbd/scenario/scenario.hpp"

namespace fs = std::filesystem;

namespace {

fs::path g_root;

void remove_root() {
  std::error_code ec;
  if (!g_root.empty()) fs::remove_all(g_root, ec);
}

const std::string& input_path() {
  static const std::string path = [] {
    std::string tmpl = (fs::temp_directory_path() / "dmbd-fuzz-scenario-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) std::abort();
    g_root = tmpl;
    std::atexit(remove_root);
    fs::create_directories(g_root / "scenarios");
    fs::create_directory_symlink(fs::path(DMBD_SOURCE_DIR) / "examples" / "diagrams", g_root / "diagrams");
    return (g_root / "scenarios" / "input.yaml").string();
  }();
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& path = input_path();
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    (void)dmbd::scenario::load_scenario(path);
  } catch (const dmbd::InputError&) {
  }
  return 0;
}
