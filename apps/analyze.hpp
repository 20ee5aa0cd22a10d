#pragma once
// `dmbd analyze`: the analysis report of one SISO transfer (a transfer function, or the
// transfer between two signals of a diagram, of any size), as JSON, as a readable
// summary, and as plots.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "dmbd/blocks/discretize.hpp"
#include "dmbd/blocks/siso.hpp"
#include "dmbd/blocks/zpk.hpp"
#include "dmbd/diagrams/diagram.hpp"

namespace dmbd::apps {

struct AnalyzeRequest {
  std::vector<double> freq_hz;           // Bode points (empty: none in the report)
  std::optional<std::pair<double, int>> step;  // t_end (s), samples
  std::optional<blocks::C2dMethod> c2d;
  double c2d_ts = 0.0;
  double prewarp_hz = 0.0;
  std::string bode_png, step_png;        // plots to write (empty: none)
  std::string title;                     // plot titles
  // A dead time exp(-s*T) of a continuous --tf: the analysed transfer holds its Padé
  // approximant; --c2d discretises `undelayed` with the delay itself, exactly.
  double delay_s = 0.0;
  std::optional<blocks::TransferFunction> undelayed;
  // The transfer is taken as a loop transfer function L (--tf, as python-control's
  // margin() takes any transfer; a diagram's --loop-at): gain and phase margins and
  // their crossovers are reported. False for a diagram's --from/--to, a transfer
  // between two signals (a closed loop, a sensitivity), which is no loop: no margins.
  bool loop = true;
};

// A diagram's transfer between two signals (`loop_at` empty) or its loop transfer at
// `loop_at`, taken apart in state space (blocks::Siso), with the verdict on every mode
// of the interconnection (`internal`: those the transfer does not see included).
// InputError unless both signals are scalar.
struct DiagramTransfer {
  blocks::Siso transfer;
  blocks::Stability internal;
  int states;
};
DiagramTransfer diagram_transfer(const diagrams::Diagram& d, const std::string& from, const std::string& to,
                                 const std::string& loop_at);
// The report's keys about the interconnection: internally_stable, internal_stability,
// states, factors.
void add_interconnection(nlohmann::json& report, const DiagramTransfer& t);

// Computes every figure of the report (docs/analyze.md). Throws InputError when the
// request does not fit the system (an improper TF where a step response or c2d is
// asked for).
nlohmann::json analyze(const blocks::Siso& g, const AnalyzeRequest& req);
// Writes the requested plots from a report (atomically; nothing is written if a
// target folder does not exist).
void write_plots(const blocks::Siso& g, const nlohmann::json& report, const AnalyzeRequest& req);
// A readable multi-line summary of a report.
std::string summary(const nlohmann::json& report);
// Descending-power polynomial as text in `var`, e.g. "s^2 + 533.1 s + 1.421e+05".
std::string polynomial_text(const std::vector<double>& descending, char var);
// Poles as [re, im] pairs, and the largest real part of their s-plane equivalents
// (log(z)/ts for a discrete system); null when there are none.
nlohmann::json roots_json(const std::vector<blocks::Complex>& roots);
nlohmann::json max_real_pole(const std::vector<blocks::Complex>& poles, double ts);

}  // namespace dmbd::apps
