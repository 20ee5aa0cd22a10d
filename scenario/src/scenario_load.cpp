// Reading a scenario file (docs/scenario-format.md) with the located YAML reader: every
// problem collected and named file:line:column, expressions wherever a number is,
// unknown keys rejected, each limit checked at the line that gives the value.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include <fmt/format.h>

#include "engine_names.hpp"
#include "scenario_reader.hpp"

#include "dmbd/base/file.hpp"
#include "dmbd/base/strings.hpp"
#include "dmbd/base/yaml_reader.hpp"
#include "dmbd/blocks/expression_numbers.hpp"
#include "dmbd/model/actuator.hpp"
#include "dmbd/scenario/scenario.hpp"

namespace dmbd::scenario {

namespace detail {

void Reader::robot(const YAML::Node& n, RobotSetup& r) const {
  keys(n, "robot", {"name", "urdf", "base", "base_pose", "actuators", "moving", "freeze", "initial", "lock", "payloads", "loads",
                    "armature", "contact", "gravity", "ground_normal", "support"});
  if (n["name"] && n["urdf"]) fail(n["urdf"], "robot: give either 'name' (a robot folder) or 'urdf' (a file), not both");
  optional(n, "name", [&](const YAML::Node& x) { robot_name(x, r); });
  optional(n, "urdf", [&](const YAML::Node& u) {
    // A bare name (no folder, no extension) is how earlier versions named their built-in
    // robot: now a robot folder found by name.
    if (u.IsScalar() && !u.Scalar().empty() && u.Scalar().find_first_of("/.") == std::string::npos && !exists_here(u.Scalar())) {
      note(at(u) + ": robot.urdf: a robot's name is deprecated there: write robot.name: " + u.Scalar() + " (the robot folder)");
      return robot_name(u, r);
    }
    r.folder.reset();
    r.urdf = path(u, "robot.urdf");
    r.actuator_file.clear();
  });
  optional(n, "base", [&](const YAML::Node& b) {
    const std::string t = text(b, "robot.base");
    if (t == "fixed") r.base = model::BaseMode::Fixed;
    else if (t == "floating") r.base = model::BaseMode::Floating;
    else fail(b, "robot.base: expected fixed or floating, got '" + t + "'");
  });
  optional(n, "base_pose", [&](const YAML::Node& p) { r.X_WB = base_pose(p); });
  optional(n, "actuators", [&](const YAML::Node& a) { robot_actuators(a, r); });
  optional(n, "moving", [&](const YAML::Node& m) {
    r.freeze_all_others = true;
    r.moving = names(m, "robot.moving", &r.where, "moving");
  });
  optional(n, "freeze", [&](const YAML::Node& f) { r.freeze = named_numbers(f, "robot.freeze", &r.where, "freeze"); });
  optional(n, "initial", [&](const YAML::Node& i) { r.initial = named_numbers(i, "robot.initial", &r.where, "initial"); });
  optional(n, "armature", [&](const YAML::Node& a) {
    r.armature = named_numbers(a, "robot.armature", &r.where, "armature");
    for (const auto& [joint, value] : r.armature)
      if (!(value >= 0 && value <= 1e6)) fail(a[joint], "robot.armature: expected a rotor inertia of 0 to 1e6 kg m² for '" + joint + "'");
  });
  optional(n, "lock", [&](const YAML::Node& l) { r.lock = named_numbers(l, "robot.lock", &r.where, "lock"); });
  optional(n, "payloads", [&](const YAML::Node&) { payloads(n, r); });
  optional(n, "loads", [&](const YAML::Node&) { loads(n, r); });
  optional(n, "contact", [&](const YAML::Node& c) { r.contact = boolean(c, "robot.contact"); });
  optional(n, "gravity", [&](const YAML::Node& g) { r.gravity_m_s2 = number(g, "robot.gravity"); });
  optional(n, "ground_normal", [&](const YAML::Node& g) {
    const Eigen::Vector3d v = vec3(g, "robot.ground_normal");
    if (!(v.z() > 0)) fail(g, "robot.ground_normal: expected a normal pointing up (its z above 0), got [" + fmt::format("{}, {}, {}", v.x(), v.y(), v.z()) + "]");
    r.ground_normal = v.normalized();
  });
  optional(n, "support", [&](const YAML::Node& x) { support(x, r); });
}

// A robot folder by name: the scenario's folder searched first (model::find_robot).
void Reader::robot_name(const YAML::Node& x, RobotSetup& r) const {
  const std::string name = text(x, "robot.name");
  try {
    r.folder = std::make_shared<const model::RobotFolder>(model::find_robot(name, {dir}));
  } catch (const InputError& e) {
    fail(x, std::string("robot.name: ") + e.what());
  }
  r.urdf = r.folder->urdf;
  r.actuator_file = r.folder->actuators;
  r.where["robot"] = at(x);
}

// `actuators`: all, a list of joints, or {file: FILE, joints: all or a list, load: SET,
// scale: {SYMBOL: FACTOR}}.
void Reader::robot_actuators(const YAML::Node& a, RobotSetup& r) const {
  // Not `YAML::Node joints = a; joints = ...`: assigning to a yaml-cpp Node overwrites
  // the node it refers to (here the scenario's own actuators map).
  if (a.IsMap()) keys(a, "robot.actuators", {"file", "joints", "load", "scale"});
  // A variant's `actuators` replaces the base's whole (docs/scenario-format.md): its
  // file, load set and factors start from the robot's defaults, never compound.
  r.actuator_file = r.folder ? r.folder->actuators : std::string();
  r.actuator_load_set.clear();
  r.actuator_scales.clear();
  const YAML::Node joints = a.IsMap() ? required(a, "joints", "robot.actuators") : a;
  if (a.IsMap()) {
    optional(a, "file", [&](const YAML::Node& f) { r.actuator_file = path(f, "robot.actuators.file"); });
    optional(a, "load", [&](const YAML::Node& l) {
      r.actuator_load_set = text(l, "robot.actuators.load");
      r.where["actuators.load"] = at(l);
    });
    optional(a, "scale", [&](const YAML::Node& sc) { actuator_scales(sc, r); });
  }
  r.all_actuators = joints.IsScalar() && joints.Scalar() == "all";
  r.actuators = r.all_actuators ? std::vector<std::string>{} : names(joints, "robot.actuators", &r.where, "actuators");
  r.where["actuators"] = at(a);
}

// `actuators.scale: {SYMBOL: FACTOR}`: each symbol one of model::scalable_parameters(),
// each factor a number >= 0 (model::scale_parameter checks the rest when the table is read).
void Reader::actuator_scales(const YAML::Node& sc, RobotSetup& r) const {
  if (!sc.IsMap() || sc.size() == 0) fail(sc, "robot.actuators.scale: expected a map {parameter: factor}, e.g. {B_l: 0.5}");
  if (!rd.keys(sc, model::scalable_parameters(), "robot.actuators.scale", "actuator parameter")) throw yaml::Skip{};
  for (const auto& kv : sc) {
    const std::string symbol = kv.first.Scalar();
    const double f = number(kv.second, "robot.actuators.scale." + symbol);
    if (!(f >= 0)) fail(kv.second, "robot.actuators.scale." + symbol + ": expected a factor >= 0, got " + kv.second.Scalar());
    r.actuator_scales.emplace_back(symbol, f);
    r.where["actuators.scale:" + symbol] = at(kv.second);
  }
}

// The start-up support of a floating base (SupportSpec, simulation.hpp).
void Reader::support(const YAML::Node& x, RobotSetup& r) const {
  keys(x, "robot.support", {"release_s", "stiffness_N_per_m", "damping_N_s_per_m", "height_m"});
  SupportSpec s;
  s.release_s = rd.number_in(required(x, "release_s", "robot.support"), "robot.support.release_s", 0.0, 1e6, "s");
  optional(x, "stiffness_N_per_m", [&](const YAML::Node& y) { s.stiffness_N_per_m = rd.number_in(y, "robot.support.stiffness_N_per_m", 0.0, 1e9, "N/m"); });
  optional(x, "damping_N_s_per_m", [&](const YAML::Node& y) { s.damping_N_s_per_m = rd.number_in(y, "robot.support.damping_N_s_per_m", 0.0, 1e9, "N s/m"); });
  optional(x, "height_m", [&](const YAML::Node& y) { s.height_m = rd.number_in(y, "robot.support.height_m", 0.01, 10.0, "m"); });
  r.support = s;
  r.where["support"] = at(x);
}

Eigen::Isometry3d Reader::base_pose(const YAML::Node& p) const {
  keys(p, "robot.base_pose", {"xyz", "rpy"});
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  if (p["xyz"]) X.translation() = vec3(p["xyz"], "robot.base_pose.xyz");
  if (p["rpy"]) {
    const Eigen::Vector3d rpy = vec3(p["rpy"], "robot.base_pose.rpy");
    X.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
  }
  return X;
}

void Reader::payloads(const YAML::Node& n, RobotSetup& r) const {
  r.payloads.clear();
  each(list(n, "payloads", "robot.payloads"), [&](const YAML::Node& e) {
    keys(e, "robot.payloads", {"link", "mass_kg", "com", "inertia_kgm2"});
    Payload p;
    p.link = text(required(e, "link", "robot.payloads"), "payload.link");
    p.mass_kg = positive(required(e, "mass_kg", "robot.payloads"), "payload.mass_kg");
    r.where["payloads:" + p.link] = at(e["link"]);
    if (e["com"]) p.com_L = vec3(e["com"], "payload.com");
    if (e["inertia_kgm2"]) p.inertia_kgm2 = vec3(e["inertia_kgm2"], "payload.inertia_kgm2");
    r.payloads.push_back(p);
  });
}

void Reader::loads(const YAML::Node& n, RobotSetup& r) const {
  r.loads.clear();
  each(list(n, "loads", "robot.loads"), [&](const YAML::Node& e) {
    keys(e, "robot.loads", {"joint", "reflected_mass_kg"});
    r.loads.push_back({text(required(e, "joint", "robot.loads"), "load.joint"),
                       positive(required(e, "reflected_mass_kg", "robot.loads"), "load.reflected_mass_kg")});
    r.where["loads:" + r.loads.back().joint] = at(e["joint"]);
  });
}

ControllerSetup Reader::controller(const YAML::Node& n) const {
  keys(n, "controller",
       {"name", "diagram", "parameters", "rate_hz", "delay_s", "scalar", "word_bits", "implementation", "inputs", "outputs"});
  ControllerSetup c;
  if (!n["name"] || !n["diagram"]) fail(n, "controller: expected 'name' and 'diagram'");
  c.where = at(n["name"]);
  c.name = text(n["name"], "controller.name");
  const std::string ctx = "controller '" + c.name + "'";
  optional(n, "diagram", [&](const YAML::Node& d) { c.diagram = path(d, ctx + ".diagram"); });
  optional(n, "parameters", [&](const YAML::Node& p) { c.parameters = named_numbers(p, ctx + ".parameters"); });
  optional(n, "rate_hz", [&](const YAML::Node& r) { c.rate_hz = rate(r, "controller.rate_hz"); });
  optional(n, "delay_s", [&](const YAML::Node& d) {
    const double delay = rd.number_in(d, "controller.delay_s", 0.0, 1e9, "s");
    if (delay > 1.0 / c.rate_hz)
      fail(d, fmt::format("controller.delay_s: {} s is longer than one period of {} Hz ({} s)", delay, c.rate_hz, 1.0 / c.rate_hz));
    c.delay_s = delay;
  });
  optional(n, "scalar", [&](const YAML::Node& s) {
    const std::string t = text(s, "controller.scalar");
    if (t == "double") c.scalar = Scalar::Double;
    else if (t == "float") c.scalar = Scalar::Float;
    else if (t == "fixed") c.scalar = Scalar::Fixed;
    else fail(s, "controller.scalar: expected double, float or fixed, got '" + t + "'");
  });
  optional(n, "word_bits", [&](const YAML::Node& w) {
    c.word_bits = static_cast<int>(integer(w, "controller.word_bits", 16, 32));
    if (c.word_bits != 16 && c.word_bits != 32) fail(w, "controller.word_bits: expected 16 or 32");
  });
  optional(n, "implementation", [&](const YAML::Node& i) {
    const std::string t = text(i, "controller.implementation");
    if (t == "interpreter") c.implementation = Implementation::Interpreter;
    else if (t == "generated") c.implementation = Implementation::Generated;
    else fail(i, "controller.implementation: expected interpreter or generated, got '" + t + "'");
  });
  for (const char* side : {"inputs", "outputs"}) rd.guard([&] { ports(n, side, c); });
  return c;
}

// The controller's program ports bound to bus signals.
void Reader::ports(const YAML::Node& n, const std::string& side, ControllerSetup& c) const {
  const std::string ctx = "controller '" + c.name + "'." + side;
  if (!n[side]) fail(n, "controller '" + c.name + "': expected '" + side + "' (program port: bus signal)");
  if (!n[side].IsMap()) fail(n[side], ctx + ": expected a map of port: signal");
  const bool inputs = side == "inputs";
  for (const auto& kv : n[side]) {
    rd.guard([&] {
      const std::string port = key(kv.first, ctx);
      auto bind = [&](const YAML::Node& signal) {
        (inputs ? c.inputs : c.outputs).emplace_back(port, text(signal, side));
        (inputs ? c.input_where : c.output_where).push_back(at(signal));
      };
      // A port wider than one element: a list of bus signals, one per element in order
      // (its length is checked against the diagram's port when the diagram is loaded).
      if (!kv.second.IsSequence()) return bind(kv.second);
      if (kv.second.size() == 0) fail(kv.second, ctx + "." + port + ": expected a bus signal, or a list of them (one per element)");
      for (const auto& e : kv.second) bind(e);
    });
  }
}

void Reader::integration(const YAML::Node& n, IntegrationSetup& in) const {
  keys(n, "integration", {"mode", "step_s", "accuracy"});
  optional(n, "mode", [&](const YAML::Node& m) {
    const std::string t = text(m, "integration.mode");
    if (t == "fixed") in.mode = model::Integration::Fixed;
    else if (t == "accurate") in.mode = model::Integration::Accurate;
    else fail(m, "integration.mode: expected fixed or accurate, got '" + t + "'");
  });
  optional(n, "step_s", [&](const YAML::Node& s) {
    const double step = positive(s, "integration.step_s");
    if (step > 0.01) fail(s, "integration.step_s: " + fmt::format("{}", step) + " s is longer than 10 ms (expected 0.1 to 2 ms)");
    in.step_s = step;
  });
  optional(n, "accuracy", [&](const YAML::Node& a) {
    const double acc = positive(a, "integration.accuracy");
    if (acc >= 0.1) fail(a, "integration.accuracy: " + fmt::format("{}", acc) + " is not a small relative accuracy (expected 1e-8 to 1e-3)");
    in.accuracy = acc;
  });
}

// Fields a variant may override (everything but frames, plots, experiment).
void Reader::variant_fields(const YAML::Node& n, VariantSetup& v) const {
  optional(n, "robot", [&](const YAML::Node& r) { robot(r, v.robot); });
  optional(n, "controllers", [&](const YAML::Node& cs) {
    v.controllers.clear();
    if (!cs.IsSequence()) fail(cs, "controllers: expected a list");
    each(cs, [&](const YAML::Node& c) { v.controllers.push_back(controller(c)); });
  });
  optional(n, "references", [&](const YAML::Node& rs) {
    v.references.clear();
    if (!rs.IsMap()) fail(rs, "references: expected a map of name: source");
    for (const auto& kv : rs)
      rd.guard([&] {
        const std::string name = key(kv.first, "references");
        v.references.push_back({name, source(kv.second, "reference '" + name + "'"), at(kv.first)});
      });
  });
  optional(n, "forces", [&](const YAML::Node&) { forces(n, v); });
  optional(n, "duration_s", [&](const YAML::Node& d) { v.duration_s = duration(d, "duration_s"); });
  optional(n, "log_rate_hz", [&](const YAML::Node& r) { v.log_rate_hz = rate(r, "log_rate_hz"); });
  optional(n, "sensors", [&](const YAML::Node& s) { sensors(s, v); });
  optional(n, "integration", [&](const YAML::Node& i) { integration(i, v.integration); });
  optional(n, "thermal", [&](const YAML::Node& t) { thermal(t, v); });
  optional(n, "bus_controllers", [&](const YAML::Node& l) { bus_controllers(l, v); });
  for (const char* old : {"osc", "balance"})  // the keys of earlier versions: one bus controller each
    optional(n, old, [&](const YAML::Node& o) {
      note(at(n[old]) + ": '" + old + ":' is deprecated: write bus_controllers: [{type: " + old + ", ...}]");
      bus_controller(o, old, v);
    });
  optional(n, "end_on_fall", [&](const YAML::Node& e) { end_on_fall(e, v); });
  optional(n, "push", [&](const YAML::Node& p) { push(p, v); });
}

// `push`: its keys over those already given (the base's, an earlier axis's).
void Reader::push(const YAML::Node& n, VariantSetup& v) const {
  keys(n, "push", {"link", "point", "direction_deg", "force_N", "duration_s", "start_s", "trigger"});
  PushSetup p = v.push.value_or(PushSetup{});
  p.where = at(n);
  optional(n, "link", [&](const YAML::Node& x) { p.link = text(x, "push.link"); });
  optional(n, "point", [&](const YAML::Node& x) { p.point = vec3(x, "push.point"); });
  optional(n, "direction_deg", [&](const YAML::Node& x) { p.direction_deg = rd.number_in(x, "push.direction_deg", -360.0, 360.0, "deg"); });
  optional(n, "force_N", [&](const YAML::Node& x) { p.force_N = rd.number_in(x, "push.force_N", 0.0, 1e6, "N"); });
  optional(n, "duration_s", [&](const YAML::Node& x) { p.duration_s = positive(x, "push.duration_s"); });
  optional(n, "start_s", [&](const YAML::Node& x) {
    p.start_s = rd.number_in(x, "push.start_s", 0.0, 1e6, "s");
    p.trigger.reset();
  });
  optional(n, "trigger", [&](const YAML::Node& x) {
    p.trigger = trigger(x);
    p.start_s.reset();
  });
  v.push = p;
}

// EndOnFall (simulation.hpp): true, false, or a map of its two thresholds.
void Reader::end_on_fall(const YAML::Node& n, VariantSetup& v) const {
  if (n.IsScalar()) {
    v.end_on_fall = boolean(n, "end_on_fall") ? std::optional<EndOnFall>(EndOnFall{}) : std::nullopt;
    return;
  }
  keys(n, "end_on_fall", {"torso_below_m", "tilt_above_rad"});
  EndOnFall e;
  optional(n, "torso_below_m", [&](const YAML::Node& x) { e.torso_below_m = rd.number_in(x, "end_on_fall.torso_below_m", 0.0, 10.0, "m"); });
  optional(n, "tilt_above_rad", [&](const YAML::Node& x) { e.tilt_above_rad = rd.number_in(x, "end_on_fall.tilt_above_rad", 0.0, M_PI, "rad"); });
  v.end_on_fall = e;
}

void Reader::forces(const YAML::Node& n, VariantSetup& v) const {
  v.forces.clear();
  each(list(n, "forces", "forces"), [&](const YAML::Node& e) {
    keys(e, "force", {"link", "point", "direction", "source", "trigger"});
    ForceSpec f;
    f.link = text(required(e, "link", "force"), "force.link");
    f.where = at(e["link"]);
    if (e["point"]) f.point_L = vec3(e["point"], "force.point");
    if (e["direction"]) f.direction_W = vec3(e["direction"], "force.direction");
    if (!e["source"]) fail(e, "force: expected 'source'");
    f.source = source(e["source"], "force.source");
    optional(e, "trigger", [&](const YAML::Node& t) { f.trigger = trigger(t); });
    v.forces.push_back(f);
  });
}

// A force's `trigger: {signal, occurrence (1), after_s (0)}`.
ForceSpec::Trigger Reader::trigger(const YAML::Node& t) const {
  keys(t, "force.trigger", {"signal", "occurrence", "after_s"});
  ForceSpec::Trigger tr;
  tr.signal = text(required(t, "signal", "force.trigger"), "force.trigger.signal");
  optional(t, "occurrence", [&](const YAML::Node& x) { tr.occurrence = static_cast<int>(integer(x, "force.trigger.occurrence", 1, 1000000000)); });
  optional(t, "after_s", [&](const YAML::Node& x) { tr.after_s = rd.number_in(x, "force.trigger.after_s", 0.0, 1e6, "s"); });
  return tr;
}

void Reader::sensors(const YAML::Node& s, VariantSetup& v) const {
  keys(s, "sensors", {"noise", "seed", "force_noise_N"});
  optional(s, "noise", [&](const YAML::Node& x) { v.sensor_noise = boolean(x, "sensors.noise"); });
  optional(s, "seed", [&](const YAML::Node& x) { v.seed = static_cast<uint64_t>(integer(x, "sensors.seed", 0, kMaxExactInteger)); });
  optional(s, "force_noise_N", [&](const YAML::Node& x) { v.force_noise_N = rd.number_in(x, "sensors.force_noise_N", 0.0, 1e9, "N"); });
}

void Reader::thermal(const YAML::Node& t, VariantSetup& v) const {
  keys(t, "thermal", {"cooling"});
  if (!t["cooling"]) fail(t, "thermal: expected 'cooling: on, off or both'");
  const std::string c = t["cooling"].IsScalar() ? t["cooling"].Scalar() : "";
  if (c == "on" || c == "true") v.cooling = Cooling::On;
  else if (c == "off" || c == "false") v.cooling = Cooling::Off;
  else if (c == "both") v.cooling = Cooling::Both;
  else fail(t["cooling"], "thermal.cooling: expected on, off or both");
}

}  // namespace detail

namespace {

using namespace detail;

const std::initializer_list<const char*> kVariantKeys = {"name", "robot", "controllers", "references", "forces", "duration_s", "log_rate_hz",
                                                         "sensors", "thermal", "integration", "bus_controllers", "osc", "balance", "end_on_fall",
                                                         "push"};

// A matrix value may also give `value`: its number on the axis (sweep_plots' x).
const std::initializer_list<const char*> kMatrixValueKeys = {"name", "value", "robot", "controllers", "references", "forces", "duration_s",
                                                             "log_rate_hz", "sensors", "thermal", "integration", "bus_controllers", "osc",
                                                             "balance", "end_on_fall", "push"};

void read_variants(const Reader& rd, const YAML::Node& list, const VariantSetup& base, Scenario& s) {
  if (!list.IsSequence()) rd.fail(list, "variants: expected a list");
  rd.each(list, [&](const YAML::Node& n) {
    rd.keys(n, "variant", kVariantKeys);
    VariantSetup v = base;
    if (!n["name"]) rd.fail(n, "variant: expected 'name'");
    v.name = rd.text(n["name"], "variant.name");
    rd.variant_fields(n, v);
    s.variants.push_back(v);
  });
}

// "file:line:col" (Fields::at) back into a Location.
Location location_of(const std::string& where) {
  const auto c2 = where.rfind(':'), c1 = c2 == std::string::npos ? c2 : where.rfind(':', c2 - 1);
  if (c1 == std::string::npos) return {where, 0, 0};
  return {where.substr(0, c1), std::atoi(where.substr(c1 + 1, c2 - c1 - 1).c_str()), std::atoi(where.substr(c2 + 1).c_str())};
}

// A variant's merged `push` as one more force: a step of force_N for duration_s along the
// horizontal direction, from start_s or from its trigger. Every key but point is needed.
// force_N 0 (the unpushed reference) keeps the force with a zero direction: nothing
// pushes, but its trigger is watched and its start logged (forces.K.start_s), so the
// reference run knows when the push would have come.
void append_push(const Reader& rd, VariantSetup& v) {
  if (!v.push) return;
  const PushSetup& p = *v.push;
  const Location at = location_of(p.where);
  std::vector<std::string> missing;
  if (!p.link) missing.push_back("link");
  if (!p.direction_deg) missing.push_back("direction_deg");
  if (!p.force_N) missing.push_back("force_N");
  if (!p.duration_s) missing.push_back("duration_s");
  if (!p.start_s && !p.trigger) missing.push_back("start_s or trigger");
  if (!missing.empty())
    rd.rd.fail(at, "variant '" + v.name + "': push: missing " + join(missing) + " (after the base, the variant and the matrix axes)");
  ForceSpec f;
  f.link = *p.link;
  f.point_L = p.point.value_or(Eigen::Vector3d::Zero());
  const double a = *p.direction_deg * M_PI / 180.0;
  f.direction_W = *p.force_N == 0 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
  f.source.kind = Source::Kind::Steps;
  const double t0 = p.start_s.value_or(0.0);
  f.source.steps = {{t0, *p.force_N}, {t0 + *p.duration_s, 0.0}};
  f.trigger = p.trigger;
  f.where = p.where;
  v.forces.push_back(f);
}

// Every combination of one value per axis, named "a/b/...".
void read_matrix(const Reader& rd, const YAML::Node& matrix, const VariantSetup& base, Scenario& s) {
  if (!matrix.IsMap()) rd.fail(matrix, "matrix: expected a map of axis: [values]");
  s.variants.push_back(base);
  s.variants.back().name.clear();
  for (const auto& axis : matrix) {
    const std::string an = rd.key(axis.first, "matrix");
    if (!axis.second.IsSequence() || axis.second.size() == 0) rd.fail(axis.second, "matrix." + an + ": expected a list of values");
    if (s.variants.size() * axis.second.size() > kMaxVariants)
      rd.fail(axis.first, fmt::format("matrix.{}: {} variants (more than {}): split the scenario", an,
                                       s.variants.size() * axis.second.size(), kMaxVariants));
    std::vector<VariantSetup> next;
    for (const VariantSetup& prev : s.variants)
      for (const auto& n : axis.second) {
        rd.keys(n, "matrix." + an, kMatrixValueKeys);
        if (!n["name"]) rd.fail(n, "matrix." + an + ": each value needs a 'name'");
        VariantSetup v = prev;
        const std::string vn = rd.text(n["name"], "name");
        v.name = prev.name.empty() ? vn : prev.name + "/" + vn;
        v.axes.emplace_back(an, vn);
        if (n["value"]) v.axis_values.emplace_back(an, rd.number(n["value"], "matrix." + an + "." + vn + ".value"));
        rd.variant_fields(n, v);
        next.push_back(v);
      }
    s.variants = next;
  }
}

void read_frames(const Reader& rd, const YAML::Node& f, const std::set<std::string>& variants, FrameSetup& frames) {
  if (f.IsScalar()) {
    frames.enabled = rd.boolean(f, "frames");
    return;
  }
  rd.keys(f, "frames", {"enabled", "fps", "width", "height", "max_frames", "camera", "variant"});
  rd.optional(f, "enabled", [&](const YAML::Node& x) { frames.enabled = rd.boolean(x, "frames.enabled"); });
  rd.optional(f, "fps", [&](const YAML::Node& x) { frames.fps = rd.positive(x, "frames.fps"); });
  rd.optional(f, "width", [&](const YAML::Node& x) { frames.width_px = static_cast<int>(rd.integer(x, "frames.width", 1, kMaxFramePixels)); });
  rd.optional(f, "height", [&](const YAML::Node& x) { frames.height_px = static_cast<int>(rd.integer(x, "frames.height", 1, kMaxFramePixels)); });
  rd.optional(f, "max_frames", [&](const YAML::Node& x) { frames.max_frames = static_cast<int>(rd.integer(x, "frames.max_frames", 1, kMaxFrames)); });
  rd.optional(f, "camera", [&](const YAML::Node& c) {
    rd.keys(c, "frames.camera", {"position", "look_at"});
    if (c["position"]) frames.camera_position = rd.vec3(c["position"], "frames.camera.position");
    if (c["look_at"]) frames.camera_look_at = rd.vec3(c["look_at"], "frames.camera.look_at");
  });
  rd.optional(f, "variant", [&](const YAML::Node& x) {
    frames.variant = rd.text(x, "frames.variant");
    if (!variants.count(frames.variant)) rd.fail(x, "frames.variant: no variant is named '" + frames.variant + "'");
  });
}

void read_plots(const Reader& rd, const YAML::Node& root, std::vector<PlotSetup>& plots) {
  rd.each(rd.list(root, "plots", "plots"), [&](const YAML::Node& p) {
    rd.keys(p, "plot", {"title", "y_label", "file", "signals"});
    PlotSetup ps;
    if (p["title"]) ps.title = rd.text(p["title"], "plot.title");
    if (p["y_label"]) ps.y_label = rd.text(p["y_label"], "plot.y_label");
    if (!p["file"] || !p["signals"]) rd.fail(p, "plot: expected 'file' and 'signals'");
    ps.file = rd.text(p["file"], "plot.file");
    ps.signals = rd.names(p["signals"], "plot.signals");
    plots.push_back(ps);
  });
}

Scenario read_scenario(const Reader& rd, const YAML::Node& root, const std::string& path) {
  if (!root.IsMap()) rd.rd.fail(Location{path, 1, 1}, "a scenario is a map (name, robot, controllers, ...)");
  // Unknown keys are reported and the rest is read all the same.
  rd.rd.keys(root, {"name", "description", "robot", "controllers", "references", "forces", "duration_s", "log_rate_hz", "sensors",
                    "thermal", "integration", "bus_controllers", "osc", "balance", "end_on_fall", "push", "frames", "plots", "sweep_plots", "log",
                    "log_only", "variants", "matrix", "experiment"},
             "scenario");
  Scenario s;
  s.file = path;
  s.name = fs::path(path).stem().string();
  rd.optional(root, "name", [&](const YAML::Node& n) { s.name = rd.text(n, "name"); });
  rd.optional(root, "description", [&](const YAML::Node& n) { s.description = rd.text(n, "description"); });
  VariantSetup base;
  base.name = "base";
  rd.variant_fields(root, base);
  if (root["variants"] && root["matrix"]) rd.fail(root["matrix"], "give either 'variants' or 'matrix', not both");
  if (root["variants"]) rd.optional(root, "variants", [&](const YAML::Node& l) { read_variants(rd, l, base, s); });
  else if (root["matrix"]) rd.optional(root, "matrix", [&](const YAML::Node& m) { read_matrix(rd, m, base, s); });
  else s.variants.push_back(base);
  for (auto& v : s.variants) rd.rd.guard([&] { append_push(rd, v); });
  std::set<std::string> seen;
  for (const auto& v : s.variants)
    if (!seen.insert(v.name).second) rd.rd.error(Location{path, 0, 0}, "two variants are named '" + v.name + "'");
  // No robot is built in: each variant's must be named (a robot folder) or given (a URDF).
  for (const auto& v : s.variants)
    if (v.robot.urdf.empty() && !rd.rd.failed())
      rd.rd.error(root["robot"] ? rd.rd.at(root["robot"]) : Location{path, 1, 1},
                  "robot: expected 'name' (a robot folder: robots/NAME) or 'urdf' (a URDF file)");
  rd.optional(root, "frames", [&](const YAML::Node& f) { read_frames(rd, f, seen, s.frames); });
  rd.optional(root, "plots", [&](const YAML::Node&) { read_plots(rd, root, s.plots); });
  rd.optional(root, "sweep_plots", [&](const YAML::Node& l) { read_sweep_plots(rd, l, root["matrix"], s.sweep_plots); });
  rd.optional(root, "log", [&](const YAML::Node& l) { s.log_signals = rd.names(l, "log"); });
  rd.optional(root, "log_only", [&](const YAML::Node& l) {
    std::map<std::string, std::string> where;
    for (const std::string& pattern : rd.names(l, "log_only", &where, "log_only")) s.log_only.push_back({pattern, where["log_only:" + pattern]});
  });
  s.experiment.file = path;
  rd.optional(root, "experiment", [&](const YAML::Node& e) { rd.experiment(e, s.experiment); });
  return s;
}

}  // namespace

Scenario load_scenario(const std::string& path) {
  std::string bytes;
  if (const auto reason = try_read_text_file(path, bytes)) throw InputError(path + ": cannot read the scenario file: " + *reason);
  const Reader rd(yaml::Reader(path, blocks::expression_numbers()), fs::path(path).parent_path().string());
  Scenario s;
  rd.rd.guard([&] { s = read_scenario(rd, rd.rd.parse(bytes), path); });
  if (rd.rd.failed()) throw InputError(join_plain(rd.rd.diagnostics()));
  s.notes = rd.notes;
  return s;
}

}  // namespace dmbd::scenario
