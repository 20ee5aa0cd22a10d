#pragma once
// `dmbd analyze DIAGRAM --sweep NAME=LO:HI:N[:log]`: the analysed transfer's stability,
// poles, DC gain and bandwidth at each value of one parameter.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "dmbd/blocks/expression.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "dmbd/diagrams/diagram_source.hpp"

namespace dmbd::apps {

struct Sweep {
  std::string parameter;
  std::vector<double> values;
};

// Parses NAME=LO:HI:N[:lin|log] against the diagram's parameters.
Sweep parse_sweep(const std::string& text, const diagrams::Diagram& d, const blocks::ParameterMap& params);

// Which transfer of the diagram is analysed: from -> to, or the loop at a break point.
struct TransferChoice {
  std::string from, to, loop_at;
};

// One JSON object per value: value, stable, stability, internally_stable, poles,
// max_real_pole, dc_gain, bandwidth_hz (the transfer taken apart as for the report:
// apps::diagram_transfer). The source is evaluated at each value (its file is not read
// again).
nlohmann::json run_sweep(const diagrams::DiagramSource& source, const blocks::ParameterMap& params, const Sweep& sweep,
                         const TransferChoice& choice);

// "sweep of K over 20 values: 3 unstable, largest real part of a pole 0.5".
std::string sweep_summary(const nlohmann::json& report);

}  // namespace dmbd::apps
