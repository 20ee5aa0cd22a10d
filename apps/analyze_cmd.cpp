#include "analyze_cmd.hpp"

#include <cmath>
#include <iostream>
#include <memory>
#include <optional>

#include "analyze.hpp"
#include "analyze_sweep.hpp"
#include "cli_values.hpp"
#include "dmbd/base/error.hpp"
#include "dmbd/base/number_text.hpp"
#include "dmbd/blocks/delay.hpp"
#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/frequency.hpp"
#include "dmbd/blocks/sampled.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "dmbd/diagrams/diagram_source.hpp"
#include "dmbd/diagrams/flat.hpp"

namespace dmbd::apps {

namespace b = dmbd::blocks;
using Args = AnalyzeCommand::Args;

AnalyzeCommand::AnalyzeCommand(CLI::App& app)
    : Command(app, "analyze",
              "Poles, zeros, DC gain, margins, bandwidth, Bode, step response and discretisation of a transfer function") {
  cmd_->add_option("diagram", a_.diagram, "A diagram file (YAML, docs/diagram-format.md)");
  cmd_->add_option("--tf", a_.tf, "Rational expression in s (or z with --ts), e.g. '1/((s/wc)^2 + sqrt(2)*s/wc + 1)'");
  cmd_->add_option("--from", a_.from, "Diagram signal where the input is injected (an input, block.port, ...)");
  cmd_->add_option("--to", a_.to, "Diagram signal that is measured");
  cmd_->add_option("--loop-at", a_.loop_at, "Loop transfer at a break point (block.port), for margins");
  cmd_->add_option("--sweep", a_.sweep, "NAME=LO:HI:N[:log]: stability over a parameter range (diagrams)");
  cmd_->add_option("--pade", a_.pade, "Order of the Padé approximant of a delay exp(-s*T) in a continuous --tf (default 3)");
  cmd_->add_option("--minreal", a_.minreal, "Cancel pole/zero pairs within this relative distance |z - p| <= TOL |p|");
  cmd_->add_option("--param", a_.params, "NAME=VALUE (VALUE may use earlier parameters: wc=2*pi*fc); repeatable");
  cmd_->add_flag("--json", a_.json, "Print one JSON object instead of the summary");
  cmd_->add_option("--freq", a_.freq, "Frequencies for the Bode report, F1,F2,... (Hz)");
  cmd_->add_option("--freq-range", a_.freq_range, "Log-spaced Bode frequencies LO:HI:N (Hz)");
  cmd_->add_option("--step", a_.step, "Step response T_END:N (N samples from 0 to T_END seconds)");
  cmd_->add_option("--c2d", a_.c2d, "Discretise: tustin, zoh or backward-euler (needs --ts)");
  cmd_->add_option("--ts", a_.ts, "Sample time in seconds (for --c2d, or for an expression in z)");
  cmd_->add_option("--prewarp", a_.prewarp, "Tustin pre-warp frequency (Hz)");
  cmd_->add_option("--bode", a_.bode, "Write a Bode plot (PNG)");
  cmd_->add_option("--step-plot", a_.step_plot, "Write a step-response plot (PNG)");
}

namespace {

// What is analysed: a transfer function, and for a diagram the diagram and figures of
// the whole interconnection.
struct System {
  std::optional<b::Siso> tf;
  // A --tf's dead time exp(-s*T) (s), the transfer without it, and how it entered the
  // analysed transfer: a Padé approximant's order, or whole samples when discrete.
  double delay_s = 0.0;
  std::optional<b::TransferFunction> undelayed;
  int pade_order = 0, delay_samples = 0;
  std::shared_ptr<const diagrams::DiagramSource> source;  // parsed once: --sweep evaluates it again
  std::shared_ptr<const diagrams::Diagram> diagram;
  std::optional<DiagramTransfer> interconnection;  // a diagram's
  bool discrete = false;
  std::string title;
};

int parse_order(const std::string& text) {
  char* end = nullptr;
  const long n = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || n < 0 || n > 20) throw InputError("--pade '" + text + "': expected an order 0..20");
  return static_cast<int>(n);
}

// g e^{-s T}: in z, T must be whole samples (z = e^{s ts}, so e^{-s T} = z^-n exactly);
// in s, the Padé approximant of the given order stands for it, and --c2d uses the delay.
b::TransferFunction delayed(System& s, const b::TransferFunction& g, double ts, int pade_order) {
  if (s.discrete) {
    const auto n = b::whole_samples(s.delay_s, ts);
    if (!n)
      throw InputError("exp(-s*" + number_text(s.delay_s) + ") is not a whole number of samples of " + number_text(ts) +
                       " s (in z, a delay is z^-n)");
    s.delay_samples = *n;
    return g * b::sample_delay(*n, ts);
  }
  s.undelayed = g;
  s.pade_order = pade_order;
  return g * b::pade(s.delay_s, pade_order);
}

System read_tf(const Args& a, const b::ParameterMap& params, double ts) {
  if (!a.from.empty() || !a.to.empty() || !a.loop_at.empty() || !a.sweep.empty())
    throw InputError("--from, --to, --loop-at and --sweep apply to a diagram, not to --tf");
  System s;
  try {
    const b::Expression expr = b::Expression::parse(a.tf);
    s.discrete = expr.uses('z');
    if (s.discrete && expr.uses('s')) throw InputError("uses both s and z");
    if (s.discrete && ts == 0.0) throw InputError("an expression in z needs --ts SECONDS");
  } catch (InputError& e) {
    e.prepend("--tf '" + a.tf + "': ");
    throw;
  }
  if (ts > 0.0 && !s.discrete && a.c2d.empty()) throw InputError("--ts is used with --c2d or with an expression in z");
  try {
    const b::Expression expr = b::Expression::parse(a.tf);
    const b::Rational r = expr.evaluate_rational(params, s.discrete ? 'z' : 's', true);
    b::TransferFunction g = b::TransferFunction(r.num, r.den, s.discrete ? ts : 0.0).with_factors(r.num_factors, r.den_factors);
    s.delay_s = r.delay_s;
    if (s.delay_s > 0.0) g = delayed(s, g, ts, a.pade.empty() ? 3 : parse_order(a.pade));
    s.tf = b::Siso::from_tf(g);
  } catch (InputError& e) {
    e.prepend("--tf '" + a.tf + "': ");
    throw;
  }
  s.title = a.tf;
  return s;
}

System read_diagram(const Args& a, const b::ParameterMap& params) {
  if (a.loop_at.empty() && (a.from.empty() || a.to.empty()))
    throw InputError("a diagram needs --from SIGNAL and --to SIGNAL (or --loop-at SIGNAL)");
  if (!a.loop_at.empty() && (!a.from.empty() || !a.to.empty())) throw InputError("give either --loop-at or --from/--to");
  System s;
  s.source = diagrams::DiagramSource::load(a.diagram);
  s.diagram = s.source->evaluate(params);
  s.discrete = s.diagram->is_discrete();
  if (!a.ts.empty() && a.c2d.empty()) throw InputError("--ts is used with --c2d");
  s.interconnection = diagram_transfer(*s.diagram, a.from, a.to, a.loop_at);
  s.tf = s.interconnection->transfer;
  s.title = s.diagram->name() + (a.loop_at.empty() ? ": " + a.from + " -> " + a.to : ": loop at " + a.loop_at);
  return s;
}

void parse_discretisation(const Args& a, const b::ParameterMap& params, const System& s, double ts, AnalyzeRequest& req) {
  if (s.discrete && !a.c2d.empty()) throw InputError("--c2d: the system is already discrete");
  if (!a.c2d.empty()) {
    req.c2d = b::parse_c2d_method(a.c2d);
    if (ts == 0.0) throw InputError("--c2d " + a.c2d + " needs --ts SECONDS");
    req.c2d_ts = ts;
  }
  if (a.prewarp.empty()) return;
  if (!req.c2d || *req.c2d != b::C2dMethod::Tustin) throw InputError("--prewarp is used with --c2d tustin");
  req.prewarp_hz = parse_number(a.prewarp, "--prewarp", params);
  if (!(req.prewarp_hz > 0.0) || req.prewarp_hz >= 0.5 / ts)
    throw InputError("--prewarp '" + a.prewarp + "': expected a frequency between 0 and the Nyquist frequency " +
                     std::to_string(0.5 / ts) + " Hz");
}

void parse_frequencies(const Args& a, const b::ParameterMap& params, double nyquist_hz, AnalyzeRequest& req) {
  if (!a.freq.empty() && !a.freq_range.empty()) throw InputError("give either --freq or --freq-range, not both");
  auto check = [&](double f, const std::string& opt, const std::string& text) {
    if (!(f > 0.0) || !std::isfinite(f)) throw InputError(opt + " '" + text + "': frequencies must be > 0 Hz");
    if (f > nyquist_hz)
      throw InputError(opt + " '" + text + "': above the Nyquist frequency " + std::to_string(nyquist_hz) + " Hz");
  };
  if (!a.freq.empty()) {
    for (const std::string& f : split(a.freq, ',')) {
      if (f.empty()) throw InputError("--freq '" + a.freq + "': expected F1,F2,... in Hz");
      req.freq_hz.push_back(parse_number(f, "--freq", params));
      check(req.freq_hz.back(), "--freq", a.freq);
    }
  }
  if (!a.freq_range.empty()) {
    const auto parts = split(a.freq_range, ':');
    if (parts.size() != 3) throw InputError("--freq-range '" + a.freq_range + "': expected LO:HI:N (Hz, log-spaced)");
    const double lo = parse_number(parts[0], "--freq-range", params), hi = parse_number(parts[1], "--freq-range", params);
    const int n = parse_count(parts[2], "--freq-range");
    check(lo, "--freq-range", a.freq_range);
    check(hi, "--freq-range", a.freq_range);
    if (hi < lo) throw InputError("--freq-range '" + a.freq_range + "': HI must not be below LO");
    req.freq_hz = b::logspace(lo, hi, n);
  }
}

void parse_step(const Args& a, const b::ParameterMap& params, AnalyzeRequest& req) {
  if (a.step.empty()) return;
  const auto parts = split(a.step, ':');
  if (parts.size() != 2) throw InputError("--step '" + a.step + "': expected T_END:N (seconds, samples)");
  const double t_end = parse_number(parts[0], "--step", params);
  if (!(t_end > 0.0) || !std::isfinite(t_end)) throw InputError("--step '" + a.step + "': T_END must be > 0 s");
  const int n = parse_count(parts[1], "--step");
  if (n < 2) throw InputError("--step '" + a.step + "': N must be at least 2 samples");
  req.step = std::make_pair(t_end, n);
}

// The blocks whose law the linear analysis replaces by its linear part: a saturation
// (the identity) and a pid with output limits (the unsaturated P + I/s + D s/(tau s + 1),
// its anti-windup left out), with subsystems' blocks under their paths.
nlohmann::json linearised_blocks(const diagrams::Diagram& d) {
  const diagrams::FlatDiagram f(d);
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t k = 0; k < f.atomic.size(); ++k) {
    const diagrams::Block& bl = *f.atomic[k];
    if (bl.type == diagrams::BlockType::Saturation)
      out.push_back({{"block", f.atomic_name[k]}, {"type", "saturation"}, {"analysed_as", "the identity (its limits left out)"}});
    if (bl.pid && bl.pid->output_limits)
      out.push_back({{"block", f.atomic_name[k]},
                     {"type", "pid"},
                     {"analysed_as", std::string("the unsaturated law P + I/s + D s/(tau s + 1) (its output_limits and anti_windup ") +
                                         diagrams::to_string(bl.pid->anti_windup) + " left out)"}});
  }
  return out;
}

// Where the transfer came from: the diagram and signals, or the expression; parameters.
void describe_source(nlohmann::json& report, const Args& a, const System& s, const b::ParameterMap& params) {
  if (!s.diagram) {
    report["expression"] = a.tf;
    report["parameters"] = params;
    return;
  }
  report["diagram"] = a.diagram;
  add_interconnection(report, *s.interconnection);
  report["linearised"] = linearised_blocks(*s.diagram);
  if (a.loop_at.empty()) {
    report["from"] = a.from;
    report["to"] = a.to;
  } else {
    report["loop_at"] = a.loop_at;
  }
  nlohmann::json ps;
  for (const auto& name : s.diagram->parameter_order()) ps[name] = s.diagram->parameters().at(name);
  report["parameters"] = ps;
}

double parse_tolerance(const std::string& text, const b::ParameterMap& params) {
  const double tol = parse_number(text, "--minreal", params);
  if (!(tol >= 0.0) || !(tol < 1.0)) throw InputError("--minreal '" + text + "': expected a relative tolerance in [0, 1)");
  return tol;
}

// A --tf's delay, and a diagram's sampled plants (continuous subsystems of a discrete
// diagram, each one block with its exact sampled-data model).
void describe_delay(nlohmann::json& report, const System& s) {
  if (s.delay_s > 0.0) {
    report["delay_s"] = s.delay_s;
    if (s.discrete) report["delay_samples"] = s.delay_samples;
    else report["pade_order"] = s.pade_order;
  }
  if (!s.diagram) return;
  nlohmann::json plants = nlohmann::json::array();
  for (const diagrams::Block& bl : s.diagram->blocks())
    if (bl.sampled)
      plants.push_back({{"block", bl.name},
                        {"file", bl.subsystem->file()},
                        {"ts", s.diagram->ts()},
                        {"input_delays_s", bl.input_delays_s},
                        {"output_delay_samples", bl.output_delay_samples},
                        {"states", bl.model.num_states()}});
  if (!plants.empty()) report["sampled_plants"] = plants;
}

}  // namespace

int AnalyzeCommand::run() {
  const Args& a = a_;
  a_.tf_given = cmd_->get_option("--tf")->count() > 0;
  const b::ParameterMap params = parse_params(a.params);
  if (a.diagram.empty() != a.tf_given)
    throw InputError(!a.tf_given ? "give a diagram file or --tf EXPR" : "give either a diagram file or --tf, not both");
  // Every output is checked before anything is computed or written.
  if (!a.bode.empty()) check_output_file(a.bode, "--bode");
  if (!a.step_plot.empty()) check_output_file(a.step_plot, "--step-plot");
  double ts = 0.0;
  if (!a.ts.empty()) {
    ts = parse_number(a.ts, "--ts", params);
    if (!(ts > 0.0) || !std::isfinite(ts)) throw InputError("--ts '" + a.ts + "': the sample time must be > 0 s");
  }
  const System s = a.tf_given ? read_tf(a, params, ts) : read_diagram(a, params);
  if (!a.pade.empty() && s.pade_order == 0)
    throw InputError("--pade applies to a delay exp(-s*T) in a continuous --tf (a diagram's delays: analysis.pade_order)");
  AnalyzeRequest req;
  req.title = s.title;
  req.loop = !s.diagram || !a.loop_at.empty();
  req.delay_s = s.undelayed ? s.delay_s : 0.0;
  req.undelayed = s.undelayed;
  parse_discretisation(a, params, s, ts, req);
  std::vector<b::Complex> cancelled;
  const double tol = a.minreal.empty() ? 0.0 : parse_tolerance(a.minreal, params);
  const b::Siso g = a.minreal.empty() ? *s.tf : s.tf->minreal(tol, &cancelled);
  if (s.discrete) ts = g.ts();
  parse_frequencies(a, params, s.discrete ? 0.5 / ts : INFINITY, req);
  parse_step(a, params, req);
  req.bode_png = a.bode;
  req.step_png = a.step_plot;
  const std::optional<Sweep> sweep = a.sweep.empty() ? std::nullopt : std::optional(parse_sweep(a.sweep, *s.diagram, params));

  nlohmann::json report = analyze(g, req);
  describe_source(report, a, s, params);
  describe_delay(report, s);
  if (!a.minreal.empty()) report["minreal"] = {{"tolerance", tol}, {"cancelled", roots_json(cancelled)}};
  if (sweep) {
    report["sweep_parameter"] = sweep->parameter;
    report["sweep"] = run_sweep(*s.source, params, *sweep, {a.from, a.to, a.loop_at});
  }
  write_plots(g, report, req);
  if (a.json) {
    std::cout << report.dump() << "\n";
    return 0;
  }
  std::cout << summary(report);
  if (sweep) std::cout << sweep_summary(report);
  if (!req.bode_png.empty()) std::cout << "wrote " << req.bode_png << "\n";
  if (!req.step_png.empty()) std::cout << "wrote " << req.step_png << "\n";
  return 0;
}

}  // namespace dmbd::apps
