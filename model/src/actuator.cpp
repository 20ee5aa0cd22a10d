// VLCA actuators without a multibody engine: the two-pivot linkage, its firmware-style
// lookup table (natural cubic spline of N_l(q)) and the per-joint parameter table read
// from YAML (format: docs/model.md, "Parameter table").
#include "dmbd/model/actuator.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "dmbd/base/file.hpp"
#include "dmbd/base/number_text.hpp"
#include "dmbd/base/yaml_reader.hpp"
#include "dmbd/model/error.hpp"

namespace dmbd::model {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

// ---- LinkageGeometry ------------------------------------------------------------------

double LinkageGeometry::length_m(double q) const {
  const double g = gamma0_rad + sign * q;
  return std::sqrt(a_m * a_m + b_m * b_m - 2.0 * a_m * b_m * std::cos(g));
}

double LinkageGeometry::moment_arm_m(double q) const {
  const double g = gamma0_rad + sign * q;
  return sign * a_m * b_m * std::sin(g) / length_m(q);
}

double LinkageGeometry::dmoment_arm_dq_m(double q) const {
  // d/dq (sign ab sin g / x) with dg/dq = sign, dx/dq = sign ab sin g / x; sign^2 = 1:
  //   ab cos g / x - (ab sin g)^2 / x^3.
  const double g = gamma0_rad + sign * q;
  const double x = length_m(q);
  const double s = a_m * b_m * std::sin(g);
  return a_m * b_m * std::cos(g) / x - s * s / (x * x * x);
}

double LinkageGeometry::N_l(double q) const { return 1.0 / moment_arm_m(q); }

double LinkageGeometry::angle_for_length_change(double dx, double guess) const {
  const double target = length_m(0) + dx;
  double q = guess;
  for (int it = 0; it < 30; ++it) {
    const double step = (length_m(q) - target) / moment_arm_m(q);
    q -= step;
    if (std::abs(step) < 1e-13) break;
  }
  return q;
}

// ---- LinkageTable ---------------------------------------------------------------------

LinkageTable::LinkageTable(const LinkageGeometry& g, double q_lo, double q_hi, int samples) {
  if (samples < 2) throw ModelError("linkage table: needs at least 2 samples, got " + std::to_string(samples));
  if (!(q_hi > q_lo) || !std::isfinite(q_lo) || !std::isfinite(q_hi))
    throw ModelError("linkage table: needs q_hi > q_lo, got [" + std::to_string(q_lo) + ", " + std::to_string(q_hi) +
                     "]");
  if (!(g.a_m > 0) || !(g.b_m > 0) || !(g.sign == 1.0 || g.sign == -1.0))
    throw ModelError("linkage table: needs a_m > 0, b_m > 0 and sign +1 or -1");
  // The moment arm vanishes where gamma is a multiple of pi (the pivots and the joint axis
  // in line): the range must not reach one.
  const double g_a = g.gamma0_rad + g.sign * q_lo, g_b = g.gamma0_rad + g.sign * q_hi;
  const double g_min = std::min(g_a, g_b), g_max = std::max(g_a, g_b);
  const double k = std::floor(g_min / kPi);
  if (!(g_min > k * kPi) || !(g_max < (k + 1) * kPi))
    throw ModelError("linkage table: the linkage is singular over [" + std::to_string(q_lo) + ", " +
                     std::to_string(q_hi) + "] rad (gamma = gamma0 + sign q reaches a multiple of pi)");
  q_lo_ = q_lo;
  q_hi_ = q_hi;
  const int n = samples;
  h_ = (q_hi - q_lo) / (n - 1);
  n_.resize(n);
  for (int i = 0; i < n; ++i) n_[i] = g.N_l(i == n - 1 ? q_hi : q_lo + i * h_);
  // Natural spline: m_0 = m_{n-1} = 0 and, for the interior,
  //   m_{i-1} + 4 m_i + m_{i+1} = 6 (y_{i+1} - 2 y_i + y_{i-1}) / h^2   (Thomas algorithm).
  m_.assign(n, 0.0);
  if (n > 2) {
    std::vector<double> c(n, 0.0), d(n, 0.0);
    for (int i = 1; i < n - 1; ++i) {
      const double rhs = 6.0 * (n_[i + 1] - 2.0 * n_[i] + n_[i - 1]) / (h_ * h_);
      const double denom = 4.0 - (i > 1 ? c[i - 1] : 0.0);
      c[i] = 1.0 / denom;
      d[i] = (rhs - (i > 1 ? d[i - 1] : 0.0)) / denom;
    }
    for (int i = n - 2; i >= 1; --i) m_[i] = d[i] - c[i] * m_[i + 1];
  }
}

double LinkageTable::N_l(double q) const {
  const int n = static_cast<int>(n_.size());
  if (n == 0) return 0.0;
  if (n == 1) return n_[0];
  const double qc = std::clamp(q, q_lo_, q_hi_);
  int i = static_cast<int>(std::floor((qc - q_lo_) / h_));
  i = std::clamp(i, 0, n - 2);
  const double a = (q_lo_ + (i + 1) * h_ - qc) / h_, b = 1.0 - a;
  return a * n_[i] + b * n_[i + 1] + ((a * a * a - a) * m_[i] + (b * b * b - b) * m_[i + 1]) * h_ * h_ / 6.0;
}

// ---- load_actuators ---------------------------------------------------------------------

namespace {

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

enum class Check { Any, Positive, NonNegative, Fraction, Sign, Whole };

// The table through the located YAML reader: every problem collected, each at its
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
    const std::string expected = "expected a map with the key 'actuators' (a list of actuators)";
    if (root.IsNull() || !root.IsDefined()) rd_.fail(Location{rd_.file(), 1, 1}, expected + ", got an empty file");
    if (!root.IsMap()) fail(root, expected);
    keys(root, {"actuators"}, "", "top-level key");
    const YAML::Node list = root["actuators"];
    if (!list) rd_.fail(Location{rd_.file(), 1, 1}, "missing 'actuators' (a list of actuators)");
    if (!list.IsSequence() || list.size() == 0) fail(list, "'actuators' must be a non-empty list of actuators");
    std::vector<ActuatorParams> out;
    std::set<std::string> joints;
    for (const YAML::Node& e : list) {
      rd_.guard([&] {
        ActuatorParams p = actuator(e);
        if (!joints.insert(p.joint).second) fail(e["joint"], "joint '" + p.joint + "' has a second actuator");
        out.push_back(std::move(p));
      });
    }
    return out;
  }

  [[noreturn]] void fail(const YAML::Node& n, const std::string& what) { rd_.fail(n, what); }

  // Every key of `map` must be in `allowed`, once. Messages: "[ctx: ]unknown WHAT 'k' (...)".
  // A map with a wrong key is left (Skip): its "missing" keys may be the misspelt ones.
  void keys(const YAML::Node& map, const std::vector<std::string>& allowed, const std::string& ctx, const std::string& what) {
    if (!rd_.keys(map, allowed, ctx, what)) throw yaml::Skip{};
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
    static const std::vector<std::string> common = {
        "joint",        "kind",    "J_m_kgm2",     "B_m_Nms",        "N_m_rad_per_m",   "K_s_N_per_m",
        "B_s_Ns_per_m", "M_r_kg",  "B_l_Ns_per_m", "k_tau_Nm_per_A", "current_limit_A", "force_limit_N",
        "efficiency",   "linkage", "thermal",      "motor_encoder",  "spring_encoder",  "potentiometer"};
    if (!e.IsMap()) fail(e, "expected an actuator: a map with the keys " + join(common));
    ActuatorParams p;
    // joint and kind first: the other messages name them.
    const YAML::Node j = e["joint"];
    if (!j) fail(e, "actuator: missing 'joint' (the URDF joint it drives)");
    if (!j.IsScalar() || j.Scalar().empty()) fail(j, "actuator: 'joint' must be a joint name");
    p.joint = j.Scalar();
    const std::string ctx = "actuator '" + p.joint + "'";
    keys(e, common, ctx, "key");
    const YAML::Node k = require(e, "kind", ctx);
    if (k.IsScalar() && k.Scalar() == "RFSEA") {
      p.kind = ActuatorKind::RFSEA;
    } else if (k.IsScalar() && k.Scalar() == "FSEA") {
      p.kind = ActuatorKind::FSEA;
    } else {
      fail(k, ctx + ": unknown kind '" + (k.IsScalar() ? k.Scalar() : std::string("?")) + "' (expected RFSEA or FSEA)");
    }

    p.J_m_kgm2 = number(e, "J_m_kgm2", ctx, Check::Positive, "kg m^2");
    p.B_m_Nms = number(e, "B_m_Nms", ctx, Check::NonNegative, "N m s/rad");
    p.N_m_rad_per_m = number(e, "N_m_rad_per_m", ctx, Check::Positive, "rad/m");
    p.K_s_N_per_m = number(e, "K_s_N_per_m", ctx, Check::Positive, "N/m");
    p.B_s_Ns_per_m = number(e, "B_s_Ns_per_m", ctx, Check::NonNegative, "N s/m");
    if (p.kind == ActuatorKind::RFSEA) {
      p.M_r_kg = number(e, "M_r_kg", ctx, Check::Positive, "kg");
    } else {
      if (e["M_r_kg"]) fail(e["M_r_kg"], ctx + ": 'M_r_kg' applies to an RFSEA only (an FSEA has no reaction mass)");
      p.M_r_kg = 0.0;
    }
    p.B_l_Ns_per_m = number(e, "B_l_Ns_per_m", ctx, Check::NonNegative, "N s/m");
    p.k_tau_Nm_per_A = number(e, "k_tau_Nm_per_A", ctx, Check::Positive, "N m/A");
    p.current_limit_A = number(e, "current_limit_A", ctx, Check::Positive, "A");
    p.force_limit_N = number(e, "force_limit_N", ctx, Check::Positive, "N");
    p.efficiency = number(e, "efficiency", ctx, Check::Fraction, "");

    const YAML::Node l = submap(e, "linkage", ctx, {"a_m", "b_m", "gamma0_rad", "sign"});
    const std::string lc = ctx + " linkage";
    p.linkage.a_m = number(l, "a_m", lc, Check::Positive, "m");
    p.linkage.b_m = number(l, "b_m", lc, Check::Positive, "m");
    p.linkage.gamma0_rad = number(l, "gamma0_rad", lc, Check::Any, "rad");
    p.linkage.sign = number(l, "sign", lc, Check::Sign, "");

    const YAML::Node t =
        submap(e, "thermal", ctx,
               {"R_winding_ohm", "alpha_per_K", "C_winding_J_per_K", "C_housing_J_per_K", "R_wh_K_per_W",
                "R_ha_air_K_per_W", "R_ha_liquid_K_per_W", "T_ambient_C", "T_winding_max_C"});
    const std::string tc = ctx + " thermal";
    p.thermal.R_winding_ohm = number(t, "R_winding_ohm", tc, Check::Positive, "ohm at 20 C");
    p.thermal.alpha_per_K = number(t, "alpha_per_K", tc, Check::NonNegative, "1/K");
    p.thermal.C_winding_J_per_K = number(t, "C_winding_J_per_K", tc, Check::Positive, "J/K");
    p.thermal.C_housing_J_per_K = number(t, "C_housing_J_per_K", tc, Check::Positive, "J/K");
    p.thermal.R_wh_K_per_W = number(t, "R_wh_K_per_W", tc, Check::Positive, "K/W");
    p.thermal.R_ha_air_K_per_W = number(t, "R_ha_air_K_per_W", tc, Check::Positive, "K/W");
    p.thermal.R_ha_liquid_K_per_W = number(t, "R_ha_liquid_K_per_W", tc, Check::Positive, "K/W");
    p.thermal.T_ambient_C = number(t, "T_ambient_C", tc, Check::Any, "C");
    p.thermal.T_winding_max_C = number(t, "T_winding_max_C", tc, Check::Any, "C");
    if (p.thermal.T_winding_max_C <= p.thermal.T_ambient_C)
      fail(t["T_winding_max_C"], tc + ": 'T_winding_max_C' must be above 'T_ambient_C'");

    const YAML::Node me = submap(e, "motor_encoder", ctx, {"counts_per_unit"});
    p.motor_encoder.counts_per_unit =
        number(me, "counts_per_unit", ctx + " motor_encoder", Check::Positive, "counts/rad");
    const YAML::Node se = submap(e, "spring_encoder", ctx, {"counts_per_unit"});
    p.spring_encoder.counts_per_unit =
        number(se, "counts_per_unit", ctx + " spring_encoder", Check::Positive, "counts/m");

    const YAML::Node pm = submap(e, "potentiometer", ctx, {"lo", "hi", "adc_bits", "noise_std", "cutoff_hz"});
    const std::string pc = ctx + " potentiometer";
    p.potentiometer.lo = number(pm, "lo", pc, Check::Any, "rad");
    p.potentiometer.hi = number(pm, "hi", pc, Check::Any, "rad");
    if (p.potentiometer.hi <= p.potentiometer.lo) fail(pm["hi"], pc + ": 'hi' must be above 'lo'");
    const double bits = number(pm, "adc_bits", pc, Check::Whole, "");
    p.potentiometer.adc_bits = std::isfinite(bits) ? static_cast<int>(bits) : 0;
    p.potentiometer.noise_std = number(pm, "noise_std", pc, Check::NonNegative, "rad");
    p.potentiometer.cutoff_hz = number(pm, "cutoff_hz", pc, Check::NonNegative, "Hz");
    return p;
  }

  yaml::Reader rd_;
};

}  // namespace

std::vector<ActuatorParams> load_actuators(const std::string& yaml_path, const NumberParser& numbers) {
  std::string bytes;
  if (const auto reason = try_read_file(yaml_path, bytes))
    throw ModelError(yaml_path + ": cannot read: " + *reason + " (expected a YAML actuator table)");
  return Reader(yaml_path, numbers).run(bytes);
}


}  // namespace dmbd::model
