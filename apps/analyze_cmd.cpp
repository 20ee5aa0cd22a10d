#include "analyze_cmd.hpp"

#include <cmath>
#include <iostream>
#include <memory>
#include <optional>

#include "analyze.hpp"
#include "analyze_sweep.hpp"
#include "cli_values.hpp"
#include "dmbd/base/error.hpp"
#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/frequency.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "dmbd/diagrams/diagram_source.hpp"

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
  std::shared_ptr<const diagrams::DiagramSource> source;  // parsed once: --sweep evaluates it again
  std::shared_ptr<const diagrams::Diagram> diagram;
  std::optional<DiagramTransfer> interconnection;  // a diagram's
  bool discrete = false;
  std::string title;
};

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
    s.tf = b::Siso::from_tf(b::TransferFunction::parse(a.tf, params, s.discrete ? ts : 0.0));
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

// Where the transfer came from: the diagram and signals, or the expression; parameters.
void describe_source(nlohmann::json& report, const Args& a, const System& s, const b::ParameterMap& params) {
  if (!s.diagram) {
    report["expression"] = a.tf;
    report["parameters"] = params;
    return;
  }
  report["diagram"] = a.diagram;
  add_interconnection(report, *s.interconnection);
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
  AnalyzeRequest req;
  req.title = s.title;
  parse_discretisation(a, params, s, ts, req);
  const b::Siso& g = *s.tf;
  if (s.discrete) ts = g.ts();
  parse_frequencies(a, params, s.discrete ? 0.5 / ts : INFINITY, req);
  parse_step(a, params, req);
  req.bode_png = a.bode;
  req.step_png = a.step_plot;
  const std::optional<Sweep> sweep = a.sweep.empty() ? std::nullopt : std::optional(parse_sweep(a.sweep, *s.diagram, params));

  nlohmann::json report = analyze(g, req);
  describe_source(report, a, s, params);
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
