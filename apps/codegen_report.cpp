#include "codegen_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "dmbd/codegen/quantisation.hpp"
#include "dmbd/codegen/ranges.hpp"
#include "dmbd/codegen/verify.hpp"

namespace dmbd::apps {

namespace cg = dmbd::codegen;
using nlohmann::json;

namespace {

const char* kind_name(cg::SlotKind k) {
  switch (k) {
    case cg::SlotKind::Input: return "input";
    case cg::SlotKind::Output: return "output";
    case cg::SlotKind::State: return "state";
    default: return "signal";
  }
}

// Every signal's guaranteed range (L1 norms of impulse responses from the input ranges)
// and the Q format it would take in 16- and 32-bit words; the blocks.
void add_slots_and_blocks(json& report, const cg::LoopProgram& program, const std::vector<Range>& ranges) {
  const std::vector<double> bounds = cg::slot_bounds(program, ranges);
  json slots = json::array();
  for (size_t k = 0; k < program.slots.size(); ++k) {
    const auto& sl = program.slots[k];
    json j{{"name", sl.name}, {"kind", kind_name(sl.kind)}, {"origin", sl.origin}, {"unit", sl.unit}};
    if (std::isfinite(bounds[k])) {
      j["bound"] = bounds[k];
      j["q16"] = cg::q_format(bounds[k], 16);
      j["q32"] = cg::q_format(bounds[k], 32);
    } else {
      j["bound"] = nullptr;  // not bounded (an integrator, or an unstable loop)
    }
    slots.push_back(j);
  }
  report["slots"] = slots;
  json blocks = json::array();
  for (const auto& bi : program.blocks)
    blocks.push_back({{"path", bi.path}, {"type", bi.type}, {"fields", bi.summary}, {"realisation", bi.realisation}});
  report["blocks"] = blocks;
}

json error_bound_json(const cg::LoopProgram& program, const cg::ErrorBound& bound) {
  json names = json::array();
  for (int k : program.outputs) names.push_back(program.slots[static_cast<size_t>(k)].name);
  return {{"steps", bound.horizon},
          {"seconds", bound.horizon * program.ts},
          {"outputs", names},
          {"bound", bound.over_horizon},
          {"rounding", bound.rounding},
          {"coefficients", bound.coefficients},
          {"rounding_sources", bound.sources},
          {"hypothesis", "at every step from reset, no saturation block engaged (input outside its limits) in the exact "
                         "or the fixed program and no word saturated in the fixed one; the bound then holds at every "
                         "step before the first that breaks it"}};
}

// An output whose predicted error may exceed its own range: the word is too narrow.
void warn_bound_beyond_range(json& report, const cg::LoopProgram& program, const cg::ErrorBound& bound,
                             const CodegenSource& source, int word_bits) {
  for (size_t j = 0; j < program.outputs.size() && j < source.output_ranges.size(); ++j) {
    if (!source.output_ranges[j]) continue;
    const double range = std::max(std::abs(source.output_ranges[j]->first), std::abs(source.output_ranges[j]->second));
    const double e = bound.over_horizon[j];
    if (e <= range) continue;
    const std::string unit = j < source.output_units.size() && !source.output_units[j].empty() ? " " + source.output_units[j] : "";
    report["warnings"].push_back(fmt::format(
        "output '{}': the predicted {}-bit fixed-point error bound over {} steps, {:.4g}{}, exceeds the output's range "
        "(+-{:.4g}{}): its value may be wrong by more than its whole range (use a 32-bit word, or narrow the input "
        "ranges)",
        program.slots[static_cast<size_t>(program.outputs[j])].name, word_bits, bound.horizon, e, unit, range, unit));
  }
}

json roots(const std::vector<blocks::Complex>& z) {
  json a = json::array();
  for (const auto& p : z) a.push_back({p.real(), p.imag()});
  return a;
}

// What quantisation does to the loop: formats, the predicted worst-case output error,
// the poles and the frequency response of the quantised program.
void add_quantisation(json& report, const cg::LoopProgram& program, const cg::FixedProgram& fx,
                      const CodegenSource& source) {
  json slots = report["slots"];
  for (size_t k = 0; k < program.slots.size(); ++k) {
    slots[k]["q"] = fx.q[k];
    slots[k]["bits"] = fx.bits[k];  // the word: fx.word_bits, or fx.state_bits where widened
    slots[k]["range"] = fx.simulated[k] ? "simulated" : "guaranteed";
    if (fx.simulated[k]) slots[k]["bound"] = fx.bound[k];
  }
  report["slots"] = slots;
  // The worst case of |fixed - exact| per output: over any number of steps (null where
  // rounding errors accumulate without bound), and over the verification run's length.
  const cg::ErrorBound bound = cg::predicted_error_bound(program, fx, source.input_ranges, cg::kVerifySamples);
  json pb = json::array();
  for (double v : bound.infinite) pb.push_back(std::isfinite(v) ? json(v) : json(nullptr));
  report["predicted_error_bound"] = pb;
  report["predicted_error_bound_horizon"] = error_bound_json(program, bound);
  json wide = json::array();
  for (size_t k = 0; k < program.slots.size(); ++k)
    if (fx.bits[k] != fx.word_bits) wide.push_back(program.slots[k].name);
  report["word_bits"] = {{"word", fx.word_bits}, {"state", fx.state_bits}, {"widened", wide}};
  warn_bound_beyond_range(report, program, bound, source, fx.word_bits);
  const cg::QuantisationEffect q = cg::quantisation_effect(program, fx.quantised);
  report["poles_exact"] = roots(q.poles_exact);
  report["poles_quantised"] = roots(q.poles_quantised);
  report["frequency_response_deviation"] = {{"max_db", q.max_db}, {"max_deg", q.max_deg}};
}

}  // namespace

json codegen_report(const cg::LoopProgram& program, const cg::FixedProgram* fixed, const CodegenSource& source) {
  json report{{"name", program.name},
              {"source", source.text},
              {"rate_hz", program.rate_hz},
              {"method", blocks::to_string(program.method)},
              {"scalar", source.scalar},
              {"language", source.language},
              {"warnings", program.warnings}};
  add_slots_and_blocks(report, program, source.input_ranges);
  if (fixed) add_quantisation(report, program, *fixed, source);
  return report;
}

}  // namespace dmbd::apps
