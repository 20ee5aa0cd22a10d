// Scenarios (docs/python.md, "Scenarios"): a scenario run as `dmbd simulate` runs it
// (docs/scenario-format.md), its logs as NumPy arrays and its metrics as a dict. The
// run directory (log.csv, metrics.json) goes to out_dir, or to a temporary folder
// removed afterwards; no report is drawn.
#include "bindings.hpp"
#include "convert.hpp"
#include "py_controller.hpp"

#include <stdlib.h>

#include <algorithm>
#include <filesystem>
#include <optional>

#include "dmbd/base/error.hpp"
#include "dmbd/scenario/run_directory.hpp"
#include "dmbd/scenario/scenario.hpp"

namespace dmbd::python {

namespace fs = std::filesystem;
using namespace pybind11::literals;

namespace {

struct ScenarioResult {
  scenario::ScenarioRun run;
  std::optional<std::string> out_dir;  // none: a temporary folder, removed

  const sim::VariantResult& variant(const py::object& name) const {
    if (name.is_none()) {
      if (run.runs.size() == 1) return run.runs.front();
      throw py::key_error("the scenario has " + std::to_string(run.runs.size()) + " variants: name one (" + variant_list() + ")");
    }
    const std::string n = name.cast<std::string>();
    for (const auto& r : run.runs)
      if (r.name == n) return r;
    throw py::key_error("no variant '" + n + "' in " + run.scenario.file + " (variants: " + variant_list() + ")");
  }

  std::string variant_list() const {
    std::string s;
    for (const auto& r : run.runs) s += (s.empty() ? "" : ", ") + r.name;
    return s;
  }
};

// A folder of its own under the system's temporary folder.
std::string temporary_folder() {
  std::string pattern = (fs::temp_directory_path() / "dmbd-python-XXXXXX").string();
  if (!mkdtemp(pattern.data())) throw OutputError("cannot create a temporary folder in " + fs::temp_directory_path().string());
  return pattern;
}

// Each Python controller of `controllers` ({name: obj}) in every variant of s, in place
// of the scenario's controller or bus controller of that name (if any).
void add_python_controllers(scenario::Scenario& s, const py::object& controllers) {
  if (!py::isinstance<py::dict>(controllers))
    throw py::type_error("controllers: expected a dict {name: controller object}, got " + py::repr(controllers).cast<std::string>());
  for (const auto& [key, obj] : controllers.cast<py::dict>()) {
    if (!py::isinstance<py::str>(key) || key.cast<std::string>().empty())
      throw InputError("run_scenario: controllers: expected names (non-empty str) as keys, got " + py::repr(key).cast<std::string>());
    const std::string name = key.cast<std::string>();
    const auto options = python_controller_options(name, py::reinterpret_borrow<py::object>(obj));
    for (auto& v : s.variants) {
      auto& c = v.controllers;
      c.erase(std::remove_if(c.begin(), c.end(), [&](const scenario::ControllerSetup& x) { return x.name == name; }), c.end());
      auto& b = v.bus_controllers;
      b.erase(std::remove_if(b.begin(), b.end(), [&](const auto& x) { return x->name == name; }), b.end());
      v.bus_controllers.push_back(options);
    }
  }
}

ScenarioResult run(const py::object& path, const py::object& duration_s, const py::object& out_dir, const py::object& controllers) {
  const std::string file = to_path(path);
  scenario::ScenarioRunOptions o;
  if (!duration_s.is_none()) {
    o.duration_s = duration_s.cast<double>();
    if (!(*o.duration_s > 0.0) || !std::isfinite(*o.duration_s))
      throw InputError("duration_s " + std::to_string(*o.duration_s) + ": expected a positive number of seconds");
  }
  ScenarioResult r;
  if (!out_dir.is_none()) r.out_dir = to_path(out_dir);
  scenario::Scenario s = scenario::load_scenario(file);
  if (!controllers.is_none()) add_python_controllers(s, controllers);
  const std::string dir = r.out_dir ? *r.out_dir : temporary_folder();
  try {
    // Minutes of simulation: other Python threads run meanwhile (a Python controller
    // takes the GIL for each of its ticks).
    py::gil_scoped_release release;
    r.run = scenario::run_scenario(s, dir, o);
  } catch (...) {
    if (!r.out_dir) {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
    throw;
  }
  if (!r.out_dir) {
    std::error_code ec;
    fs::remove_all(dir, ec);
    r.run.files.clear();
  }
  return r;
}

}  // namespace

void bind_sim(py::module_& m) {
  register_python_controller_type();
  py::class_<ScenarioResult>(m, "ScenarioRun", R"doc(
A scenario's run: every variant's log and the experiment's metrics. Made by run_scenario().)doc")
      .def_property_readonly("name", [](const ScenarioResult& r) { return r.run.scenario.name; })
      .def_property_readonly("file", [](const ScenarioResult& r) { return r.run.scenario.file; })
      .def_property_readonly("variants",
                             [](const ScenarioResult& r) {
                               py::list l;
                               for (const auto& v : r.run.runs) l.append(v.name);
                               return l;
                             },
                             "The variants' names, in the scenario's order.")
      .def("log",
           [](const ScenarioResult& r, const py::object& variant) {
             const sim::Log& log = r.variant(variant).log;
             py::dict d;
             for (size_t c = 0; c < log.columns(); ++c) d[py::str(log.name(static_cast<int>(c)))] = to_array(log.column(static_cast<int>(c)));
             return d;
           },
           "variant"_a = py::none(), R"doc(
A variant's log as {signal: NumPy array}, every array one value per logged instant; "t"
is the time (s). variant may be omitted when the scenario has one.)doc")
      .def("units",
           [](const ScenarioResult& r, const py::object& variant) {
             const sim::Log& log = r.variant(variant).log;
             py::dict d;
             for (size_t c = 0; c < log.columns(); ++c) d[py::str(log.name(static_cast<int>(c)))] = log.unit(static_cast<int>(c));
             return d;
           },
           "variant"_a = py::none(), "A variant's {signal: unit}.")
      .def_property_readonly("metrics", [](const ScenarioResult& r) { return to_python(r.run.metrics, true); },
                             "The metrics of metrics.json as a dict (the experiment's, and per run its figures);\n"
                             "a figure that was not reached is float('inf') or float('nan').")
      .def_property_readonly("runs",
                             [](const ScenarioResult& r) {
                               py::list l;
                               for (const auto& v : r.run.runs) {
                                 py::dict axes;
                                 for (const auto& [axis, value] : v.axes) axes[py::str(axis)] = value;
                                 l.append(py::dict("name"_a = v.name, "axes"_a = axes, "wall_s"_a = v.wall_s,
                                                   "real_time_factor"_a = v.real_time_factor,
                                                   "integrator_steps"_a = v.integrator_steps, "warnings"_a = v.warnings));
                               }
                               return l;
                             },
                             "Per variant: name, axes, wall_s, real_time_factor, integrator_steps, warnings.")
      .def_property_readonly("warnings", [](const ScenarioResult& r) { return r.run.experiment.warnings; },
                             "The experiment's warnings (e.g. a run shorter than its windows).")
      .def_property_readonly("notes", [](const ScenarioResult& r) { return r.run.experiment.notes; })
      .def_property_readonly("out_dir", [](const ScenarioResult& r) { return r.out_dir ? py::object(py::str(*r.out_dir)) : py::object(py::none()); },
                             "The run directory, or None when it was a temporary one.")
      .def_property_readonly("files", [](const ScenarioResult& r) { return r.run.files; },
                             "Files written to out_dir (relative to it); empty without out_dir.")
      .def("__repr__", [](const ScenarioResult& r) {
        return "<dmbd.ScenarioRun '" + r.run.scenario.name + "': " + std::to_string(r.run.runs.size()) + " variants>";
      });

  m.def("run_scenario", &run, "path"_a, "duration_s"_a = py::none(), "out_dir"_a = py::none(), "controllers"_a = py::none(), R"doc(
Run every variant of a scenario file (docs/scenario-format.md), as `dmbd simulate` does
without its report: duration_s overrides every variant's duration; out_dir receives
log.csv and metrics.json (created if missing; default: a temporary folder, removed).
controllers: {name: obj}, controllers written in Python on the bus of every variant, each
in place of the scenario's controller of that name if it has one: obj.step(t, inputs) ->
outputs (1-D NumPy array in, array-like out), obj.rate_hz, obj.delay_s (default 0),
obj.inputs (bus signals), obj.outputs (bus signals, or {signal: unit}), and optionally
obj.reset(), called before each variant runs. An exception in step() stops the run:
ControllerError with the traceback's last line (docs/python.md).
Returns a ScenarioRun. InputError (file:line:column: ...) for a mistake in the scenario,
DivergenceError or ModelError for a run that diverges.)doc");
}

}  // namespace dmbd::python
