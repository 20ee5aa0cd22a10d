// What every experiment shares: step metrics, RMS errors, figure labels, and the
// default record (the experiment joint's actuator parameters) (experiment.hpp).
#include "dmbd/experiments/experiment.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dmbd::experiments {

namespace {

// x at the first sample at or after ts (the last when there is none; NaN for no samples).
double value_at(const std::vector<double>& t, const std::vector<double>& x, double ts) {
  if (x.empty() || x.size() != t.size()) return std::numeric_limits<double>::quiet_NaN();
  const auto it = std::lower_bound(t.begin(), t.end(), ts - 1e-12);
  return it == t.end() ? x.back() : x[static_cast<std::size_t>(it - t.begin())];
}

}  // namespace

StepMetrics step_metrics(const std::vector<double>& t, const std::vector<double>& r, const std::vector<double>& y, double t_step,
                         double t_end) {
  StepMetrics m;
  const double r1 = value_at(t, r, t_step), y0 = value_at(t, y, t_step);
  const double d = r1 - y0;
  if (d == 0) return m;
  double peak = -std::numeric_limits<double>::infinity();
  double t10 = -1, t90 = -1;
  double ss = 0;
  int nss = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    // [t_step, t_end): a reference that steps back at t_end is already back there.
    if (t[k] < t_step || t[k] >= t_end) continue;
    const double frac = (y[k] - y0) / d;
    peak = std::max(peak, frac);
    if (t10 < 0 && frac >= 0.1) t10 = t[k];
    if (t90 < 0 && frac >= 0.9) t90 = t[k];
    if (t[k] >= t_end - 0.2 * (t_end - t_step)) {
      ss += y[k] - r[k];
      ++nss;
    }
  }
  m.overshoot_pct = std::max(0.0, (peak - 1.0) * 100.0);
  m.rise_time_s = (t10 >= 0 && t90 >= 0) ? t90 - t10 : std::numeric_limits<double>::infinity();
  m.steady_state_error = nss ? std::abs(ss / nss) : std::numeric_limits<double>::quiet_NaN();
  return m;
}

double rms_error(const std::vector<double>& t, const std::vector<double>& r, const std::vector<double>& y, double t0, double t1) {
  double sq = 0;
  std::size_t n = 0;
  for (std::size_t k = 0; k < t.size(); ++k)
    if (t[k] >= t0 && t[k] <= t1) {
      sq += (y[k] - r[k]) * (y[k] - r[k]);
      ++n;
    }
  return n ? std::sqrt(sq / static_cast<double>(n)) : std::numeric_limits<double>::quiet_NaN();
}

std::string labelled(const ExperimentSetup& setup, const std::string& figure, const std::string& title) {
  const auto it = setup.figure_labels.find(figure);
  return it == setup.figure_labels.end() ? title : title + " (" + it->second + ")";
}

std::vector<sim::Overlay> Experiment::overlays(const ExperimentSetup&) const { return {}; }

// The simulator's values of the experiment joint's actuator (a joint without one: none),
// the load it sees reflected through its transmission at its initial angle included.
void Experiment::record(const ExperimentSetup& setup, const RecordContext& c, std::map<std::string, double>& truth) const {
  for (int k = 0; k < c.plant.num_actuators(); ++k) {
    const model::ActuatorParams& a = c.plant.actuator(k);
    if (a.joint != setup.joint) continue;
    double q0 = 0.0;
    for (const auto& [name, q] : c.initial_angles)
      if (name == a.joint) q0 = q;
    const double n_l = a.N_l(q0);
    const int j = c.robot.joint_index(a.joint);
    const std::map<std::string, double> values = {{"J_m", a.J_m_kgm2}, {"B_m", a.B_m_Nms}, {"M_r", a.M_r_kg}, {"B_r", a.B_s_Ns_per_m}, {"K_r", a.K_s_N_per_m},
             {"B_l", a.B_l_Ns_per_m}, {"M_l", model::subtree_axis_inertia(c.robot, j) * n_l * n_l}, {"k_tau", a.k_tau_Nm_per_A},
             {"N_m", a.N_m_rad_per_m}, {"N_l", n_l}, {"q0", q0}, {"efficiency", a.efficiency}};
    for (const auto& [key, value] : values) truth[key] = value;
  }
}

}  // namespace dmbd::experiments
