#pragma once
// `dmbd analyze`: the analysis report of one SISO transfer function, as JSON, as a
// readable summary, and as plots. Diagram analysis (a later issue) reduces a diagram
// to a transfer function between two signals and reuses this report.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "dmbd/blocks/discretize.hpp"
#include "dmbd/blocks/transfer_function.hpp"

namespace dmbd::apps {

struct AnalyzeRequest {
  std::vector<double> freq_hz;           // Bode points (empty: none in the report)
  std::optional<std::pair<double, int>> step;  // t_end (s), samples
  std::optional<blocks::C2dMethod> c2d;
  double c2d_ts = 0.0;
  double prewarp_hz = 0.0;
  std::string bode_png, step_png;        // plots to write (empty: none)
  std::string title;                     // plot titles
};

// Computes every figure of the report. Throws InputError when the request does not
// fit the system (an improper TF where a step response or c2d is asked for).
nlohmann::json analyze(const blocks::TransferFunction& g, const AnalyzeRequest& req);
// Writes the requested plots from a report (atomically; nothing is written if a
// target folder does not exist).
void write_plots(const blocks::TransferFunction& g, const nlohmann::json& report, const AnalyzeRequest& req);
// A readable multi-line summary of a report.
std::string summary(const nlohmann::json& report);
// Descending-power polynomial as text in `var`, e.g. "s^2 + 533.1 s + 1.421e+05".
std::string polynomial_text(const std::vector<double>& descending, char var);

}  // namespace dmbd::apps
