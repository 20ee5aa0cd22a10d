#pragma once
// A pid block with output limits lowered term by term (docs/codegen.md, "PID blocks").
#include <string>

#include "dmbd/diagrams/diagram.hpp"
#include "lower_parts.hpp"

namespace dmbd::codegen {

// The operations of a pid block whose law has output_limits, from its input slot e to
// its output slot y: the proportional term, the integral term (a state of its own,
// when the law has one) with its anti-windup, the filtered derivative (a first-order
// section, when it has one), their sum u and its clamp to the limits. `method`
// discretises the integral and the derivative. Returns the realisation's description.
std::string lower_limited_pid(Builder& bld, BlockCode& code, const diagrams::PidLaw& law, double ts,
                              blocks::C2dMethod method, int e, int y, int block, const std::string& path);

}  // namespace dmbd::codegen
