// The output damping replayed (damping_replay.hpp; docs/experiments.md, "The robot's
// output damping"). For a joint moving as logged, a change of the output damping from B_l
// to s B_l changes the force the screw (or gear) must deliver by (s - 1) B_l x', x' the
// output travel rate, and so the motor current by
//     di = (s - 1) B_l x' / (eta k_tau N_m)
// (the drive's force per ampere, efficiency included, as the plant applies it). x' is
// the travel of the motor side less the spring's, x = theta_m / N_m - s_def, differentiated
// from the log (central differences; the log's own rate). The rest of the current (the
// load, the rotor's inertia and friction, the spring) is the run's, unchanged. The
// replayed current drives each joint's two-node thermal model (model::ThermalModel, exact
// for a constant current over each log interval), cooled and uncooled, from the ambient
// temperature, with the segment [from_s, end of run] repeated until duration_s. A current
// beyond the drive's limit is kept (the motion could not be followed: counted, and the
// heat is then a lower bound of what following it would need).
#include "damping_replay.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "dmbd/experiments/sampled_interval.hpp"
#include "dmbd/model/thermal.hpp"
#include "experiment_support.hpp"

namespace dmbd::experiments::detail {

namespace {

const char* const kThermalKeys[] = {"R_winding_ohm", "alpha_per_K", "C_winding_J_per_K", "C_housing_J_per_K", "R_wh_K_per_W",
                                    "R_ha_air_K_per_W", "R_ha_liquid_K_per_W", "T_ambient_C", "T_winding_max_C"};

double model::ThermalParams::*thermal_field(int k) {
  static double model::ThermalParams::*const f[] = {
      &model::ThermalParams::R_winding_ohm,       &model::ThermalParams::alpha_per_K,      &model::ThermalParams::C_winding_J_per_K,
      &model::ThermalParams::C_housing_J_per_K,   &model::ThermalParams::R_wh_K_per_W,     &model::ThermalParams::R_ha_air_K_per_W,
      &model::ThermalParams::R_ha_liquid_K_per_W, &model::ThermalParams::T_ambient_C,      &model::ThermalParams::T_winding_max_C};
  return f[k];
}

// One joint's actuator as the replay needs it (from the run's truth).
struct Drive {
  double B_l = 0, N_m = 0, amps_per_newton = 0, current_limit_A = 0;
  model::ThermalParams thermal;
};

std::optional<Drive> drive_of(const sim::VariantResult& r, const std::string& joint) {
  auto get = [&](const std::string& key) { return r.truth.at(joint + "." + key); };
  if (!r.truth.count(joint + ".B_l")) return std::nullopt;
  Drive d;
  d.B_l = get("B_l");
  d.N_m = get("N_m");
  d.amps_per_newton = 1.0 / (get("efficiency") * get("k_tau") * d.N_m);
  d.current_limit_A = get("current_limit_A");
  for (int k = 0; k < 9; ++k) d.thermal.*thermal_field(k) = get(std::string("thermal.") + kThermalKeys[k]);
  return d;
}

// The output travel rate x' over the segment (central differences inside, one-sided at its ends).
std::vector<double> travel_rate(const std::vector<double>& t, const std::vector<double>& theta, const std::vector<double>& s_def, double N_m,
                                std::size_t k0, std::size_t k1) {
  auto x = [&](std::size_t k) { return theta[k] / N_m - s_def[k]; };
  std::vector<double> xd;
  for (std::size_t k = k0; k < k1; ++k) {
    const std::size_t a = k == k0 ? k : k - 1, b = k + 1 == k1 ? k : k + 1;
    xd.push_back((x(b) - x(a)) / (t[b] - t[a]));
  }
  return xd;
}

struct Heat {
  double peak_cooled = 0, peak_uncooled = 0;
  double uncooled_passes_s = NAN;  // when the uncooled winding first passed the threshold
};

// The current held over each log interval, the segment repeated until `duration`.
Heat heat(const model::ThermalParams& th, const std::vector<double>& dt, const std::vector<double>& i, double duration, std::optional<double> above) {
  model::ThermalModel cooled(th), uncooled(th);
  cooled.reset();
  uncooled.reset();
  Heat h{th.T_ambient_C, th.T_ambient_C, NAN};
  for (double t = 0; t < duration;)
    for (std::size_t k = 0; k < dt.size() && t < duration; ++k) {
      const double step = std::min(dt[k], duration - t);
      cooled.step(i[k], step, true);
      uncooled.step(i[k], step, false);
      t += step;
      h.peak_cooled = std::max(h.peak_cooled, cooled.state().T_winding_C);
      h.peak_uncooled = std::max(h.peak_uncooled, uncooled.state().T_winding_C);
      if (above && std::isnan(h.uncooled_passes_s) && uncooled.state().T_winding_C > *above) h.uncooled_passes_s = t;
    }
  return h;
}

double rms(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return std::sqrt(s / static_cast<double>(v.size()));
}

plot::Figure figure_of(const sim::VariantResult& r, const ReplayParams& p, const std::vector<double>& s, const nlohmann::json& joints) {
  plot::Figure fig(1000, 820);
  fig.title = fmt::format("Run {}: {:g} s replayed with B_l = s x the run's", r.name, p.duration_s);
  const char* keys[] = {"peak_winding_cooled_C", "peak_winding_uncooled_C", "current_rms_A"};
  const char* labels[] = {"Cooled winding peak (C)", "Uncooled winding peak (C)", "Current RMS (A)"};
  const std::optional<double> bounds[] = {p.cooled_below_C, p.uncooled_above_C, std::nullopt};
  for (int a = 0; a < 3; ++a) {
    plot::Axes& ax = stacked_axes(fig, labels[a], a == 2, "s (B_l as a fraction of the run's)");
    const bool log_x = s.front() > 0 && s.back() > s.front();
    ax.x_scale = log_x ? plot::Scale::Log : plot::Scale::Linear;
    if (log_x) ax.x_limits = std::pair{s.front() / std::pow(s.back() / s.front(), 0.04), s.back() * std::pow(s.back() / s.front(), 0.04)};
    if (a == 1) ax.y_scale = plot::Scale::Log;  // the uncooled peaks span decades at large s
    std::size_t c = 0;
    double lo = INFINITY, hi = -INFINITY;
    for (const auto& j : p.joints) {
      if (!joints.contains(j)) continue;
      plot::Series line{j, s, joints[j][keys[a]].get<std::vector<double>>(), plot::palette_color(c++)};
      line.markers = true;
      for (double y : line.y) lo = std::min(lo, y), hi = std::max(hi, y);
      ax.series.push_back(line);
    }
    if (bounds[a] && std::isfinite(lo)) {  // the threshold in view
      lo = std::min(lo, *bounds[a]), hi = std::max(hi, *bounds[a]);
      ax.y_limits = a == 1 ? std::pair{lo / 1.2, hi * 1.2} : std::pair{lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo)};
    }
    if (bounds[a]) {
      ax.h_lines.push_back(*bounds[a]);
      ax.h_line_labels.push_back(fmt::format("{} {:g} C", a == 0 ? "below" : "above", *bounds[a]));
    }
  }
  return fig;
}

}  // namespace

void record_replay(const std::vector<std::string>& joints, const RecordContext& c, std::map<std::string, double>& truth) {
  for (int k = 0; k < c.plant.num_actuators(); ++k) {
    const model::ActuatorParams& a = c.plant.actuator(k);
    if (std::find(joints.begin(), joints.end(), a.joint) == joints.end()) continue;
    const std::string j = a.joint + ".";
    truth[j + "B_l"] = a.B_l_Ns_per_m;
    truth[j + "N_m"] = a.N_m_rad_per_m;
    truth[j + "k_tau"] = a.k_tau_Nm_per_A;
    truth[j + "efficiency"] = a.efficiency;
    truth[j + "current_limit_A"] = a.applied_current_limit_A();
    for (int t = 0; t < 9; ++t) truth[j + "thermal." + kThermalKeys[t]] = a.thermal.*thermal_field(t);
  }
}

std::optional<ReplayOutcome> replay_damping(const sim::VariantResult& r, const ReplayParams& p, const std::string& file) {
  const std::vector<double>& t = r.log.time();
  const std::size_t k0 = static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), p.from_s) - t.begin()), k1 = t.size();
  std::vector<double> s = p.scales;
  std::sort(s.begin(), s.end());
  nlohmann::json joints = nlohmann::json::object();
  std::vector<bool> holds(s.size(), true);
  for (const std::string& joint : p.joints) {
    const std::optional<Drive> d = drive_of(r, joint);
    if (!d) continue;
    if (k1 < k0 + 3)
      throw InputError(fmt::format("{}: variant '{}': the replay's segment from {} s holds {} log samples (expected at least 3)", file, r.name,
                                   p.from_s, k1 > k0 ? k1 - k0 : 0));
    const std::vector<double> xd = travel_rate(t, signal(r, joint + ".motor_angle", file), signal(r, joint + ".spring_deflection", file), d->N_m, k0, k1);
    const std::vector<double>& i_run = signal(r, joint + ".current_applied", file);
    std::vector<double> dt;
    for (std::size_t k = k0; k + 1 < k1; ++k) dt.push_back(t[k + 1] - t[k]);
    nlohmann::json m;
    for (std::size_t n = 0; n < s.size(); ++n) {
      std::vector<double> i;
      long over = 0;
      for (std::size_t k = k0; k + 1 < k1; ++k) {
        i.push_back(i_run[k] + (s[n] - 1.0) * d->B_l * xd[k - k0] * d->amps_per_newton);
        over += std::abs(i.back()) > d->current_limit_A;
      }
      const Heat h = heat(d->thermal, dt, i, p.duration_s, p.uncooled_above_C);
      m["B_l"].push_back(s[n] * d->B_l);
      m["current_rms_A"].push_back(rms(i));
      m["over_current_limit_fraction"].push_back(static_cast<double>(over) / static_cast<double>(i.size()));
      m["peak_winding_cooled_C"].push_back(h.peak_cooled);
      m["peak_winding_uncooled_C"].push_back(h.peak_uncooled);
      m["uncooled_passes_s"].push_back(std::isnan(h.uncooled_passes_s) ? nlohmann::json() : nlohmann::json(h.uncooled_passes_s));
      holds[n] = holds[n] && (!p.cooled_below_C || h.peak_cooled < *p.cooled_below_C) && (!p.uncooled_above_C || h.peak_uncooled > *p.uncooled_above_C);
    }
    joints[joint] = m;
  }
  if (joints.empty()) return std::nullopt;
  ReplayOutcome out;
  out.metrics = {{"scales", s}, {"from_s", t[k0]}, {"to_s", t[k1 - 1]}, {"duration_s", p.duration_s}, {"joints", joints}};
  out.metrics.update(sampled_interval(s, holds));
  out.figure = figure_of(r, p, s, joints);
  out.note = fmt::format("Run {}: its motion from {:.3g} to {:.3g} s replayed for {:g} s with B_l at s times its own: the winding conditions {}.", r.name,
                         t[k0], t[k1 - 1], p.duration_s, out.metrics["verdict"].get<std::string>());
  return out;
}

}  // namespace dmbd::experiments::detail
