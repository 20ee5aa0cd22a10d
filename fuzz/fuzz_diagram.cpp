// Fuzz target: the diagram loader (diagrams/src/load.cpp) on YAML text. The text is
// named as a file in examples/diagrams/, so a subsystem may name a real diagram there.
// Any exception other than dmbd::InputError, a crash or a sanitizer report is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "dmbd/blocks/error.hpp"
#include "dmbd/diagrams/diagram.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = std::string(DMBD_SOURCE_DIR) + "/examples/diagrams/fuzz-input.yaml";
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)dmbd::diagrams::Diagram::parse(text, path);
  } catch (const dmbd::InputError&) {
  }
  return 0;
}
