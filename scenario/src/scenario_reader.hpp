#pragma once
// The scenario reader's shared part (scenario_load.cpp reads the file and most sections;
// scenario_balance.cpp the balance map): a Reader on top of the located YAML reader, its
// generic value readers, and the sections' declarations. Internal to scenario/.
#include <algorithm>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "engine_names.hpp"
#include "dmbd/sim/event_grid.hpp"

#include "dmbd/base/yaml_fields.hpp"
#include "dmbd/base/yaml_reader.hpp"
#include "dmbd/scenario/scenario.hpp"

namespace dmbd::scenario::detail {

namespace fs = std::filesystem;

// Limits of what a scenario may ask for (each checked at its line).
constexpr std::size_t kMaxVariants = 1000;
constexpr long long kMaxFramePixels = 16384;
constexpr long long kMaxFrames = 1000000;
constexpr long long kMaxExactInteger = 1LL << 53;  // doubles hold every integer up to here

// The scenario's reading on top of yaml::Reader (which records every problem) and its
// settings helpers (yaml::Fields): a function that meets a wrong value records it and
// throws yaml::Skip, and optional() and each list entry catch it, so that one mistake
// loses only its own value.
struct ReaderBase {
  mutable yaml::Reader rd;
};
struct Reader : ReaderBase, yaml::Fields {
  std::string dir;

  Reader(yaml::Reader r, std::string folder) : ReaderBase{std::move(r)}, yaml::Fields(rd), dir(std::move(folder)) {}
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  // A rate of the co-simulation's nanosecond grid.
  double rate(const YAML::Node& n, const std::string& what) const {
    const double r = positive(n, what);
    if (const std::string problem = rate_problem(r); !problem.empty()) fail(n, what + ": " + problem);
    return r;
  }
  double duration(const YAML::Node& n, const std::string& what) const {
    const double d = positive(n, what);
    if (!(d < kMaxDurationS)) fail(n, fmt::format("{}: {:g} s is too long (the simulation counts nanoseconds: below 1e9 s)", what, d));
    return d;
  }
  Eigen::Vector3d vec3(const YAML::Node& n, const std::string& what) const {
    const auto v = numbers<3>(n, what);
    return {v[0], v[1], v[2]};
  }
  // Whether a file of that name is in the scenario's folder (false when the system
  // cannot tell, e.g. a name too long).
  bool exists_here(const std::string& name) const {
    std::error_code ec;
    return fs::exists(fs::path(dir) / name, ec);
  }
  std::string path(const YAML::Node& n, const std::string& what) const {
    const std::string p = text(n, what);
    const fs::path full = fs::path(p).is_absolute() ? fs::path(p) : fs::path(dir) / p;
    std::error_code ec;  // the throwing fs::exists escaped on a name too long for the system
    const bool exists = fs::exists(full, ec);
    if (ec) fail(n, what + ": cannot use the file '" + full.string() + "': " + ec.message());
    if (!exists) fail(n, what + ": file '" + full.string() + "' does not exist");
    return full.lexically_normal().string();
  }

  Source source(const YAML::Node& n, const std::string& what) const {
    Source s;
    if (n.IsSequence()) {  // a sum of sources
      if (n.size() == 0) fail(n, what + ": expected at least one source");
      s = source(n[0], what);
      for (std::size_t k = 1; k < n.size(); ++k) s.plus.push_back(source(n[k], what));
      return s;
    }
    if (n.IsScalar()) {
      s.offset = number(n, what);
      return s;
    }
    keys(n, what, {"type", "value", "offset", "amplitude", "start_s", "duration_s", "freq_hz", "f0_hz", "f1_hz", "ramp_s", "steps"});
    if (!n["type"]) fail(n, what + ": expected 'type' (constant, steps, sine or chirp)");
    const std::string type = text(n["type"], what + ".type");
    if (n["offset"]) s.offset = number(n["offset"], what + ".offset");
    if (n["value"]) s.offset = number(n["value"], what + ".value");
    if (n["amplitude"]) s.amplitude = number(n["amplitude"], what + ".amplitude");
    if (n["start_s"]) s.start_s = number(n["start_s"], what + ".start_s");
    if (n["duration_s"]) s.duration_s = number(n["duration_s"], what + ".duration_s");
    if (n["ramp_s"]) s.ramp_s = number(n["ramp_s"], what + ".ramp_s");
    if (type == "constant") {
      s.kind = Source::Kind::Constant;
    } else if (type == "steps") {
      s.kind = Source::Kind::Steps;
      if (!n["steps"] || !n["steps"].IsSequence()) fail(n, what + ": a steps source needs 'steps: [[time_s, value], ...]'");
      double last = -1e300;
      for (const auto& e : n["steps"]) {
        if (!e.IsSequence() || e.size() != 2) fail(e, what + ".steps: expected [time_s, value]");
        const double t = number(e[0], what + ".steps time"), v = number(e[1], what + ".steps value");
        if (t < last) fail(e, what + ".steps: times must not decrease");
        last = t;
        s.steps.emplace_back(t, v);
      }
    } else if (type == "sine") {
      s.kind = Source::Kind::Sine;
      if (!n["freq_hz"]) fail(n, what + ": a sine needs freq_hz");
      s.freq_hz = positive(n["freq_hz"], what + ".freq_hz");
    } else if (type == "chirp") {
      s.kind = Source::Kind::Chirp;
      if (!n["f0_hz"] || !n["f1_hz"] || !n["duration_s"]) fail(n, what + ": a chirp needs f0_hz, f1_hz and duration_s");
      s.f0_hz = positive(n["f0_hz"], what + ".f0_hz");
      s.f1_hz = positive(n["f1_hz"], what + ".f1_hz");
      if (!(s.duration_s > 0)) fail(n["duration_s"], what + ".duration_s: expected a positive number");
    } else {
      fail(n["type"], what + ": unknown source type '" + type + "' (expected constant, steps, sine or chirp)");
    }
    return s;
  }

  Eigen::Vector2d vec2(const YAML::Node& n, const std::string& what) const {
    if (!n.IsSequence() || n.size() != 2) fail(n, what + ": expected a list of 2 numbers [x, y]");
    return {number(n[0], what), number(n[1], what)};
  }

  // Notes on deprecated keys read (Scenario::notes), each once.
  mutable std::vector<std::string> notes;
  void note(const std::string& line) const {
    if (std::find(notes.begin(), notes.end(), line) == notes.end()) notes.push_back(line);
  }

  // The sections (scenario_load.cpp; bus controllers: scenario_bus.cpp; the
  // experiment: scenario_experiment.cpp).
  void robot(const YAML::Node& n, RobotSetup& r) const;
  void robot_name(const YAML::Node& n, RobotSetup& r) const;
  void robot_actuators(const YAML::Node& a, RobotSetup& r) const;
  void actuator_scales(const YAML::Node& sc, RobotSetup& r) const;
  ForceSpec::Trigger trigger(const YAML::Node& t) const;
  void push(const YAML::Node& n, VariantSetup& v) const;
  void support(const YAML::Node& x, RobotSetup& r) const;
  Eigen::Isometry3d base_pose(const YAML::Node& p) const;
  void payloads(const YAML::Node& n, RobotSetup& r) const;
  void loads(const YAML::Node& n, RobotSetup& r) const;
  ControllerSetup controller(const YAML::Node& n) const;
  void ports(const YAML::Node& n, const std::string& side, ControllerSetup& c) const;
  void integration(const YAML::Node& n, IntegrationSetup& in) const;
  void variant_fields(const YAML::Node& n, VariantSetup& v) const;
  void end_on_fall(const YAML::Node& n, VariantSetup& v) const;
  void bus_controllers(const YAML::Node& list, VariantSetup& v) const;
  void bus_controller(const YAML::Node& n, const std::string& type, VariantSetup& v) const;
  void experiment(const YAML::Node& e, experiments::ExperimentSetup& x) const;
  void forces(const YAML::Node& n, VariantSetup& v) const;
  void sensors(const YAML::Node& s, VariantSetup& v) const;
  void thermal(const YAML::Node& t, VariantSetup& v) const;
};

// `sweep_plots` (sweep_plot_load.cpp): each entry's axis must be one of `matrix`'s
// axes whose every value gives `value`.
void read_sweep_plots(const Reader& rd, const YAML::Node& list, const YAML::Node& matrix, std::vector<SweepPlotSetup>& out);

}  // namespace dmbd::scenario::detail
