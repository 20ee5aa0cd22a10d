#include "analyze.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/frequency.hpp"
#include "dmbd/blocks/state_space.hpp"
#include "dmbd/blocks/time_response.hpp"
#include "dmbd/viz/plot.hpp"

namespace dmbd::apps {

using nlohmann::json;
namespace b = dmbd::blocks;

namespace {

constexpr double kTwoPi = 2.0 * M_PI;

json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }
json number(const std::optional<double>& v) { return v ? number(*v) : json(nullptr); }

json roots_json(const std::vector<b::Complex>& roots) {
  json a = json::array();
  for (const auto& r : roots) a.push_back({r.real(), r.imag()});
  return a;
}

json hz(const std::optional<double>& w_rad_s) {
  return w_rad_s ? number(*w_rad_s / kTwoPi) : json(nullptr);
}

std::string fmt_num(double v) { return fmt::format("{:.6g}", v); }

std::string fmt_opt(const json& j, const char* unit, double scale = 1.0) {
  if (j.is_null()) return "none";
  return fmt_num(j.get<double>() * scale) + unit;
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

std::string polynomial_text(const std::vector<double>& d, char var) {
  if (d.empty()) return "0";
  std::string out;
  const int n = static_cast<int>(d.size()) - 1;
  for (int i = 0; i <= n; ++i) {
    const double c = d[static_cast<size_t>(i)];
    const int p = n - i;
    if (c == 0.0) continue;
    const double a = std::abs(c);
    std::string term;
    if (p == 0 || a != 1.0) term = fmt_num(a);
    if (p > 0) {
      if (!term.empty()) term += " ";
      term += var;
      if (p > 1) term += "^" + std::to_string(p);
    }
    if (out.empty()) {
      out = (c < 0 ? "-" : "") + term;
    } else {
      out += (c < 0 ? " - " : " + ") + term;
    }
  }
  return out.empty() ? "0" : out;
}

json analyze(const b::TransferFunction& g, const AnalyzeRequest& req) {
  check_output_path(req.bode_png, "--bode");
  check_output_path(req.step_png, "--step-plot");
  json r;
  r["continuous"] = !g.is_discrete();
  r["ts"] = g.ts();
  r["num"] = g.num().descending();
  r["den"] = g.den().descending();
  r["order"] = g.order();
  r["proper"] = g.is_proper();
  r["poles"] = roots_json(g.poles());
  r["zeros"] = roots_json(g.zeros());
  r["dc_gain"] = number(g.dc_gain());
  r["stable"] = g.is_stable();

  const b::Margins m = b::margins(g);
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
  r["bandwidth_hz"] = hz(b::bandwidth(g));

  // Bode: the requested points, or an automatic grid when only a plot is asked for.
  std::vector<double> w;
  for (double f : req.freq_hz) w.push_back(f * kTwoPi);
  if (!w.empty()) {
    const b::Bode bd = b::bode(g, w);
    json j;
    j["freq_hz"] = req.freq_hz;
    json mag = json::array(), ph = json::array();
    for (size_t k = 0; k < w.size(); ++k) {
      mag.push_back(number(bd.mag_db[k]));
      ph.push_back(number(bd.phase_deg[k]));
    }
    j["mag_db"] = mag;
    j["phase_deg"] = ph;
    r["bode"] = j;
  }

  const bool need_ss = req.step.has_value() || !req.step_png.empty();
  if (need_ss && !g.is_proper())
    throw InputError("a step response needs a proper transfer function (numerator degree " +
                     std::to_string(g.num().degree()) + " > denominator degree " + std::to_string(g.den().degree()) + ")");
  if (req.step) {
    const b::StateSpace ss = b::StateSpace::from_tf(g);
    const b::TimeResponse tr = b::step(ss, req.step->first, req.step->second);
    const b::StepInfo si = b::step_info(ss, tr);
    json j;
    j["t"] = tr.t;
    json y = json::array();
    for (Eigen::Index k = 0; k < tr.y.rows(); ++k) y.push_back(number(tr.y(k, 0)));
    j["y"] = y;
    j["rise_time_s"] = number(si.rise_time_s);
    j["settling_time_s"] = number(si.settling_time_s);
    j["overshoot_pct"] = number(si.overshoot_pct);
    j["final_value"] = number(si.final_value);
    j["peak"] = number(si.peak);
    j["peak_time_s"] = number(si.peak_time_s);
    r["step"] = j;
  }

  if (req.c2d) {
    if (g.is_discrete()) throw InputError("--c2d: the system is already discrete (an expression in z)");
    if (!g.is_proper()) throw InputError("--c2d needs a proper transfer function");
    const b::TransferFunction gd = b::c2d(g, req.c2d_ts, *req.c2d, req.prewarp_hz * kTwoPi);
    json j;
    j["method"] = b::to_string(*req.c2d);
    j["ts"] = req.c2d_ts;
    if (req.prewarp_hz > 0.0) j["prewarp_hz"] = req.prewarp_hz;
    j["num"] = gd.num().descending();
    j["den"] = gd.den().descending();
    // The images of the continuous poles: exact, and better conditioned than the roots
    // of the discrete denominator.
    std::vector<b::Complex> pd;
    for (const b::Complex& p : g.poles()) pd.push_back(b::c2d_pole(p, req.c2d_ts, *req.c2d, req.prewarp_hz * kTwoPi));
    std::sort(pd.begin(), pd.end(), [](const b::Complex& x, const b::Complex& y) {
      return x.real() != y.real() ? x.real() < y.real() : x.imag() < y.imag();
    });
    j["poles"] = roots_json(pd);
    j["zeros"] = roots_json(gd.zeros());
    j["stable"] = gd.is_stable();
    r["discrete"] = j;
  }
  return r;
}

void write_plots(const b::TransferFunction& g, const json& r, const AnalyzeRequest& req) {
  const std::string title = req.title.empty() ? "G" : req.title;
  if (!req.bode_png.empty()) {
    // A dense grid: over the requested frequencies' span when they span one, else two
    // decades beyond the poles and zeros.
    std::vector<double> w = b::default_frequency_grid(g, 600);
    if (!req.freq_hz.empty()) {
      const auto [lo, hi] = std::minmax_element(req.freq_hz.begin(), req.freq_hz.end());
      if (*hi > *lo) w = b::logspace(*lo * kTwoPi, *hi * kTwoPi, 600);
    }
    const b::Bode bd = b::bode(g, w);
    std::vector<double> f(w.size());
    for (size_t k = 0; k < w.size(); ++k) f[k] = w[k] / kTwoPi;
    std::optional<double> gc, pc;
    if (!r["gain_crossover_hz"].is_null()) gc = r["gain_crossover_hz"].get<double>();
    if (!r["phase_crossover_hz"].is_null() && r["phase_crossover_hz"].get<double>() > 0.0)
      pc = r["phase_crossover_hz"].get<double>();
    viz::bode_figure(f, bd.mag_db, bd.phase_deg, "Bode: " + title, gc, pc).save_png(req.bode_png);
  }
  if (!req.step_png.empty()) {
    const b::StateSpace ss = b::StateSpace::from_tf(g);
    b::TimeResponse tr;
    if (req.step) {
      tr = b::step(ss, req.step->first, req.step->second);
    } else {
      tr = b::step(ss, b::default_step_horizon(ss), 1000);
    }
    std::vector<double> y(static_cast<size_t>(tr.y.rows()));
    for (size_t k = 0; k < y.size(); ++k) y[k] = tr.y(static_cast<Eigen::Index>(k), 0);
    std::optional<double> fv;
    if (auto dc = g.dc_gain(); dc && g.is_stable()) fv = *dc;
    viz::step_figure(tr.t, y, "Step response: " + title, fv).save_png(req.step_png);
  }
}

std::string summary(const json& r) {
  std::ostringstream o;
  const char var = r["continuous"].get<bool>() ? 's' : 'z';
  const std::string num = polynomial_text(r["num"].get<std::vector<double>>(), var);
  const std::string den = polynomial_text(r["den"].get<std::vector<double>>(), var);
  o << "G(" << var << ") = (" << num << ") / (" << den << ")";
  if (!r["continuous"].get<bool>()) o << "   [ts = " << fmt_num(r["ts"].get<double>()) << " s]";
  o << "\n";
  o << "order " << r["order"].get<int>() << ", " << (r["proper"].get<bool>() ? "proper" : "improper") << ", "
    << (r["stable"].get<bool>() ? "stable" : "not stable") << "\n";
  auto roots = [&](const char* name, const json& list) {
    o << name << ":";
    if (list.empty()) o << " none";
    o << "\n";
    for (const auto& p : list) {
      const double re = p[0].get<double>(), im = p[1].get<double>();
      if (im < 0) continue;  // print each conjugate pair once
      o << "  " << fmt_num(re);
      if (im > 0) o << " ± " << fmt_num(im) << "j";
      if (var == 's') {
        const double wn = std::hypot(re, im);
        if (wn > 0) o << fmt::format("   (|p| = {} rad/s = {} Hz, zeta = {:.4g})", fmt_num(wn), fmt_num(wn / kTwoPi), -re / wn);
      } else {
        o << fmt::format("   (|z| = {:.6g})", std::hypot(re, im));
      }
      o << "\n";
    }
  };
  roots("poles", r["poles"]);
  roots("zeros", r["zeros"]);
  if (r["dc_gain"].is_null()) {
    o << "DC gain: infinite\n";
  } else {
    const double k = r["dc_gain"].get<double>();
    o << "DC gain: " << fmt_num(k);
    if (k != 0) o << fmt::format(" ({:.4g} dB)", 20 * std::log10(std::abs(k)));
    o << "\n";
  }
  o << "bandwidth (-3 dB): " << fmt_opt(r["bandwidth_hz"], " Hz") << "\n";
  o << "gain margin: " << fmt_opt(r["gain_margin_db"], " dB");
  if (!r["phase_crossover_hz"].is_null()) o << " at " << fmt_num(r["phase_crossover_hz"].get<double>()) << " Hz";
  o << "; phase margin: " << fmt_opt(r["phase_margin_deg"], " deg");
  if (!r["gain_crossover_hz"].is_null()) o << " at " << fmt_num(r["gain_crossover_hz"].get<double>()) << " Hz";
  o << "  (as a loop transfer function)\n";
  if (r.contains("step")) {
    const json& s = r["step"];
    o << "step: rise (10-90 %) " << fmt_opt(s["rise_time_s"], " ms", 1e3) << ", settling (2 %) "
      << fmt_opt(s["settling_time_s"], " ms", 1e3) << ", overshoot " << fmt_opt(s["overshoot_pct"], " %")
      << ", final value " << fmt_opt(s["final_value"], "") << "\n";
  }
  if (r.contains("bode")) {
    const json& bd = r["bode"];
    o << "frequency response:\n";
    for (size_t k = 0; k < bd["freq_hz"].size(); ++k) {
      o << "  " << fmt::format("{:>12}", fmt_num(bd["freq_hz"][k].get<double>())) << " Hz  "
        << fmt::format("{:>10}", fmt_opt(bd["mag_db"][k], "")) << " dB  "
        << fmt::format("{:>10}", fmt_opt(bd["phase_deg"][k], "")) << " deg\n";
    }
  }
  if (r.contains("discrete")) {
    const json& d = r["discrete"];
    o << "discrete (" << d["method"].get<std::string>() << ", ts = " << fmt_num(d["ts"].get<double>()) << " s): ("
      << polynomial_text(d["num"].get<std::vector<double>>(), 'z') << ") / ("
      << polynomial_text(d["den"].get<std::vector<double>>(), 'z') << "), "
      << (d["stable"].get<bool>() ? "stable" : "not stable") << "\n";
  }
  return o.str();
}

}  // namespace dmbd::apps
