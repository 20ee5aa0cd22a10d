#include "codegen_verify.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <iostream>

#include "dmbd/codegen/verify.hpp"

namespace dmbd::apps {

namespace cg = dmbd::codegen;
using nlohmann::json;

namespace {

json check_json(const cg::BoundCheck& c, const cg::ErrorBound& bound) {
  if (c.steps == 0) return json(nullptr);
  return json{{"scale", c.scale}, {"steps", c.steps}, {"hypothesis_held", c.hypothesis_held()},
              {"clamp_steps_exact", c.clamp_steps_exact}, {"clamp_steps_fixed", c.clamp_steps_fixed},
              {"saturation_steps", c.saturation_steps}, {"violation_steps", c.violation_steps},
              {"first_violation", c.first_violation}, {"covered_steps", c.covered_steps},
              {"max_error", c.max_error}, {"max_error_covered", c.max_error_covered}, {"within", c.within(bound)}};
}

// "verify: full-range run: hypothesis held on every step", or where it broke.
void print_run(const cg::BoundCheck& c, const std::string& what) {
  std::string line = fmt::format("verify: {}: ", what);
  if (c.hypothesis_held()) {
    line += "hypothesis held on every step";
  } else {
    line += fmt::format("hypothesis broken on {} of {} steps (saturation block engaged: {} steps exact, {} fixed; "
                        "word saturated: {}), first at step {}: ",
                        c.violation_steps, c.steps, c.clamp_steps_exact, c.clamp_steps_fixed, c.saturation_steps,
                        c.first_violation);
    line += c.covered_steps == 0 ? std::string("the bound covers no step of this run")
                                 : fmt::format("the bound covers the {} steps before it", c.covered_steps);
  }
  std::cout << line << "\n";
}

// "; full run: max error 1e-3 (within)" for output j.
std::string run_error(const cg::BoundCheck& c, const char* what, size_t j, double bound) {
  std::string part = fmt::format("; {}: max error {:.3g}", what, c.max_error[j]);
  if (c.hypothesis_held()) return part + (c.max_error[j] <= bound ? " (within)" : " (EXCEEDED)");
  if (c.covered_steps == 0) return part + " (not covered)";
  return part + fmt::format(", {:.3g} over the covered steps{}", c.max_error_covered[j],
                            c.max_error_covered[j] <= bound ? " (within)" : " (EXCEEDED)");
}

// The fixed point against the exact program: the runs and each output's error and bound.
bool report_fixed(const cg::LoopProgram& program, const cg::VerifyResult& v, json& report) {
  report["verification"]["max_abs_error_vs_exact"] = v.max_abs_error_vs_exact;
  // clamp_free: the scaled run, when the hypothesis broke on the full one (null: not
  // needed, or no scaled input keeps every saturation block idle).
  report["verification"]["bound_check"] = {
      {"full", check_json(v.full, v.bound)},
      {"clamp_free", v.full.hypothesis_held() ? json(nullptr) : check_json(v.clamp_free, v.bound)}};
  std::cout << fmt::format("verify: fixed point against the exact (double) program; predicted bound: the worst case "
                           "over {} steps ({:.6g} s at {:.6g} Hz) from reset, for inputs within their ranges, while no "
                           "saturation block engages in either program and no word saturates\n",
                           v.bound.horizon, v.bound.horizon / program.rate_hz, program.rate_hz);
  print_run(v.full, "full-range run");
  const bool scaled = !v.full.hypothesis_held() && v.clamp_free.steps > 0;
  if (scaled)
    print_run(v.clamp_free, fmt::format("clamp-free run (the input scaled by 2^{}, generated code)",
                                        static_cast<int>(std::lround(std::log2(v.clamp_free.scale)))));
  else if (!v.full.hypothesis_held())
    std::cout << "verify: no scaled copy of the input (down to 2^-40) keeps every saturation block idle\n";
  for (size_t j = 0; j < program.outputs.size(); ++j) {
    const auto& sl = program.slots[static_cast<size_t>(program.outputs[j])];
    const double b = v.bound.over_horizon[j], inf = v.bound.infinite[j];
    std::string line = fmt::format("verify:   {}{}: bound {:.3g} over {} steps (infinite horizon: {})", sl.name,
                                   sl.unit.empty() ? "" : " [" + sl.unit + "]", b, v.bound.horizon,
                                   std::isfinite(inf) ? fmt::format("{:.3g}", inf) : std::string("none, a response does not decay"));
    line += run_error(v.full, "full run", j, b);
    if (scaled) line += run_error(v.clamp_free, "clamp-free run", j, b);
    std::cout << line << "\n";
  }
  return v.full.within(v.bound) && (v.clamp_free.steps == 0 || v.clamp_free.within(v.bound));
}

}  // namespace

VerifyOutcome verify_generated(const cg::LoopProgram& program, cg::Scalar scalar, const std::string& header,
                               const std::string& out_dir, const std::vector<Range>& ranges,
                               const cg::FixedProgram* fixed, json& report, cg::Language language) {
  const std::string work = (std::filesystem::path(out_dir) / (".verify_" + program.name)).string();
  struct RemoveWhenDone {  // also when verification fails: no harness left behind
    const std::string& dir;
    ~RemoveWhenDone() {
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
    }
  } remove{work};
  const cg::VerifyResult v = cg::verify(program, scalar, header, work, ranges, fixed, language);
  report["verification"] = {{"samples", v.samples}, {"max_abs_error", v.max_abs_error}, {"max_output", v.max_output},
                            {"sqnr_db", std::isfinite(v.sqnr_db) ? json(v.sqnr_db) : json(nullptr)},
                            {"saturations", v.saturations}, {"ns_per_step", v.ns_per_step},
                            {"compiler", v.compiler_command}};
  std::cout << "verify: " << v.samples << " samples (chirp + step), max |generated - interpreter| = " << v.max_abs_error
            << " (outputs up to " << v.max_output << "), SQNR " << v.sqnr_db << " dB, " << v.saturations
            << " saturations, " << v.ns_per_step << " ns/step\n";
  VerifyOutcome out;
  out.identical = v.max_abs_error == 0.0;
  if (fixed) out.within_bound = report_fixed(program, v, report);
  return out;
}

}  // namespace dmbd::apps
