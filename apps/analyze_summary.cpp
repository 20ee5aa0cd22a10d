// The readable summary of an analysis report (`dmbd analyze` without --json): the
// transfer, its roots, gain figures, margins, step figures and frequency response as text.
#include <fmt/format.h>

#include <cmath>
#include <sstream>

#include "analyze.hpp"

namespace dmbd::apps {

using nlohmann::json;

namespace {

constexpr double kTwoPi = 2.0 * M_PI;

std::string fmt_num(double v) { return fmt::format("{:.6g}", v); }

std::string fmt_opt(const json& j, const char* unit, double scale = 1.0) {
  if (j.is_null()) return "none";
  return fmt_num(j.get<double>() * scale) + unit;
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

namespace {

// Roots, each conjugate pair once, runs of equal roots as one line with their count.
void list_roots(std::ostringstream& o, const char* name, const json& list, char var) {
  o << name << ":";
  if (list.empty()) o << " none";
  o << "\n";
  for (size_t k = 0; k < list.size();) {
    const double re = list[k][0].get<double>(), im = list[k][1].get<double>();
    size_t n = 1;
    while (k + n < list.size() && list[k + n][0].get<double>() == re && list[k + n][1].get<double>() == im) ++n;
    k += n;
    if (im < 0) continue;  // print each conjugate pair once
    o << "  " << fmt_num(re);
    if (im > 0) o << " ± " << fmt_num(im) << "j";
    if (var == 's') {
      const double wn = std::hypot(re, im);
      if (wn > 0) o << fmt::format("   (|p| = {} rad/s = {} Hz, zeta = {:.4g})", fmt_num(wn), fmt_num(wn / kTwoPi), -re / wn);
    } else {
      // Near the circle |z| is shown as its distance from 1 (1 - 5e-07, not 1).
      const double m = std::hypot(re, im);
      if (m != 1.0 && std::abs(m - 1.0) < 1e-4) {
        o << fmt::format("   (|z| = 1 {} {:.3g})", m < 1.0 ? "-" : "+", std::abs(m - 1.0));
      } else {
        o << fmt::format("   (|z| = {:.6g})", m);
      }
    }
    if (n > 1) o << "   x " << n;
    o << "\n";
  }
}

// A --tf's delay, cancelled pole/zero pairs, and a diagram's sampled plants.
void describe_delays(std::ostringstream& o, const json& r) {
  if (r.contains("pade_order"))
    o << "delay: exp(-s*" << fmt_num(r["delay_s"].get<double>()) << ") as its Padé approximant of order "
      << r["pade_order"].get<int>() << " (--c2d discretises the delay itself)\n";
  if (r.contains("delay_samples"))
    o << "delay: exp(-s*" << fmt_num(r["delay_s"].get<double>()) << ") = z^-" << r["delay_samples"].get<int>() << "\n";
  if (r.contains("minreal"))
    o << "--minreal " << fmt_num(r["minreal"]["tolerance"].get<double>()) << ": " << r["minreal"]["cancelled"].size()
      << " pole/zero pair(s) cancelled\n";
  if (!r.contains("sampled_plants")) return;
  for (const json& p : r["sampled_plants"]) {
    o << "sampled plant '" << p["block"].get<std::string>() << "': zero-order hold and sampler at "
      << fmt_num(p["ts"].get<double>()) << " s, exact (" << p["states"].get<int>() << " states";
    std::string delays;
    for (const json& d : p["input_delays_s"]) delays += (delays.empty() ? "" : ", ") + fmt_num(d.get<double>());
    o << "; input delays " << delays << " s";
    delays.clear();
    for (const json& d : p["output_delay_samples"]) delays += (delays.empty() ? "" : ", ") + std::to_string(d.get<int>());
    o << "; output delays " << delays << " samples)\n";
  }
}

// Margins of a loop transfer; a transfer between two signals is no loop and has none.
void describe_margins(std::ostream& o, const json& r) {
  if (!r.value("loop_transfer", true)) {
    o << "margins: none (a transfer between two signals is not a loop; --loop-at SIGNAL gives the loop's margins)\n";
    return;
  }
  o << "gain margin: " << fmt_opt(r["gain_margin_db"], " dB");
  if (!r["phase_crossover_hz"].is_null()) o << " at " << fmt_num(r["phase_crossover_hz"].get<double>()) << " Hz";
  o << "; phase margin: " << fmt_opt(r["phase_margin_deg"], " deg");
  if (!r["gain_crossover_hz"].is_null()) o << " at " << fmt_num(r["gain_crossover_hz"].get<double>()) << " Hz";
  o << "  (as a loop transfer function)\n";
}

const char* stability_text(const std::string& s) {
  if (s == "undecided") return "stability undecided at this precision (a pole's certified enclosure straddles the boundary)";
  return s == "stable" ? "stable" : s == "marginal" ? "marginally stable" : "not stable";
}

}  // namespace

std::string summary(const json& r) {
  std::ostringstream o;
  const char var = r["continuous"].get<bool>() ? 's' : 'z';
  if (r["num"].is_null()) {
    o << "G(" << var << "): order " << r["order"].get<int>()
      << " (its coefficients exceed double precision: see the poles and zeros)";
  } else {
    o << "G(" << var << ") = (" << polynomial_text(r["num"].get<std::vector<double>>(), var) << ") / ("
      << polynomial_text(r["den"].get<std::vector<double>>(), var) << ")";
  }
  if (!r["continuous"].get<bool>()) o << "   [ts = " << fmt_num(r["ts"].get<double>()) << " s]";
  o << "\n";
  o << "order " << r["order"].get<int>() << ", " << (r["proper"].get<bool>() ? "proper" : "improper") << ", "
    << stability_text(r["stability"].get<std::string>()) << "\n";
  describe_delays(o, r);
  list_roots(o, "poles", r["poles"], var);
  list_roots(o, "zeros", r["zeros"], var);
  if (!r["hidden_poles"].empty())
    o << r["hidden_poles"].size() << " more mode(s) the transfer does not see (hidden_poles in --json)\n";
  if (r["dc_gain"].is_null()) {
    o << "DC gain: infinite\n";
  } else {
    const double k = r["dc_gain"].get<double>();
    o << "DC gain: " << fmt_num(k);
    if (k != 0) o << fmt::format(" ({:.4g} dB)", 20 * std::log10(std::abs(k)));
    o << "\n";
  }
  o << "bandwidth (-3 dB): " << fmt_opt(r["bandwidth_hz"], " Hz") << "\n";
  describe_margins(o, r);
  if (r.contains("linearised"))
    for (const json& l : r["linearised"])
      o << "linearised: " << l["type"].get<std::string>() << " '" << l["block"].get<std::string>() << "' analysed as "
        << l["analysed_as"].get<std::string>() << "\n";
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
