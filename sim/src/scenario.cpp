// Scenario files: parsing (with file:line:column in every message) and running a variant.
#include "dmbd/sim/scenario.hpp"

#include "variant_controllers.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "dmbd/blocks/error.hpp"
#include "dmbd/codegen/fixed.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "dmbd/model/actuator.hpp"
#include "dmbd/model/error.hpp"
#include "dmbd/model/robot_description.hpp"

namespace dmbd::sim {

namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------- YAML reading
// Limits of what a scenario may ask for (each checked at its line).
constexpr std::size_t kMaxVariants = 1000;
constexpr long long kMaxFramePixels = 16384;
constexpr long long kMaxFrames = 1000000;
constexpr long long kMaxExactInteger = 1LL << 53;  // doubles hold every integer up to here

struct Reader {
  std::string file;
  std::string dir;

  std::string at(const YAML::Node& n) const {
    if (!n.IsDefined()) return file;  // a missing key: callers name the map that lacks it
    const YAML::Mark m = n.Mark();
    if (m.line < 0) return file;
    return fmt::format("{}:{}:{}", file, m.line + 1, m.column + 1);
  }
  // The value of a key the map n must have.
  YAML::Node required(const YAML::Node& n, const char* key, const std::string& what) const {
    if (!n[key]) fail(n, what + ": expected '" + key + "'");
    return n[key];
  }
  [[noreturn]] void fail(const YAML::Node& n, const std::string& what) const { throw InputError(at(n) + ": " + what); }

  // A map key: a plain name (yaml-cpp would throw on a list, a map or a null as key).
  std::string key(const YAML::Node& k, const std::string& what) const {
    if (!k.IsScalar()) fail(k, what + ": a key must be a name, not a list, a map or empty");
    return k.Scalar();
  }
  // The list map[key], to iterate (yaml-cpp iterates a map as pairs whose nodes are
  // unusable). An empty value has no place of its own: the error names its key's.
  YAML::Node list(const YAML::Node& map, const char* key, const std::string& what) const {
    const YAML::Node n = map[key];
    if (n.IsSequence()) return n;
    for (const auto& kv : map)
      if (n.IsNull() && kv.first.IsScalar() && kv.first.Scalar() == key) fail(kv.first, what + ": expected a list");
    fail(n, what + ": expected a list");
  }
  void keys(const YAML::Node& n, const std::string& what, std::initializer_list<const char*> allowed) const {
    if (!n.IsMap()) fail(n, what + ": expected a map");
    for (const auto& kv : n) {
      const std::string k = key(kv.first, what);
      bool ok = false;
      std::string list;
      for (const char* a : allowed) {
        ok = ok || k == a;
        list += (list.empty() ? "" : ", ") + std::string(a);
      }
      if (!ok) fail(kv.first, what + ": unknown key '" + k + "' (expected one of: " + list + ")");
    }
  }
  double number(const YAML::Node& n, const std::string& what) const {
    if (!n.IsScalar()) fail(n, what + ": expected a number");
    try {
      const double v = n.as<double>();
      if (!std::isfinite(v)) fail(n, what + ": expected a finite number");
      return v;
    } catch (const YAML::Exception&) {
      fail(n, what + ": expected a number, got '" + n.Scalar() + "'");
    }
  }
  // A whole number in [lo, hi] (checked before it is converted).
  long long integer(const YAML::Node& n, const std::string& what, long long lo, long long hi) const {
    const double v = number(n, what);
    if (v != std::floor(v) || v < static_cast<double>(lo) || v > static_cast<double>(hi))
      fail(n, fmt::format("{}: expected a whole number from {} to {}", what, lo, hi));
    return static_cast<long long>(v);
  }
  double positive(const YAML::Node& n, const std::string& what) const {
    const double v = number(n, what);
    if (!(v > 0)) fail(n, what + ": expected a positive number");
    return v;
  }
  std::string text(const YAML::Node& n, const std::string& what) const {
    if (!n.IsScalar()) fail(n, what + ": expected a string");
    return n.Scalar();
  }
  bool boolean(const YAML::Node& n, const std::string& what) const {
    if (!n.IsScalar()) fail(n, what + ": expected true or false");
    try {
      return n.as<bool>();
    } catch (const YAML::Exception&) {
      fail(n, what + ": expected true or false, got '" + n.Scalar() + "'");
    }
  }
  Eigen::Vector3d vec3(const YAML::Node& n, const std::string& what) const {
    if (!n.IsSequence() || n.size() != 3) fail(n, what + ": expected a list of 3 numbers");
    return {number(n[0], what), number(n[1], what), number(n[2], what)};
  }
  // A name or a list of names; where[prefix + ":" + name] is set to each one's location.
  std::vector<std::string> names(const YAML::Node& n, const std::string& what, std::map<std::string, std::string>* where = nullptr,
                                 const std::string& prefix = "") const {
    std::vector<std::string> r;
    if (n.IsScalar()) {
      if (where) (*where)[prefix + ":" + n.Scalar()] = at(n);
      return {n.Scalar()};
    }
    if (!n.IsSequence()) fail(n, what + ": expected a list of names");
    for (const auto& e : n) {
      r.push_back(text(e, what));
      if (where) (*where)[prefix + ":" + r.back()] = at(e);
    }
    return r;
  }
  std::vector<std::pair<std::string, double>> angles(const YAML::Node& n, const std::string& what,
                                                     std::map<std::string, std::string>* where = nullptr, const std::string& prefix = "") const {
    if (!n.IsMap()) fail(n, what + ": expected a map of joint: value");
    std::vector<std::pair<std::string, double>> r;
    for (const auto& kv : n) {
      const std::string k = key(kv.first, what);
      r.emplace_back(k, number(kv.second, what + "." + k));
      if (where) (*where)[prefix + ":" + r.back().first] = at(kv.first);
    }
    return r;
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

  void robot(const YAML::Node& n, RobotSetup& r) const {
    keys(n, "robot", {"urdf", "base", "base_pose", "actuators", "moving", "freeze", "initial", "lock", "payloads", "loads",
                      "contact", "gravity"});
    if (n["urdf"]) r.urdf = text(n["urdf"], "robot.urdf") == "draco" ? "draco" : path(n["urdf"], "robot.urdf");
    if (n["base"]) {
      const std::string b = text(n["base"], "robot.base");
      if (b == "fixed") r.base = model::BaseMode::Fixed;
      else if (b == "floating") r.base = model::BaseMode::Floating;
      else fail(n["base"], "robot.base: expected fixed or floating, got '" + b + "'");
    }
    if (n["base_pose"]) {
      const YAML::Node p = n["base_pose"];
      keys(p, "robot.base_pose", {"xyz", "rpy"});
      Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
      if (p["xyz"]) X.translation() = vec3(p["xyz"], "robot.base_pose.xyz");
      if (p["rpy"]) {
        const Eigen::Vector3d rpy = vec3(p["rpy"], "robot.base_pose.rpy");
        X.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                      Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                         .toRotationMatrix();
      }
      r.X_WB = X;
    }
    if (n["actuators"]) {
      r.all_actuators = n["actuators"].IsScalar() && n["actuators"].Scalar() == "all";
      r.actuators = r.all_actuators ? std::vector<std::string>{} : names(n["actuators"], "robot.actuators", &r.where, "actuators");
    }
    if (n["moving"]) {
      r.freeze_all_others = true;
      r.moving = names(n["moving"], "robot.moving", &r.where, "moving");
    }
    if (n["freeze"]) r.freeze = angles(n["freeze"], "robot.freeze", &r.where, "freeze");
    if (n["initial"]) r.initial = angles(n["initial"], "robot.initial", &r.where, "initial");
    if (n["lock"]) r.lock = angles(n["lock"], "robot.lock", &r.where, "lock");
    if (n["payloads"]) {
      r.payloads.clear();
      for (const auto& e : list(n, "payloads", "robot.payloads")) {
        keys(e, "robot.payloads", {"link", "mass_kg", "com", "inertia_kgm2"});
        Payload p;
        p.link = text(required(e, "link", "robot.payloads"), "payload.link");
        p.mass_kg = positive(required(e, "mass_kg", "robot.payloads"), "payload.mass_kg");
        r.where["payloads:" + p.link] = at(e["link"]);
        if (e["com"]) p.com_L = vec3(e["com"], "payload.com");
        if (e["inertia_kgm2"]) p.inertia_kgm2 = vec3(e["inertia_kgm2"], "payload.inertia_kgm2");
        r.payloads.push_back(p);
      }
    }
    if (n["loads"]) {
      r.loads.clear();
      for (const auto& e : list(n, "loads", "robot.loads")) {
        keys(e, "robot.loads", {"joint", "reflected_mass_kg"});
        r.loads.push_back({text(required(e, "joint", "robot.loads"), "load.joint"),
                           positive(required(e, "reflected_mass_kg", "robot.loads"), "load.reflected_mass_kg")});
        r.where["loads:" + r.loads.back().joint] = at(e["joint"]);
      }
    }
    if (n["contact"]) r.contact = boolean(n["contact"], "robot.contact");
    if (n["gravity"]) r.gravity_m_s2 = number(n["gravity"], "robot.gravity");
  }

  ControllerSetup controller(const YAML::Node& n) const {
    keys(n, "controller", {"name", "diagram", "parameters", "rate_hz", "delay_s", "scalar", "word_bits", "inputs", "outputs"});
    ControllerSetup c;
    if (!n["name"] || !n["diagram"]) fail(n, "controller: expected 'name' and 'diagram'");
    c.where = at(n["name"]);
    c.name = text(n["name"], "controller.name");
    c.diagram = path(n["diagram"], "controller '" + c.name + "'.diagram");
    if (n["parameters"]) c.parameters = angles(n["parameters"], "controller '" + c.name + "'.parameters");
    if (n["rate_hz"]) c.rate_hz = positive(n["rate_hz"], "controller.rate_hz");
    if (n["delay_s"]) c.delay_s = number(n["delay_s"], "controller.delay_s");
    if (n["scalar"]) {
      const std::string s = text(n["scalar"], "controller.scalar");
      if (s == "double") c.scalar = Scalar::Double;
      else if (s == "float") c.scalar = Scalar::Float;
      else if (s == "fixed") c.scalar = Scalar::Fixed;
      else fail(n["scalar"], "controller.scalar: expected double, float or fixed, got '" + s + "'");
    }
    if (n["word_bits"]) {
      c.word_bits = static_cast<int>(integer(n["word_bits"], "controller.word_bits", 16, 32));
      if (c.word_bits != 16 && c.word_bits != 32) fail(n["word_bits"], "controller.word_bits: expected 16 or 32");
    }
    for (const char* side : {"inputs", "outputs"}) {
      if (!n[side]) fail(n, "controller '" + c.name + "': expected '" + side + "' (program port: bus signal)");
      if (!n[side].IsMap()) fail(n[side], "controller '" + c.name + "'." + side + ": expected a map of port: signal");
      const bool inputs = std::string(side) == "inputs";
      for (const auto& kv : n[side]) {
        (inputs ? c.inputs : c.outputs).emplace_back(key(kv.first, "controller '" + c.name + "'." + side), text(kv.second, side));
        (inputs ? c.input_where : c.output_where).push_back(at(kv.second));
      }
    }
    return c;
  }

  void integration(const YAML::Node& n, IntegrationSetup& in) const {
    keys(n, "integration", {"mode", "step_s", "accuracy"});
    if (n["mode"]) {
      const std::string m = text(n["mode"], "integration.mode");
      if (m == "fixed") in.mode = model::Integration::Fixed;
      else if (m == "accurate") in.mode = model::Integration::Accurate;
      else fail(n["mode"], "integration.mode: expected fixed or accurate, got '" + m + "'");
    }
    if (n["step_s"]) in.step_s = positive(n["step_s"], "integration.step_s");
    if (n["accuracy"]) in.accuracy = positive(n["accuracy"], "integration.accuracy");
    if (in.step_s > 0.01) fail(n["step_s"], "integration.step_s: " + fmt::format("{}", in.step_s) + " s is longer than 10 ms (expected 0.1 to 2 ms)");
    if (in.accuracy >= 0.1) fail(n["accuracy"], "integration.accuracy: " + fmt::format("{}", in.accuracy) + " is not a small relative accuracy (expected 1e-8 to 1e-3)");
  }

  // Fields a variant may override (everything but frames, plots, experiment).
  void variant_fields(const YAML::Node& n, VariantSetup& v) const {
    if (n["robot"]) robot(n["robot"], v.robot);
    if (n["controllers"]) {
      v.controllers.clear();
      if (!n["controllers"].IsSequence()) fail(n["controllers"], "controllers: expected a list");
      for (const auto& c : n["controllers"]) v.controllers.push_back(controller(c));
    }
    if (n["references"]) {
      v.references.clear();
      if (!n["references"].IsMap()) fail(n["references"], "references: expected a map of name: source");
      for (const auto& kv : n["references"]) {
        const std::string name = key(kv.first, "references");
        v.references.push_back({name, source(kv.second, "reference '" + name + "'"), at(kv.first)});
      }
    }
    if (n["forces"]) {
      v.forces.clear();
      for (const auto& e : list(n, "forces", "forces")) {
        keys(e, "force", {"link", "point", "direction", "source"});
        ForceSpec f;
        f.link = text(required(e, "link", "force"), "force.link");
        f.where = at(e["link"]);
        if (e["point"]) f.point_L = vec3(e["point"], "force.point");
        if (e["direction"]) f.direction_W = vec3(e["direction"], "force.direction");
        if (!e["source"]) fail(e, "force: expected 'source'");
        f.source = source(e["source"], "force.source");
        v.forces.push_back(f);
      }
    }
    if (n["duration_s"]) v.duration_s = positive(n["duration_s"], "duration_s");
    if (n["log_rate_hz"]) v.log_rate_hz = positive(n["log_rate_hz"], "log_rate_hz");
    if (n["sensors"]) {
      const YAML::Node s = n["sensors"];
      keys(s, "sensors", {"noise", "seed", "force_noise_N"});
      if (s["noise"]) v.sensor_noise = boolean(s["noise"], "sensors.noise");
      if (s["seed"]) v.seed = static_cast<uint64_t>(integer(s["seed"], "sensors.seed", 0, kMaxExactInteger));
      if (s["force_noise_N"]) v.force_noise_N = number(s["force_noise_N"], "sensors.force_noise_N");
    }
    if (n["integration"]) integration(n["integration"], v.integration);
    if (n["thermal"]) {
      const YAML::Node t = n["thermal"];
      keys(t, "thermal", {"cooling"});
      if (!t["cooling"]) fail(t, "thermal: expected 'cooling: on, off or both'");
      const std::string c = t["cooling"].IsScalar() ? t["cooling"].Scalar() : "";
      if (c == "on" || c == "true") v.cooling = Cooling::On;
      else if (c == "off" || c == "false") v.cooling = Cooling::Off;
      else if (c == "both") v.cooling = Cooling::Both;
      else fail(t["cooling"], "thermal.cooling: expected on, off or both");
    }
  }
};

const std::initializer_list<const char*> kVariantKeys = {"name", "robot", "controllers", "references", "forces", "duration_s",
                                                         "log_rate_hz", "sensors", "thermal", "integration"};

}  // namespace

Scenario load_scenario(const std::string& path) {
  std::error_code ec;
  const bool exists = fs::exists(path, ec);
  if (ec) throw InputError(path + ": cannot read the scenario file: " + ec.message());
  if (!exists) throw InputError(path + ": the scenario file does not exist");
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::ParserException& e) {
    throw InputError(fmt::format("{}:{}:{}: malformed YAML: {}", path, e.mark.line + 1, e.mark.column + 1, e.msg));
  } catch (const YAML::Exception& e) {
    throw InputError(path + ": cannot read: " + e.what());
  }
  Reader rd{path, fs::path(path).parent_path().string()};
  if (!root.IsMap()) throw InputError(path + ":1:1: a scenario is a map (name, robot, controllers, ...)");
  rd.keys(root, "scenario", {"name", "description", "robot", "controllers", "references", "forces", "duration_s", "log_rate_hz",
                             "sensors", "thermal", "integration", "frames", "plots", "variants", "matrix", "experiment"});
  Scenario s;
  s.file = path;
  s.name = root["name"] ? rd.text(root["name"], "name") : fs::path(path).stem().string();
  if (root["description"]) s.description = rd.text(root["description"], "description");
  VariantSetup base;
  base.name = "base";
  rd.variant_fields(root, base);

  if (root["variants"] && root["matrix"]) rd.fail(root["matrix"], "give either 'variants' or 'matrix', not both");
  if (root["variants"]) {
    if (!root["variants"].IsSequence()) rd.fail(root["variants"], "variants: expected a list");
    for (const auto& n : root["variants"]) {
      rd.keys(n, "variant", kVariantKeys);
      VariantSetup v = base;
      if (!n["name"]) rd.fail(n, "variant: expected 'name'");
      v.name = rd.text(n["name"], "variant.name");
      rd.variant_fields(n, v);
      s.variants.push_back(v);
    }
  } else if (root["matrix"]) {
    if (!root["matrix"].IsMap()) rd.fail(root["matrix"], "matrix: expected a map of axis: [values]");
    s.variants.push_back(base);
    s.variants.back().name.clear();
    for (const auto& axis : root["matrix"]) {
      const std::string an = rd.key(axis.first, "matrix");
      if (!axis.second.IsSequence() || axis.second.size() == 0) rd.fail(axis.second, "matrix." + an + ": expected a list of values");
      if (s.variants.size() * axis.second.size() > kMaxVariants)
        rd.fail(axis.first, fmt::format("matrix.{}: {} variants (more than {}): split the scenario", an,
                                         s.variants.size() * axis.second.size(), kMaxVariants));
      std::vector<VariantSetup> next;
      for (const VariantSetup& prev : s.variants)
        for (const auto& n : axis.second) {
          rd.keys(n, "matrix." + an, kVariantKeys);
          if (!n["name"]) rd.fail(n, "matrix." + an + ": each value needs a 'name'");
          VariantSetup v = prev;
          const std::string vn = rd.text(n["name"], "name");
          v.name = prev.name.empty() ? vn : prev.name + "/" + vn;
          v.axes.emplace_back(an, vn);
          rd.variant_fields(n, v);
          next.push_back(v);
        }
      s.variants = next;
    }
  } else {
    s.variants.push_back(base);
  }
  std::set<std::string> seen;
  for (const auto& v : s.variants)
    if (!seen.insert(v.name).second) throw InputError(path + ": two variants are named '" + v.name + "'");

  if (root["frames"]) {
    const YAML::Node f = root["frames"];
    if (f.IsScalar()) {
      s.frames.enabled = rd.boolean(f, "frames");
    } else {
      rd.keys(f, "frames", {"enabled", "fps", "width", "height", "max_frames", "camera", "variant"});
      if (f["enabled"]) s.frames.enabled = rd.boolean(f["enabled"], "frames.enabled");
      if (f["fps"]) s.frames.fps = rd.positive(f["fps"], "frames.fps");
      if (f["width"]) s.frames.width_px = static_cast<int>(rd.integer(f["width"], "frames.width", 1, kMaxFramePixels));
      if (f["height"]) s.frames.height_px = static_cast<int>(rd.integer(f["height"], "frames.height", 1, kMaxFramePixels));
      if (f["max_frames"]) s.frames.max_frames = static_cast<int>(rd.integer(f["max_frames"], "frames.max_frames", 1, kMaxFrames));
      if (f["camera"]) {
        rd.keys(f["camera"], "frames.camera", {"position", "look_at"});
        if (f["camera"]["position"]) s.frames.camera_position = rd.vec3(f["camera"]["position"], "frames.camera.position");
        if (f["camera"]["look_at"]) s.frames.camera_look_at = rd.vec3(f["camera"]["look_at"], "frames.camera.look_at");
      }
      if (f["variant"]) {
        s.frames.variant = rd.text(f["variant"], "frames.variant");
        if (!seen.count(s.frames.variant)) rd.fail(f["variant"], "frames.variant: no variant is named '" + s.frames.variant + "'");
      }
    }
  }
  if (root["plots"]) {
    for (const auto& p : rd.list(root, "plots", "plots")) {
      rd.keys(p, "plot", {"title", "y_label", "file", "signals"});
      PlotSetup ps;
      if (p["title"]) ps.title = rd.text(p["title"], "plot.title");
      if (p["y_label"]) ps.y_label = rd.text(p["y_label"], "plot.y_label");
      if (!p["file"] || !p["signals"]) rd.fail(p, "plot: expected 'file' and 'signals'");
      ps.file = rd.text(p["file"], "plot.file");
      ps.signals = rd.names(p["signals"], "plot.signals");
      s.plots.push_back(ps);
    }
  }
  if (root["experiment"]) {
    const YAML::Node e = root["experiment"];
    if (!e.IsMap() || !e["type"]) rd.fail(e, "experiment: expected a map with 'type'");
    s.experiment.type = rd.text(e["type"], "experiment.type");
    static const std::set<std::string> kTypes = {"sysid_rfsea", "force_tracking", "step_response", "thermal", "standing"};
    if (!kTypes.count(s.experiment.type))
      rd.fail(e["type"], "experiment.type: expected sysid_rfsea, force_tracking, step_response, thermal or standing, got '" + s.experiment.type + "'");
    // The keys each analysis reads (experiments.cpp, sysid_experiment.cpp): a name
    // (true) or a number (false).
    static const std::map<std::string, std::map<std::string, bool>> kKeys = {
        {"step_response",
         {{"reference", true}, {"output", true}, {"step_start_s", false}, {"step_end_s", false}, {"sine_start_s", false}, {"sine_end_s", false}}},
        {"force_tracking", {{"reference", true}, {"output", true}, {"start_s", false}, {"plot_window_s", false}}},
        {"thermal", {}},
        {"standing", {}},
        {"sysid_rfsea",
         {{"lead_in_s", false}, {"locked_f0_hz", false}, {"locked_f1_hz", false}, {"free_f0_hz", false}, {"free_f1_hz", false}, {"frequencies", false}}},
    };
    const auto& allowed = kKeys.at(s.experiment.type);
    for (const auto& kv : e) {
      const std::string k = rd.key(kv.first, "experiment");
      if (k == "type") continue;
      if (k == "joint") {
        s.experiment.joint = rd.text(kv.second, "experiment.joint");
        continue;
      }
      const auto it = allowed.find(k);
      if (it == allowed.end()) {
        std::string list = "type, joint";
        for (const auto& [name, is_text] : allowed) list += ", " + name;
        rd.fail(kv.first, "experiment " + s.experiment.type + ": unknown key '" + k + "' (expected one of: " + list + ")");
      }
      if (it->second) s.experiment.text[k] = rd.text(kv.second, "experiment." + k);
      else s.experiment.number[k] = rd.number(kv.second, "experiment." + k);
    }
  }
  return s;
}

// ---------------------------------------------------------------- running a variant
namespace {

model::RobotDescription load_robot(const RobotSetup& r) {
  const std::string path = r.urdf == "draco" ? std::string(DMBD_DRACO_DIR) + "/draco.urdf" : r.urdf;
  return model::load_urdf(path);
}

}  // namespace

VariantPlant variant_plant(const Scenario& s, const VariantSetup& v) {
  const RobotSetup& r = v.robot;
  // Where an entry of robot: was written (its file:line:col), else the scenario file.
  auto where = [&](const std::string& key) {
    const auto it = r.where.find(key);
    return it == r.where.end() ? s.file : it->second;
  };
  model::RobotDescription robot = load_robot(r);
  // Welded joints.
  std::vector<std::pair<std::string, double>> freeze = r.freeze;
  if (r.freeze_all_others)
    for (const auto& j : robot.joints) {
      const bool one_dof = j.type == model::JointType::Revolute || j.type == model::JointType::Continuous || j.type == model::JointType::Prismatic;
      if (!one_dof || std::count(r.moving.begin(), r.moving.end(), j.name)) continue;
      if (std::any_of(freeze.begin(), freeze.end(), [&](const auto& f) { return f.first == j.name; })) continue;
      freeze.emplace_back(j.name, j.has_limits ? std::clamp(0.0, j.lower, j.upper) : 0.0);
    }
  for (const auto& m : r.moving)
    if (robot.joint_index(m) < 0) throw InputError(where("moving:" + m) + ": robot.moving: the robot has no joint '" + m + "'");
  // The explicit welds, each checked where it was written (freeze_joints checks again).
  for (const auto& [name, q] : r.freeze) {
    const int j = robot.joint_index(name);
    if (j < 0) throw InputError(where("freeze:" + name) + ": robot.freeze: the robot has no joint '" + name + "'");
    const model::Joint& J = robot.joints[static_cast<std::size_t>(j)];
    if (J.has_limits && (q < J.lower || q > J.upper))
      throw InputError(fmt::format("{}: robot.freeze: joint '{}' welded at {} rad, outside its limits [{}, {}]", where("freeze:" + name), name, q,
                                   J.lower, J.upper));
  }
  try {
    robot = model::freeze_joints(robot, freeze);
  } catch (model::ModelError& e) {
    e.prepend(s.file + ": robot.freeze: ");
    throw;
  }
  for (const auto& p : r.payloads) {
    if (robot.link_index(p.link) < 0) throw InputError(where("payloads:" + p.link) + ": robot.payloads: the robot has no link '" + p.link + "'");
    model::add_payload(robot, p.link, p.mass_kg, p.com_L, p.inertia_kgm2);
  }

  // Actuators.
  std::vector<model::ActuatorParams> table;
  if (r.all_actuators || !r.actuators.empty()) {
    if (r.urdf != "draco") throw InputError(s.file + ": robot.actuators: actuator parameters exist for DRACO only (urdf: draco)");
    table = model::draco_actuators();
  }
  model::PlantOptions po;
  po.base = r.base;
  po.X_WB = r.X_WB;
  po.gravity_m_s2 = r.gravity_m_s2;
  po.contact = r.contact;
  po.integration = v.integration.mode;
  po.step_s = v.integration.step_s;
  po.accuracy = v.integration.accuracy;
  for (const auto& a : table) {
    const bool wanted = r.all_actuators || std::count(r.actuators.begin(), r.actuators.end(), a.joint);
    const int j = robot.joint_index(a.joint);
    if (wanted && j >= 0 && robot.joints[static_cast<std::size_t>(j)].type != model::JointType::Fixed) po.actuators.push_back(a);
  }
  for (const auto& name : r.actuators)
    if (!std::any_of(po.actuators.begin(), po.actuators.end(), [&](const auto& a) { return a.joint == name; }))
      throw InputError(where("actuators:" + name) + ": robot.actuators: '" + name + "' is not a moving joint with an actuator");

  auto initial_of = [&](const std::string& joint) { return initial_angle(r, joint); };
  // Reflected loads: a disc on the joint axis (added to the child link at the joint origin).
  for (const auto& load : r.loads) {
    const int j = robot.joint_index(load.joint);
    const auto act = std::find_if(po.actuators.begin(), po.actuators.end(), [&](const auto& a) { return a.joint == load.joint; });
    if (j < 0 || act == po.actuators.end())
      throw InputError(where("loads:" + load.joint) + ": robot.loads: '" + load.joint + "' is not an actuated moving joint");
    const double n_l = act->linkage.N_l(initial_of(load.joint));
    const double need = load.reflected_mass_kg / (n_l * n_l) - model::subtree_axis_inertia(robot, j);
    if (need < 0)
      throw InputError(fmt::format("{}: robot.loads: {} kg reflected is less than the bare link's {:.1f} kg", where("loads:" + load.joint), load.reflected_mass_kg,
                                   model::subtree_axis_inertia(robot, j) * n_l * n_l));
    const model::Joint& J = robot.joints[static_cast<std::size_t>(j)];
    const Eigen::Vector3d ax = J.axis.cwiseAbs();
    // A thin 10 kg disc about the axis, centred on it (no gravity torque).
    model::add_payload(robot, J.child, 10.0, Eigen::Vector3d::Zero(), need * ax + 0.5 * need * (Eigen::Vector3d::Ones() - ax));
  }
  return {std::move(robot), po};
}

double initial_angle(const RobotSetup& r, const std::string& joint) {
  for (const auto& [n, q] : r.initial)
    if (n == joint) return q;
  for (const auto& [n, q] : r.lock)
    if (n == joint) return q;
  return 0.0;
}

VariantResult run_variant(const Scenario& s, const VariantSetup& v, const RunOptions& options) {
  const RobotSetup& r = v.robot;
  auto where = [&](const std::string& key) {
    const auto it = r.where.find(key);
    return it == r.where.end() ? s.file : it->second;
  };
  const VariantPlant vp = variant_plant(s, v);
  const model::RobotDescription& robot = vp.robot;
  auto initial_of = [&](const std::string& joint) { return initial_angle(r, joint); };
  VariantResult res;
  res.name = v.name;
  res.axes = v.axes;
  model::Plant plant(robot, vp.options);
  plant.reset();
  Eigen::VectorXd q0 = plant.joint_positions();
  for (const auto& [n, q] : r.initial) {
    const int j = plant.joint_index(n);
    if (j < 0) throw InputError(where("initial:" + n) + ": robot.initial: '" + n + "' is not a moving joint");
    q0[j] = q;
  }
  plant.set_joint_positions(q0);
  plant.place_on_ground();  // a floating robot stands on its feet in its initial posture
  for (const auto& [n, q] : r.lock) {
    const int j = plant.joint_index(n);
    if (j < 0) throw InputError(where("lock:" + n) + ": robot.lock: '" + n + "' is not a moving joint");
    plant.lock_joint(j, q);
  }

  // The simulator's true values for the experiment of the first actuated joint.
  for (int k = 0; k < plant.num_actuators(); ++k) {
    const model::ActuatorParams& a = plant.actuator(k);
    if (a.joint != s.experiment.joint) continue;
    const int j = robot.joint_index(a.joint);
    const double n_l = a.linkage.N_l(initial_of(a.joint));
    res.truth = {{"J_m", a.J_m_kgm2}, {"B_m", a.B_m_Nms}, {"M_r", a.M_r_kg}, {"B_r", a.B_s_Ns_per_m}, {"K_r", a.K_s_N_per_m},
                 {"B_l", a.B_l_Ns_per_m}, {"M_l", model::subtree_axis_inertia(robot, j) * n_l * n_l}, {"k_tau", a.k_tau_Nm_per_A},
                 {"N_m", a.N_m_rad_per_m}, {"N_l", n_l}, {"q0", initial_of(a.joint)}, {"efficiency", a.efficiency}};
  }

  SimulationSpec spec;
  spec.references = v.references;
  spec.forces = v.forces;
  spec.duration_s = options.duration_s.value_or(v.duration_s);
  spec.log_rate_hz = v.log_rate_hz;
  spec.sensor_noise = v.sensor_noise;
  spec.seed = v.seed;
  spec.force_noise_N = v.force_noise_N;
  spec.cooling = v.cooling;
  for (const auto& c : v.controllers) {
    VariantController vc = variant_controller(s, c, spec.duration_s);
    spec.controllers.push_back(std::move(vc.spec));
    res.fixed_point.insert(res.fixed_point.end(), vc.fixed_point.begin(), vc.fixed_point.end());
  }

  Simulation sim(plant, spec);
  const auto t0 = std::chrono::steady_clock::now();
  const long long steps0 = plant.integrator_steps();
  res.log = sim.run(options.on_progress);
  res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  res.real_time_factor = spec.duration_s / std::max(res.wall_s, 1e-9);
  res.integrator_steps = plant.integrator_steps() - steps0;
  res.controller_steps = sim.controller_steps();
  res.clamp_events = sim.controller_clamp_events();
  fixed_point_warnings(res);
  return res;
}

}  // namespace dmbd::sim
