#include "analyze.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "dmbd/base/number_text.hpp"
#include "dmbd/blocks/delay.hpp"
#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/exact_frequency.hpp"
#include "dmbd/blocks/sampled.hpp"
#include "dmbd/blocks/frequency.hpp"
#include "dmbd/blocks/zpk.hpp"
#include "dmbd/diagrams/linearize.hpp"
#include "dmbd/viz/plot.hpp"

namespace dmbd::apps {

using nlohmann::json;
namespace b = dmbd::blocks;

namespace {

constexpr double kTwoPi = 2.0 * M_PI;

json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }
json number(const std::optional<double>& v) { return v ? number(*v) : json(nullptr); }

json hz(const std::optional<double>& w_rad_s) {
  return w_rad_s ? number(*w_rad_s / kTwoPi) : json(nullptr);
}

void check_output_path(const std::string& path, const char* option) {
  if (path.empty()) return;
  const std::filesystem::path p(path);
  const auto dir = p.has_parent_path() ? p.parent_path() : std::filesystem::path(".");
  if (!std::filesystem::is_directory(dir))
    throw InputError(std::string(option) + " '" + path + "': folder '" + dir.string() + "' does not exist");
  if (p.extension() != ".png") throw InputError(std::string(option) + " '" + path + "': expected a .png file name");
}

}  // namespace


json roots_json(const std::vector<b::Complex>& roots) {
  json a = json::array();
  for (const auto& r : roots) a.push_back({r.real(), r.imag()});
  return a;
}

json max_real_pole(const std::vector<b::Complex>& poles, double ts) {
  double m = -INFINITY;
  for (const b::Complex& p : poles) m = std::max(m, (ts > 0.0 ? std::log(p) / ts : p).real());
  return number(m);
}

DiagramTransfer diagram_transfer(const diagrams::Diagram& d, const std::string& from, const std::string& to,
                                 const std::string& loop_at) {
  const b::SparseStateSpace ss =
      loop_at.empty() ? diagrams::linearize_sparse(d, from, to) : diagrams::loop_transfer_sparse(d, loop_at);
  if (ss.num_inputs() != 1 || ss.num_outputs() != 1)
    throw InputError("analysis needs scalar signals: the model has " + std::to_string(ss.num_inputs()) + " inputs and " +
                     std::to_string(ss.num_outputs()) + " outputs");
  b::Siso g = b::Siso::from_state_space(ss);
  const b::Stability internal = b::stability(g.modes(), ss.is_discrete());
  return {std::move(g), internal, ss.num_states()};
}

void add_interconnection(json& report, const DiagramTransfer& t) {
  // `stable`: the analysed transfer; `internally_stable`: every mode of the
  // interconnection, including those the two signals do not see.
  report["internally_stable"] = t.internal == b::Stability::Stable;
  report["internal_stability"] = b::to_string(t.internal);
  report["states"] = t.states;
  report["factors"] = t.transfer.factors();
}

namespace {

// What the transfer is: coefficients (when representable), poles, zeros, DC gain, and
// the stability verdict (blocks::stability: marginal for a simple pole on the boundary).
void describe(json& r, const b::Siso& g) {
  const b::Zpk& z = g.zpk();
  r["continuous"] = !g.is_discrete();
  r["ts"] = g.ts();
  r["num"] = g.tf() ? json(g.tf()->num().descending()) : json(nullptr);
  r["den"] = g.tf() ? json(g.tf()->den().descending()) : json(nullptr);
  r["order"] = z.order();
  r["proper"] = z.is_zero() || z.relative_degree() >= 0;
  r["poles"] = roots_json(z.all_poles());
  r["zeros"] = roots_json(z.is_zero() ? std::vector<b::Complex>{} : z.all_zeros());
  r["hidden_poles"] = roots_json(g.hidden());
  r["dc_gain"] = number(z.dc_gain());
  const b::Stability st = g.verdict();
  r["stable"] = st == b::Stability::Stable;
  r["stability"] = b::to_string(st);
}

// The transfer's own response (coefficients or state space), on which the figures
// found on the zeros and poles are refined (blocks/exact_frequency.hpp).
b::ExactResponse exact_response(const b::Siso& g) {
  return [&g](double w) { return g.response(w); };
}

void add_margins(json& r, const b::Siso& g) {
  const b::Margins m = b::margins(g.zpk(), exact_response(g));
  r["gain_margin_db"] = number(m.gain_margin_db);
  r["phase_crossover_hz"] = hz(m.phase_crossover_rad_s);
  r["phase_margin_deg"] = number(m.phase_margin_deg);
  r["gain_crossover_hz"] = hz(m.gain_crossover_rad_s);
  json all = json::array();
  for (const auto& c : m.gain_crossovers) all.push_back({{"freq_hz", c.w_rad_s / kTwoPi}, {"phase_margin_deg", c.margin}});
  r["gain_crossovers"] = all;
  all = json::array();
  for (const auto& c : m.phase_crossovers) all.push_back({{"freq_hz", c.w_rad_s / kTwoPi}, {"gain_margin_db", c.margin}});
  r["phase_crossovers"] = all;
}

json bode_json(const b::Siso& g, const std::vector<double>& freq_hz) {
  std::vector<double> w;
  for (double f : freq_hz) w.push_back(f * kTwoPi);
  const b::Bode bd = b::bode(g.zpk(), w, exact_response(g));
  json mag = json::array(), ph = json::array();
  for (size_t k = 0; k < w.size(); ++k) {
    mag.push_back(number(bd.mag_db[k]));
    ph.push_back(number(bd.phase_deg[k]));
  }
  return {{"freq_hz", freq_hz}, {"mag_db", mag}, {"phase_deg", ph}};
}

json step_json(const b::Siso& g, double t_end, int n) {
  const b::Siso::Step st = g.step(t_end, n);
  json y = json::array();
  for (Eigen::Index k = 0; k < st.response.y.rows(); ++k) y.push_back(number(st.response.y(k, 0)));
  return {{"t", st.response.t},
          {"y", y},
          {"rise_time_s", number(st.info.rise_time_s)},
          {"settling_time_s", number(st.info.settling_time_s)},
          {"overshoot_pct", number(st.info.overshoot_pct)},
          {"final_value", number(st.info.final_value)},
          {"peak", number(st.info.peak)},
          {"peak_time_s", number(st.info.peak_time_s)}};
}

// The exact discretisation of G(s) e^{-s T}: ZOH by the modified z-transform (any T);
// Tustin and backward Euler times z^-n when T is n whole samples (they have no exact
// form for a fraction of one).
b::TransferFunction c2d_delayed(const b::TransferFunction& g, const AnalyzeRequest& req, double prewarp) {
  if (*req.c2d == b::C2dMethod::Zoh) return b::c2d_zoh_delayed(g, req.c2d_ts, req.delay_s);
  const auto n = b::whole_samples(req.delay_s, req.c2d_ts);
  if (!n)
    throw InputError("--c2d " + std::string(b::to_string(*req.c2d)) + ": the delay exp(-s*" + number_text(req.delay_s) +
                     ") is not a whole number of samples of " + number_text(req.c2d_ts) +
                     " s; --c2d zoh discretises any delay exactly");
  return b::c2d(g, req.c2d_ts, *req.c2d, prewarp) * b::sample_delay(*n, req.c2d_ts);
}

json c2d_json(const b::TransferFunction& analysed, const AnalyzeRequest& req) {
  const b::TransferFunction& g = req.undelayed ? *req.undelayed : analysed;
  if (g.is_discrete()) throw InputError("--c2d: the system is already discrete (an expression in z)");
  if (!g.is_proper()) throw InputError("--c2d needs a proper transfer function");
  const double prewarp = req.prewarp_hz * kTwoPi;
  const b::TransferFunction gd = req.delay_s > 0.0 ? c2d_delayed(g, req, prewarp) : b::c2d(g, req.c2d_ts, *req.c2d, prewarp);
  json j;
  j["method"] = b::to_string(*req.c2d);
  j["ts"] = req.c2d_ts;
  if (req.prewarp_hz > 0.0) j["prewarp_hz"] = req.prewarp_hz;
  j["num"] = gd.num().descending();
  j["den"] = gd.den().descending();
  // The images of the continuous poles: exact, and better conditioned than the roots
  // of the discrete denominator.
  std::vector<b::Complex> pd;
  for (const b::Complex& p : g.poles()) pd.push_back(b::c2d_pole(p, req.c2d_ts, *req.c2d, prewarp));
  // A delay's poles sit at z = 0 (whole samples, and one for a fraction of a sample).
  pd.insert(pd.end(), static_cast<size_t>(gd.order() - g.order()), b::Complex(0.0, 0.0));
  b::sort_roots(pd);
  if (req.delay_s > 0.0) j["delay_s"] = req.delay_s;
  j["poles"] = roots_json(pd);
  j["zeros"] = roots_json(gd.zeros());
  j["stable"] = gd.is_stable();
  return j;
}

}  // namespace

json analyze(const b::Siso& g, const AnalyzeRequest& req) {
  check_output_path(req.bode_png, "--bode");
  check_output_path(req.step_png, "--step-plot");
  json r;
  describe(r, g);
  r["loop_transfer"] = req.loop;
  if (req.loop) add_margins(r, g);
  r["bandwidth_hz"] = hz(b::bandwidth(g.zpk(), exact_response(g)));
  if (!req.freq_hz.empty()) r["bode"] = bode_json(g, req.freq_hz);
  const bool need_step = req.step.has_value() || !req.step_png.empty();
  if (need_step && !g.realisation()) {
    throw InputError("a step response needs a proper transfer function (numerator degree " +
                     std::to_string(g.tf()->num().degree()) + " > denominator degree " +
                     std::to_string(g.tf()->den().degree()) + ")");
  }
  if (req.step) r["step"] = step_json(g, req.step->first, req.step->second);
  if (req.c2d) {
    if (!g.tf())
      throw InputError("--c2d needs the transfer function's coefficients, and those of this order-" +
                       std::to_string(g.zpk().order()) + " transfer overflow double precision");
    r["discrete"] = c2d_json(*g.tf(), req);
  }
  return r;
}

void write_plots(const b::Siso& g, const json& r, const AnalyzeRequest& req) {
  const std::string title = req.title.empty() ? "G" : req.title;
  if (!req.bode_png.empty()) {
    // A dense grid: over the requested frequencies' span when they span one, else two
    // decades beyond the poles and zeros.
    std::vector<double> w = b::default_frequency_grid(g.zpk(), 600);
    if (!req.freq_hz.empty()) {
      const auto [lo, hi] = std::minmax_element(req.freq_hz.begin(), req.freq_hz.end());
      if (*hi > *lo) w = b::logspace(*lo * kTwoPi, *hi * kTwoPi, 600);
    }
    const b::Bode bd = b::bode(g.zpk(), w, exact_response(g));
    std::vector<double> f(w.size());
    for (size_t k = 0; k < w.size(); ++k) f[k] = w[k] / kTwoPi;
    std::optional<double> gc, pc;
    // Crossovers are marked only on a loop transfer (no margins otherwise).
    if (r.contains("gain_crossover_hz") && !r["gain_crossover_hz"].is_null()) gc = r["gain_crossover_hz"].get<double>();
    if (r.contains("phase_crossover_hz") && !r["phase_crossover_hz"].is_null() &&
        r["phase_crossover_hz"].get<double>() > 0.0)
      pc = r["phase_crossover_hz"].get<double>();
    viz::bode_figure(f, bd.mag_db, bd.phase_deg, "Bode: " + title, gc, pc).save_png(req.bode_png);
  }
  if (!req.step_png.empty()) {
    const b::Siso::Step st = req.step ? g.step(req.step->first, req.step->second) : g.step(g.default_step_horizon(), 1000);
    std::vector<double> y(static_cast<size_t>(st.response.y.rows()));
    for (size_t k = 0; k < y.size(); ++k) y[k] = st.response.y(static_cast<Eigen::Index>(k), 0);
    viz::step_figure(st.response.t, y, "Step response: " + title, st.info.final_value).save_png(req.step_png);
  }
}

}  // namespace dmbd::apps
