// The actuator file (format 1, docs/actuator-format.md) through the located YAML reader,
// and the table's checks against the robot it is for.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "dmbd/base/strings.hpp"
#include "dmbd/base/file.hpp"
#include "dmbd/base/number_text.hpp"
#include "dmbd/base/yaml_reader.hpp"
#include "dmbd/model/actuator.hpp"
#include "dmbd/model/error.hpp"
#include "dmbd/model/robot_description.hpp"

namespace dmbd::model {

namespace {


enum class Check { Any, Positive, NonNegative, Fraction, Sign, Whole };

// The keys an entry of each kind may have (docs/actuator-format.md). Every kind:
const std::vector<std::string> kCommonKeys = {"joint",           "kind",       "J_m_kgm2", "k_tau_Nm_per_A",
                                              "current_limit_A", "efficiency", "thermal",  "motor_encoder",
                                              "load",            "load_sets"};
// The VLCAs' (M_r_kg: RFSEA only) and the rotary kinds' (K_s, B_s, spring_encoder:
// ROTARY_SEA only).
const std::vector<std::string> kVlcaKeys = {"B_m_Nms",      "N_m_rad_per_m", "K_s_N_per_m",    "B_s_Ns_per_m",
                                            "M_r_kg",       "force_limit_N", "linkage",        "spring_encoder",
                                            "potentiometer"};
const std::vector<std::string> kRotaryKeys = {"B_m_Nms",         "gear_ratio",          "torque_limit_Nm",
                                              "viscous_friction_Nms", "coulomb_friction_Nm", "coulomb_velocity_rad_s",
                                              "K_s_Nm_per_rad",  "B_s_Nms_per_rad",     "spring_encoder",
                                              "potentiometer"};

std::vector<std::string> keys_of(ActuatorKind k) {
  std::vector<std::string> keys = kCommonKeys;
  const bool rotary = k == ActuatorKind::ROTARY || k == ActuatorKind::ROTARY_SEA;
  for (const std::string& key : rotary ? kRotaryKeys : kVlcaKeys) {
    if (key == "M_r_kg" && k != ActuatorKind::RFSEA) continue;
    if ((key == "K_s_Nm_per_rad" || key == "B_s_Nms_per_rad" || key == "spring_encoder") && k == ActuatorKind::ROTARY)
      continue;
    keys.push_back(key);
  }
  return keys;
}

// The kinds (as the file writes them) whose entries may have `key`.
std::vector<std::string> kinds_with(const std::string& key) {
  std::vector<std::string> out;
  for (ActuatorKind k : {ActuatorKind::RFSEA, ActuatorKind::FSEA, ActuatorKind::ROTARY, ActuatorKind::ROTARY_SEA}) {
    const auto keys = keys_of(k);
    if (std::find(keys.begin(), keys.end(), key) != keys.end()) out.push_back(kind_name(k));
  }
  return out;
}

// rfsea, fsea, rotary, rotary_sea; today's upper-case RFSEA and FSEA too.
bool parse_kind(const std::string& s, ActuatorKind& k) {
  if (s == "rfsea" || s == "RFSEA") k = ActuatorKind::RFSEA;
  else if (s == "fsea" || s == "FSEA") k = ActuatorKind::FSEA;
  else if (s == "rotary") k = ActuatorKind::ROTARY;
  else if (s == "rotary_sea") k = ActuatorKind::ROTARY_SEA;
  else return false;
  return true;
}

// The file through the located YAML reader: every problem collected, each at its
// file:line:column.
class Reader {
 public:
  Reader(std::string path, NumberParser numbers) : rd_(std::move(path), std::move(numbers)) {}

  std::vector<ActuatorParams> run(const std::string& bytes) {
    std::vector<ActuatorParams> out;
    rd_.guard([&] { out = table(rd_.parse(bytes)); });
    if (rd_.failed()) throw ModelError(join_plain(rd_.diagnostics()));
    return out;
  }

 private:
  std::vector<ActuatorParams> table(const YAML::Node& root) {
    const std::string expected = "expected a map with the keys 'format' (1) and 'actuators' (a list of actuators)";
    if (root.IsNull() || !root.IsDefined()) rd_.fail(Location{rd_.file(), 1, 1}, expected + ", got an empty file");
    if (!root.IsMap()) fail(root, expected);
    keys(root, {"format", "actuators"}, "", "top-level key");
    format(root);
    const YAML::Node list = root["actuators"];
    if (!list) rd_.fail(Location{rd_.file(), 1, 1}, "missing 'actuators' (a list of actuators)");
    if (!list.IsSequence() || list.size() == 0) fail(list, "'actuators' must be a non-empty list of actuators");
    std::vector<ActuatorParams> out;
    std::map<std::string, int> first_line;  // joint -> line of its first entry
    for (const YAML::Node& e : list) {
      rd_.guard([&] {
        distinct_joint(e, first_line);
        out.push_back(actuator(e));
      });
    }
    return out;
  }

  // `format: 1`, required: the version of this contract.
  void format(const YAML::Node& root) {
    const YAML::Node f = root["format"];
    if (!f) rd_.fail(Location{rd_.file(), 1, 1}, "missing 'format: 1' (the actuator file's format version, first key of the file)");
    if (!f.IsScalar()) fail(f, "'format' must be a version number (this version of dmbd reads format 1)");
    if (f.Scalar() != "1")
      fail(f, "unknown format " + yaml::quoted(f.Scalar()) + " (this version of dmbd reads format 1)");
  }

  // A joint's second entry is an error at its 'joint', naming the first's line.
  void distinct_joint(const YAML::Node& e, std::map<std::string, int>& first_line) {
    if (!e.IsMap() || !e["joint"] || !e["joint"].IsScalar()) return;  // actuator() reports it
    const YAML::Node j = e["joint"];
    const auto [it, fresh] = first_line.emplace(j.Scalar(), rd_.at(e).line);
    if (!fresh)
      fail(j, "joint '" + j.Scalar() + "' has a second actuator (the first is at line " + std::to_string(it->second) + ")");
  }

  [[noreturn]] void fail(const YAML::Node& n, const std::string& what) { rd_.fail(n, what); }

  // Every key of `map` must be in `allowed`, once. Messages: "[ctx: ]unknown WHAT 'k' (...)".
  // A map with a wrong key is left (Skip): its "missing" keys may be the misspelt ones.
  void keys(const YAML::Node& map, const std::vector<std::string>& allowed, const std::string& ctx, const std::string& what) {
    if (!rd_.keys(map, allowed, ctx, what)) throw yaml::Skip{};
  }

  // An entry's keys for its kind: a key of another kind is named as such, any other
  // unknown key lists the kind's keys.
  void entry_keys(const YAML::Node& e, ActuatorKind kind, const std::string& ctx) {
    std::vector<std::string> allowed = keys_of(kind);
    bool ok = true;
    for (const auto& kv : e) {
      if (!kv.first.IsScalar() || std::count(allowed.begin(), allowed.end(), kv.first.Scalar())) continue;
      const std::string& k = kv.first.Scalar();
      const std::vector<std::string> kinds = kinds_with(k);
      if (kinds.empty()) continue;  // unknown to every kind: rd_.keys reports it
      rd_.error(rd_.at(kv.first), ctx + ": '" + k + "' applies to kind " + join(kinds) + " only, not " + kind_name(kind));
      allowed.push_back(k);  // reported once
      ok = false;
    }
    keys(e, allowed, ctx, "key");
    if (!ok) throw yaml::Skip{};
  }

  YAML::Node require(const YAML::Node& map, const std::string& key, const std::string& ctx) {
    const YAML::Node n = map[key];
    if (!n) fail(map, ctx + ": missing '" + key + "'");
    return n;
  }

  // map[key] as a number that passes `check`; NaN (and the problem recorded) if not.
  double number(const YAML::Node& map, const std::string& key, const std::string& ctx, Check check, const char* unit) {
    double v = NAN;
    rd_.guard([&] {
      const std::string u = unit[0] ? std::string(" (") + unit + ")" : std::string();
      const YAML::Node n = require(map, key, ctx);
      const double got = rd_.number(n, ctx + ": '" + key + "'" + u);
      if (const std::string why = violation(check, got); !why.empty())
        fail(n, ctx + ": '" + key + "' must be " + why + (check == Check::Positive || check == Check::NonNegative ? u : "") +
                    ", got " + number_text(got));
      v = got;
    });
    return v;
  }

  // An optional key: `fallback` when absent.
  double optional(const YAML::Node& map, const std::string& key, const std::string& ctx, Check check, const char* unit,
                  double fallback) {
    return map[key] ? number(map, key, ctx, check, unit) : fallback;
  }

  static std::string violation(Check check, double v) {
    switch (check) {
      case Check::Any: return "";
      case Check::Positive: return v > 0 ? "" : "> 0";
      case Check::NonNegative: return v >= 0 ? "" : ">= 0";
      case Check::Fraction: return (v > 0 && v <= 1) ? "" : "in (0, 1]";
      case Check::Sign: return (v == 1.0 || v == -1.0) ? "" : "+1 or -1";
      case Check::Whole: return (v == std::floor(v) && v >= 1 && v <= 30) ? "" : "a whole number 1..30";
    }
    return "";
  }

  YAML::Node submap(const YAML::Node& map, const std::string& key, const std::string& ctx,
                    const std::vector<std::string>& allowed) {
    const YAML::Node n = require(map, key, ctx);
    if (!n.IsMap()) fail(n, ctx + ": '" + key + "' must be a map with the keys " + join(allowed));
    keys(n, allowed, ctx, key + " key");
    return n;
  }

  ActuatorParams actuator(const YAML::Node& e) {
    if (!e.IsMap()) fail(e, "expected an actuator: a map with the keys joint, kind and those of its kind");
    ActuatorParams p;
    p.where = rd_.at(e).str();
    // joint and kind first: the other messages name them, and the kind sets the keys.
    const YAML::Node j = e["joint"];
    if (!j) fail(e, "actuator: missing 'joint' (the URDF joint it drives)");
    if (!j.IsScalar() || j.Scalar().empty()) fail(j, "actuator: 'joint' must be a joint name");
    p.joint = j.Scalar();
    const std::string ctx = "actuator '" + p.joint + "'";
    const YAML::Node k = require(e, "kind", ctx);
    if (!k.IsScalar() || !parse_kind(k.Scalar(), p.kind))
      fail(k, ctx + ": unknown kind '" + (k.IsScalar() ? k.Scalar() : std::string("?")) +
                  "' (expected rfsea, fsea, rotary or rotary_sea)");
    entry_keys(e, p.kind, ctx);

    p.J_m_kgm2 = number(e, "J_m_kgm2", ctx, Check::Positive, "kg m^2");
    p.k_tau_Nm_per_A = number(e, "k_tau_Nm_per_A", ctx, Check::Positive, "N m/A");
    p.current_limit_A = number(e, "current_limit_A", ctx, Check::Positive, "A");
    p.efficiency = number(e, "efficiency", ctx, Check::Fraction, "");
    if (p.is_rotary()) rotary(e, ctx, p);
    else vlca(e, ctx, p);
    load(e, ctx, p);
    load_sets(e, ctx, p);
    thermal(e, ctx, p.thermal);
    const YAML::Node me = submap(e, "motor_encoder", ctx, {"counts_per_unit"});
    p.motor_encoder.counts_per_unit = number(me, "counts_per_unit", ctx + " motor_encoder", Check::Positive, "counts/rad");
    if (p.has_spring()) {
      const YAML::Node se = submap(e, "spring_encoder", ctx, {"counts_per_unit"});
      p.spring_encoder.counts_per_unit = number(se, "counts_per_unit", ctx + " spring_encoder", Check::Positive,
                                                p.is_rotary() ? "counts/rad" : "counts/m");
    }
    p.has_potentiometer = !p.is_rotary() || e["potentiometer"];
    if (p.has_potentiometer) potentiometer(e, ctx, p.potentiometer);
    return p;
  }

  // RFSEA and FSEA: the ball screw on its linkage, every key required (M_r_kg: RFSEA only).
  void vlca(const YAML::Node& e, const std::string& ctx, ActuatorParams& p) {
    p.B_m_Nms = number(e, "B_m_Nms", ctx, Check::NonNegative, "N m s/rad");
    p.N_m_rad_per_m = number(e, "N_m_rad_per_m", ctx, Check::Positive, "rad/m");
    p.K_s_N_per_m = number(e, "K_s_N_per_m", ctx, Check::Positive, "N/m");
    p.B_s_Ns_per_m = number(e, "B_s_Ns_per_m", ctx, Check::NonNegative, "N s/m");
    p.M_r_kg = p.kind == ActuatorKind::RFSEA ? number(e, "M_r_kg", ctx, Check::Positive, "kg") : 0.0;
    p.force_limit_N = number(e, "force_limit_N", ctx, Check::Positive, "N");
    const YAML::Node l = submap(e, "linkage", ctx, {"a_m", "b_m", "gamma0_rad", "sign"});
    const std::string lc = ctx + " linkage";
    p.linkage.a_m = number(l, "a_m", lc, Check::Positive, "m");
    p.linkage.b_m = number(l, "b_m", lc, Check::Positive, "m");
    p.linkage.gamma0_rad = number(l, "gamma0_rad", lc, Check::Any, "rad");
    p.linkage.sign = number(l, "sign", lc, Check::Sign, "");
  }

  // ROTARY and ROTARY_SEA: the gear, its friction at the output and (SEA) the torsion spring.
  void rotary(const YAML::Node& e, const std::string& ctx, ActuatorParams& p) {
    p.B_m_Nms = optional(e, "B_m_Nms", ctx, Check::NonNegative, "N m s/rad", 0.0);
    p.N_m_rad_per_m = number(e, "gear_ratio", ctx, Check::Positive, "motor rad per joint rad");
    p.torque_limit_Nm = number(e, "torque_limit_Nm", ctx, Check::Positive, "N m");
    p.viscous_friction_Nms = number(e, "viscous_friction_Nms", ctx, Check::NonNegative, "N m s/rad");
    p.coulomb_friction_Nm = number(e, "coulomb_friction_Nm", ctx, Check::NonNegative, "N m");
    p.coulomb_velocity_rad_s = optional(e, "coulomb_velocity_rad_s", ctx, Check::Positive, "rad/s", 1e-3);
    p.M_r_kg = 0.0;
    p.K_s_N_per_m = p.B_s_Ns_per_m = 0.0;  // ROTARY: no spring
    if (p.has_spring()) {
      p.K_s_N_per_m = number(e, "K_s_Nm_per_rad", ctx, Check::Positive, "N m/rad");
      p.B_s_Ns_per_m = number(e, "B_s_Nms_per_rad", ctx, Check::NonNegative, "N m s/rad");
    }
  }

  // The output-side load terms, optional: `load: {B_l_Ns_per_m: ...}` (VLCA, along the
  // actuator) or `load: {B_l_Nms_per_rad: ...}` (rotary, at the joint), 0 when absent.
  void load(const YAML::Node& e, const std::string& ctx, ActuatorParams& p) {
    const std::string key = p.is_rotary() ? "B_l_Nms_per_rad" : "B_l_Ns_per_m";
    p.B_l_Ns_per_m = 0.0;
    if (!e["load"]) return;
    const YAML::Node l = submap(e, "load", ctx, {key});
    p.B_l_Ns_per_m = optional(l, key, ctx + " load", Check::NonNegative, p.is_rotary() ? "N m s/rad" : "N s/m", 0.0);
  }

  // Named alternatives to `load:`, optional: `load_sets: {NAME: {the load keys}}` (a
  // robot's output damping beside the test stand's). A key left out of a set is 0, as
  // in `load:`.
  void load_sets(const YAML::Node& e, const std::string& ctx, ActuatorParams& p) {
    if (!e["load_sets"]) return;
    const YAML::Node sets = e["load_sets"];
    const std::string key = p.is_rotary() ? "B_l_Nms_per_rad" : "B_l_Ns_per_m";
    if (!sets.IsMap() || sets.size() == 0) fail(sets, ctx + ": 'load_sets' must be a map of named load terms, e.g. {robot: {" + key + ": 4000}}");
    for (const auto& kv : sets) {
      const std::string name = kv.first.Scalar();
      for (const auto& earlier : p.load_sets)
        if (earlier.name == name) fail(kv.first, ctx + " load_sets: '" + name + "' is given twice (first at " + earlier.where + ")");
      if (!kv.second.IsMap()) fail(kv.second, ctx + " load_sets: '" + name + "' must be a map with the key " + key);
      keys(kv.second, {key}, ctx + " load_sets '" + name + "'", "key");
      const double b = optional(kv.second, key, ctx + " load_sets '" + name + "'", Check::NonNegative,
                                p.is_rotary() ? "N m s/rad" : "N s/m", 0.0);
      p.load_sets.push_back({name, b, rd_.at(kv.first).str()});
    }
  }

  void thermal(const YAML::Node& e, const std::string& ctx, ThermalParams& th) {
    const YAML::Node t =
        submap(e, "thermal", ctx,
               {"R_winding_ohm", "alpha_per_K", "C_winding_J_per_K", "C_housing_J_per_K", "R_wh_K_per_W",
                "R_ha_air_K_per_W", "R_ha_liquid_K_per_W", "T_ambient_C", "T_winding_max_C"});
    const std::string tc = ctx + " thermal";
    th.R_winding_ohm = number(t, "R_winding_ohm", tc, Check::Positive, "ohm at 20 C");
    th.alpha_per_K = number(t, "alpha_per_K", tc, Check::NonNegative, "1/K");
    th.C_winding_J_per_K = number(t, "C_winding_J_per_K", tc, Check::Positive, "J/K");
    th.C_housing_J_per_K = number(t, "C_housing_J_per_K", tc, Check::Positive, "J/K");
    th.R_wh_K_per_W = number(t, "R_wh_K_per_W", tc, Check::Positive, "K/W");
    th.R_ha_air_K_per_W = number(t, "R_ha_air_K_per_W", tc, Check::Positive, "K/W");
    th.R_ha_liquid_K_per_W = number(t, "R_ha_liquid_K_per_W", tc, Check::Positive, "K/W");
    th.T_ambient_C = number(t, "T_ambient_C", tc, Check::Any, "C");
    th.T_winding_max_C = number(t, "T_winding_max_C", tc, Check::Any, "C");
    if (th.T_winding_max_C <= th.T_ambient_C) fail(t["T_winding_max_C"], tc + ": 'T_winding_max_C' must be above 'T_ambient_C'");
  }

  void potentiometer(const YAML::Node& e, const std::string& ctx, PotentiometerParams& pot) {
    const YAML::Node pm = submap(e, "potentiometer", ctx, {"lo", "hi", "adc_bits", "noise_std", "cutoff_hz"});
    const std::string pc = ctx + " potentiometer";
    pot.lo = number(pm, "lo", pc, Check::Any, "rad");
    pot.hi = number(pm, "hi", pc, Check::Any, "rad");
    if (pot.hi <= pot.lo) fail(pm["hi"], pc + ": 'hi' must be above 'lo'");
    const double bits = number(pm, "adc_bits", pc, Check::Whole, "");
    pot.adc_bits = std::isfinite(bits) ? static_cast<int>(bits) : 0;
    pot.noise_std = number(pm, "noise_std", pc, Check::NonNegative, "rad");
    pot.cutoff_hz = number(pm, "cutoff_hz", pc, Check::NonNegative, "Hz");
  }

  yaml::Reader rd_;
};


}  // namespace

std::vector<ActuatorParams> load_actuators(const std::string& yaml_path, const NumberParser& numbers) {
  std::string bytes;
  if (const auto reason = try_read_text_file(yaml_path, bytes))
    throw ModelError(yaml_path + ": cannot read: " + *reason + " (expected a YAML actuator file)");
  return Reader(yaml_path, numbers).run(bytes);
}


void check_actuators_against(const std::vector<ActuatorParams>& table, const RobotDescription& robot) {
  std::string problems;
  const std::string robot_name = "robot '" + robot.name + "'" + (robot.source.empty() ? "" : " (" + robot.source + ")");
  for (const ActuatorParams& p : table) {
    const std::string at = (p.where.empty() ? std::string("actuator table") : p.where) + ": actuator '" + p.joint + "': ";
    const int j = robot.joint_index(p.joint);
    std::string why;
    if (j < 0) {
      why = "the " + robot_name + " has no joint '" + p.joint + "'";
    } else {
      const JointType t = robot.joints[static_cast<std::size_t>(j)].type;
      if (t == JointType::Fixed) why = "joint '" + p.joint + "' of the " + robot_name + " is fixed: it cannot move";
      else if (t != JointType::Revolute && t != JointType::Continuous)
        why = "joint '" + p.joint + "' of the " + robot_name + " is " + joint_type_name(t) +
              "; an actuator drives a revolute or continuous joint";
    }
    if (!why.empty()) problems += (problems.empty() ? "" : "\n") + at + why;
  }
  if (!problems.empty()) throw ModelError(problems);
}

std::vector<std::string> joints_without_actuator(const std::vector<ActuatorParams>& table, const RobotDescription& robot) {
  std::vector<std::string> out;
  for (const Joint& j : robot.joints) {
    const bool moves = j.type == JointType::Revolute || j.type == JointType::Continuous || j.type == JointType::Prismatic;
    const bool driven = std::any_of(table.begin(), table.end(), [&](const ActuatorParams& p) { return p.joint == j.name; });
    if (moves && !driven) out.push_back(j.name);
  }
  return out;
}

}  // namespace dmbd::model
