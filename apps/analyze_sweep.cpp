#include "analyze_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "analyze.hpp"
#include "cli_values.hpp"
#include "dmbd/base/error.hpp"
#include "dmbd/base/number_text.hpp"
#include "dmbd/blocks/exact_frequency.hpp"
#include "dmbd/blocks/frequency.hpp"
#include "dmbd/blocks/zpk.hpp"

namespace dmbd::apps {

namespace b = dmbd::blocks;
using nlohmann::json;

Sweep parse_sweep(const std::string& text, const diagrams::Diagram& d, const b::ParameterMap& params) {
  const auto eq = text.find('=');
  const auto parts = split(eq == std::string::npos ? "" : text.substr(eq + 1), ':');
  if (eq == std::string::npos || (parts.size() != 3 && parts.size() != 4) ||
      (parts.size() == 4 && parts[3] != "log" && parts[3] != "lin"))
    throw InputError("--sweep '" + text + "': expected NAME=LO:HI:N or NAME=LO:HI:N:log");
  Sweep s;
  s.parameter = text.substr(0, eq);
  if (!d.parameters().count(s.parameter))
    throw InputError("--sweep '" + text + "': the diagram has no parameter '" + s.parameter + "'");
  const double lo = parse_number(parts[0], "--sweep", params), hi = parse_number(parts[1], "--sweep", params);
  const int n = parse_count(parts[2], "--sweep");
  const bool log = parts.size() == 4 && parts[3] == "log";
  if (log && !(lo > 0.0 && hi > 0.0)) throw InputError("--sweep '" + text + "': a log sweep needs LO, HI > 0");
  if (log) {
    s.values = b::logspace(lo, hi, n);
  } else {
    for (int k = 0; k < n; ++k) s.values.push_back(n == 1 ? lo : lo + (hi - lo) * k / (n - 1));
  }
  return s;
}

namespace {

json sweep_point(const diagrams::Diagram& d, double value, const TransferChoice& c) {
  const DiagramTransfer t = diagram_transfer(d, c.from, c.to, c.loop_at);
  const b::Zpk& z = t.transfer.zpk();
  const b::Stability st = b::stability(z);
  const std::vector<b::Complex> poles = z.all_poles();
  const std::optional<double> dc = z.dc_gain(),
                              bw = b::bandwidth(z, [&t](double w) { return t.transfer.response(w); });
  return {{"value", value},
          {"stable", st == b::Stability::Stable},
          {"stability", b::to_string(st)},
          {"internally_stable", t.internal == b::Stability::Stable},
          {"poles", roots_json(poles)},
          {"max_real_pole", max_real_pole(poles, z.ts())},
          {"dc_gain", dc ? json(*dc) : json(nullptr)},
          {"bandwidth_hz", bw ? json(*bw / (2 * M_PI)) : json(nullptr)}};
}

}  // namespace

json run_sweep(const diagrams::DiagramSource& source, const b::ParameterMap& params, const Sweep& sweep,
               const TransferChoice& choice) {
  json out = json::array();
  for (double v : sweep.values) {
    b::ParameterMap p = params;
    p[sweep.parameter] = v;
    out.push_back(sweep_point(*source.evaluate(p), v, choice));
  }
  return out;
}

std::string sweep_summary(const json& report) {
  int unstable = 0;
  double worst = -INFINITY;
  for (const auto& p : report["sweep"]) {
    unstable += p["stable"].get<bool>() ? 0 : 1;
    if (!p["max_real_pole"].is_null()) worst = std::max(worst, p["max_real_pole"].get<double>());
  }
  std::ostringstream s;
  s << "sweep of " << report["sweep_parameter"].get<std::string>() << " over " << report["sweep"].size() << " values: "
    << (unstable ? std::to_string(unstable) + " unstable" : std::string("all stable")) << ", largest real part of a pole "
    << worst << "\n";
  const std::string name = report["sweep_parameter"].get<std::string>();
  for (const auto& p : report["sweep"]) {
    s << "  " << name << " = " << number_text(p["value"].get<double>()) << ": " << p["stability"].get<std::string>()
      << (p["internally_stable"].get<bool>() ? "" : " (not internally stable)");
    if (!p["max_real_pole"].is_null()) s << ", largest real part of a pole " << number_text(p["max_real_pole"].get<double>()) << " rad/s";
    if (!p["bandwidth_hz"].is_null()) s << ", bandwidth " << number_text(p["bandwidth_hz"].get<double>()) << " Hz";
    s << "\n";
  }
  return s.str();
}

}  // namespace dmbd::apps
