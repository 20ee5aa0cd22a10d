// Code generation (docs/python.md, "Code generation"): the header `dmbd codegen` writes,
// or its C files (--language c), as text, from a diagram file or a transfer function. The
// program's warnings (a delay rounded to whole samples, a pole above the loop's Nyquist
// frequency) become Python UserWarnings.
#include "bindings.hpp"
#include "convert.hpp"
#include "lowering.hpp"
#include "systems.hpp"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <optional>

#include "dmbd/base/error.hpp"
#include "dmbd/base/file.hpp"
#include "dmbd/codegen/emit.hpp"
#include "dmbd/codegen/emit_c.hpp"
#include "dmbd/codegen/fixed.hpp"
#include "dmbd/codegen/loop_program.hpp"
#include "dmbd/diagrams/diagram.hpp"

namespace dmbd::python {

namespace b = dmbd::blocks;
namespace cg = dmbd::codegen;
using namespace pybind11::literals;

namespace {

// The generated files {file name: text}: <name>.hpp (C++), or <name>.h and <name>.c (C),
// made by the emitters `dmbd codegen` calls, so they are its files byte for byte.
std::vector<std::pair<std::string, std::string>> emitted(const cg::LoopProgram& p, const Lowered& l, const std::string& scalar,
                                                         int word_bits, cg::Language language) {
  const cg::EmitOptions eo{scalar == "float" ? cg::Scalar::Float : cg::Scalar::Double, l.source};
  std::optional<cg::FixedProgram> fx;
  if (scalar == "fixed") fx = cg::make_fixed(p, l.input_ranges, word_bits);
  if (language == cg::Language::Cpp)
    return {{p.name + ".hpp", fx ? cg::emit_fixed_header(p, *fx, eo) : cg::emit_header(p, eo)}};
  const cg::CFiles c = fx ? cg::emit_fixed_c(p, *fx, eo) : cg::emit_c(p, eo);
  return {{p.name + ".h", c.header}, {p.name + ".c", c.source}};
}

// out_dir given: the files written there, each atomically (write_file_atomic).
void write_files(const std::vector<std::pair<std::string, std::string>>& files, const py::object& out_dir) {
  if (out_dir.is_none()) return;
  const std::filesystem::path dir = to_path(out_dir);
  if (!std::filesystem::is_directory(dir)) throw InputError("out_dir '" + dir.string() + "': not a directory");
  for (const auto& [name, text] : files) write_file_atomic((dir / name).string(), text);
}

py::object generate_code(const py::object& source, double rate_hz, const py::object& method, const py::object& block_methods,
                         const std::string& scalar, int word_bits, const py::object& input_range, const py::object& name,
                         const py::object& params, const std::string& language, const py::object& out_dir) {
  if (language != "cpp" && language != "c") throw InputError("language '" + language + "': expected cpp or c");
  if (scalar != "double" && scalar != "float" && scalar != "fixed")
    throw InputError("scalar '" + scalar + "': expected double, float or fixed");
  if (word_bits != 32 && word_bits != 16) throw InputError("word_bits " + std::to_string(word_bits) + ": expected 16 or 32");
  std::optional<Range> range;
  if (!input_range.is_none()) {
    const std::vector<double> r = to_vector(input_range, "input_range");
    if (r.size() != 2 || !(r[0] < r[1])) throw InputError("input_range: expected (lo, hi) with lo < hi");
    range = Range{r[0], r[1]};
  }
  Lowered l = lower(source, lower_options(rate_hz, method, block_methods), !method.is_none(), range, params);
  cg::LoopProgram& p = l.program;
  if (!name.is_none()) p.name = name.cast<std::string>();
  if (p.name.empty()) throw InputError("name: expected a C++ identifier, got an empty name");
  for (char c : p.name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_'))
      throw InputError("name '" + p.name + "': expected a C++ identifier");
  for (const std::string& w : p.warnings)
    if (PyErr_WarnEx(PyExc_UserWarning, (p.name + ": " + w).c_str(), 1) != 0) throw py::error_already_set();
  const auto files = emitted(p, l, scalar, word_bits, language == "c" ? cg::Language::C : cg::Language::Cpp);
  write_files(files, out_dir);
  if (language == "cpp") return py::str(files[0].second);
  py::dict d;
  for (const auto& [file, text] : files) d[py::str(file)] = py::str(text);
  return std::move(d);
}

}  // namespace

void bind_codegen(py::module_& m) {
  m.def("generate_code", &generate_code, "source"_a, "rate_hz"_a, "method"_a = py::none(), "block_methods"_a = py::none(),
        "scalar"_a = "double", "word_bits"_a = 32, "input_range"_a = py::none(), "name"_a = py::none(),
        "params"_a = py::none(), "language"_a = "cpp", "out_dir"_a = py::none(), R"doc(
The C++ header `dmbd codegen` generates (docs/codegen.md), as text: `source` is a diagram
file (str or path) or a TransferFunction, run at rate_hz. method: "tustin", "zoh" or
"backward-euler" for continuous blocks (default: the diagram's `discretization`, else
tustin); block_methods {block path: method}; scalar "double", "float" or "fixed" (with
word_bits 16 or 32 and input_range (lo, hi) for inputs the diagram gives no range);
name: the namespace (default: the diagram's name, "tf" for a TransferFunction); params:
the diagram's parameter overrides. The program's warnings are issued as UserWarnings.
language="c": the C99 files of `dmbd codegen --language c` instead, as a dict
{"<name>.h": text, "<name>.c": text}. out_dir: also write the file(s) there.)doc");
}

}  // namespace dmbd::python
