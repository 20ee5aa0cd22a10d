#include "tune_cmd.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <iostream>

#include "cli_values.hpp"
#include "dmbd/base/error.hpp"
#include "dmbd/diagrams/tune.hpp"

namespace dmbd::apps {

TuneCommand::TuneCommand(CLI::App& app)
    : Command(app, "tune",
              "Tune a PD position loop by the paper's procedure (raise D to the stability limit less a gain margin, "
              "then the highest P without overshoot), or to critical damping at a natural frequency") {
  cmd_->add_option("diagram", diagram_, "A diagram file (YAML)")->required();
  cmd_->add_option("--from", from_, "Reference signal of the closed loop (e.g. q_d)")->required();
  cmd_->add_option("--to", to_, "Measured signal of the closed loop (e.g. q)")->required();
  cmd_->add_option("--p", p_, "Parameter name of the proportional gain")->required();
  cmd_->add_option("--d", d_, "Parameter name of the derivative gain")->required();
  cmd_->add_option("--gain-margin-db", gain_margin_db_, "Back-off of D from its stability limit (dB, default 6)");
  cmd_->add_option("--max-overshoot", overshoot_, "Largest step overshoot that counts as none (%, default 0.5)");
  cmd_->add_option("--natural-frequency-hz", wn_hz_,
                   "Critical damping at this closed-loop natural frequency instead (controller 3 of the paper)");
  cmd_->add_option("--param", params_, "NAME=VALUE parameter override; repeatable");
  cmd_->add_flag("--json", json_, "Print one JSON object");
}

int TuneCommand::run() {
  const blocks::ParameterMap params = parse_params(params_);
  const double overshoot = parse_number(overshoot_, "--max-overshoot");
  if (!(overshoot >= 0.0)) throw InputError("--max-overshoot must be >= 0 %");
  diagrams::PdTuningResult r;
  const bool critical = !wn_hz_.empty();
  if (critical) {
    const double f = parse_number(wn_hz_, "--natural-frequency-hz", params);
    if (!(f > 0.0)) throw InputError("--natural-frequency-hz must be > 0");
    r = diagrams::tune_critical({diagram_, from_, to_, p_, d_, params, 2 * M_PI * f, overshoot});
  } else {
    const double gm = parse_number(gain_margin_db_, "--gain-margin-db");
    if (!(gm >= 0.0)) throw InputError("--gain-margin-db must be >= 0");
    r = diagrams::tune_pd({diagram_, from_, to_, p_, d_, params, gm, overshoot});
  }
  const double wn_hz = r.figures.natural_frequency_rad_s / (2 * M_PI);
  if (json_) {
    nlohmann::json j{{"diagram", diagram_},  {"p_param", p_},
                     {"d_param", d_},        {"p", r.p},
                     {"d", r.d},             {"stable", r.figures.stable},
                     {"overshoot_pct", r.figures.overshoot_pct}, {"natural_frequency_hz", wn_hz},
                     {"rise_time_s", r.figures.rise_time_s},     {"evaluations", r.evaluations}};
    if (!critical) j["d_critical"] = r.d_critical;
    std::cout << j.dump() << "\n";
    return 0;
  }
  if (!critical) std::cout << d_ << " at the stability limit (" << p_ << " = 0): " << r.d_critical << "\n";
  std::cout << p_ << " = " << r.p << ", " << d_ << " = " << r.d << "\n"
            << "closed loop " << from_ << " -> " << to_ << ": " << (r.figures.stable ? "stable" : "NOT stable")
            << ", overshoot " << r.figures.overshoot_pct << " %, natural frequency " << wn_hz << " Hz, rise time "
            << r.figures.rise_time_s * 1e3 << " ms (" << r.evaluations << " evaluations)\n";
  return 0;
}

}  // namespace dmbd::apps
