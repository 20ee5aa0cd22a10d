// Fuzz target: a sweep's part read back (scenario::read_part: part.json and log.bin, as
// `dmbd sweep collect` and the parent of `dmbd simulate --jobs` read them), then the
// experiment evaluated on the run it gave (as collect does). The scenario is
// examples/scenarios/position_controllers.yaml, loaded once; the part is of its variant
// 'encoder'. The input is part.json, a NUL byte, then log.bin (no NUL: all of it is
// part.json and log.bin is empty), written to a temporary folder. Any exception other than
// dmbd::InputError, a crash or a sanitizer report is a bug.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "dmbd/base/error.hpp"
#include "dmbd/scenario/evaluate.hpp"
#include "dmbd/scenario/run_parts.hpp"
#include "dmbd/scenario/scenario.hpp"

namespace fs = std::filesystem;

namespace {

fs::path g_dir;

void remove_dir() {
  std::error_code ec;
  if (!g_dir.empty()) fs::remove_all(g_dir, ec);
}

const std::string& part_dir() {
  static const std::string dir = [] {
    std::string tmpl = (fs::temp_directory_path() / "dmbd-fuzz-sweep-part-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) std::abort();
    g_dir = tmpl;
    std::atexit(remove_dir);
    return tmpl;
  }();
  return dir;
}

const dmbd::scenario::Scenario& scenario() {
  static const dmbd::scenario::Scenario s =
      dmbd::scenario::load_scenario(std::string(DMBD_SOURCE_DIR) + "/examples/scenarios/position_controllers.yaml");
  return s;
}

void write(const fs::path& p, const uint8_t* data, size_t size) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const dmbd::scenario::Scenario& s = scenario();
  const fs::path dir = part_dir();
  const auto* nul = static_cast<const uint8_t*>(std::memchr(data, 0, size));
  const size_t json = nul ? static_cast<size_t>(nul - data) : size;
  write(dir / "part.json", data, json);
  write(dir / "log.bin", data + json + (nul ? 1 : 0), nul ? size - json - 1 : 0);
  try {
    const dmbd::sim::VariantResult r = dmbd::scenario::read_part(s, s.variants.front(), dir.string());
    (void)dmbd::scenario::evaluate_experiment(s, {r});
  } catch (const dmbd::InputError&) {
  }
  return 0;
}
