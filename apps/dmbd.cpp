// The `dmbd` command line.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "analyze.hpp"
#include "diagram_picture.hpp"
#include "model_cmd.hpp"
#include "report_cmd.hpp"
#include "simulate_cmd.hpp"
#include "dmbd/base/file.hpp"
#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/expression.hpp"
#include "dmbd/blocks/frequency.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "dmbd/codegen/emit.hpp"
#include "dmbd/codegen/fixed.hpp"
#include "dmbd/codegen/loop_program.hpp"
#include "dmbd/codegen/ranges.hpp"
#include "dmbd/codegen/verify.hpp"
#include "dmbd/diagrams/linearize.hpp"
#include "dmbd/diagrams/tune.hpp"
#include "dmbd/viz/diagram_drawing.hpp"
#include "dmbd/viz/plot.hpp"
#include "dmbd/version.hpp"

namespace {

using dmbd::InputError;
namespace b = dmbd::blocks;

// A number given on the command line: any constant expression (`1e-3`, `2*pi*60`).
double parse_number(const std::string& text, const std::string& option, const b::ParameterMap& params = {}) {
  try {
    return b::Expression::parse(text).evaluate(params);
  } catch (const b::ExpressionError& e) {
    throw InputError(option + " '" + text + "': " + e.what());
  }
}

int parse_count(const std::string& text, const std::string& option) {
  const double v = parse_number(text, option);
  if (v != std::floor(v) || v < 1 || v > 1e7)
    throw InputError(option + " '" + text + "': expected a whole number of samples from 1 to 10^7");
  return static_cast<int>(v);
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == sep) {
      out.push_back(cur);
      cur.clear();
    } else {
      cur.push_back(c);
    }
  }
  out.push_back(cur);
  return out;
}

// --param NAME=VALUE, in order: each VALUE may use the parameters before it.
b::ParameterMap parse_params(const std::vector<std::string>& list) {
  b::ParameterMap params;
  for (const std::string& p : list) {
    const auto eq = p.find('=');
    if (eq == std::string::npos || eq == 0) throw InputError("--param '" + p + "': expected NAME=VALUE");
    const std::string name = p.substr(0, eq);
    for (char c : name)
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_') || std::isdigit(static_cast<unsigned char>(name[0])))
        throw InputError("--param '" + p + "': '" + name + "' is not a valid parameter name");
    if (name == "s" || name == "z") throw InputError("--param '" + p + "': s and z are the transfer-function variables");
    params[name] = parse_number(p.substr(eq + 1), "--param " + name, params);
  }
  return params;
}

bool fs_parent_missing(const std::string& path) {
  const std::filesystem::path p(path);
  return p.has_parent_path() && !std::filesystem::is_directory(p.parent_path());
}

// <name>.report.json and a readable <name>.report.md next to the header.
void write_report(const nlohmann::json& r, const std::string& dir, const std::string& name) {
  const std::string base = (std::filesystem::path(dir) / (name + ".report")).string();
  const std::string js = r.dump(2) + "\n";
  dmbd::write_file_atomic(base + ".json", std::vector<unsigned char>(js.begin(), js.end()));
  std::ostringstream md;
  md << "# " << name << ": code generation report\n\n"
     << "Generated from " << r["source"].get<std::string>() << " at " << r["rate_hz"].get<double>() << " Hz ("
     << r["method"].get<std::string>() << "), " << r["scalar"].get<std::string>() << " arithmetic.\n\n"
     << "## Blocks\n\n| block | type | fields | realisation |\n|---|---|---|---|\n";
  for (const auto& b : r["blocks"])
    md << "| " << b["path"].get<std::string>() << " | " << b["type"].get<std::string>() << " | "
       << b["fields"].get<std::string>() << " | " << b["realisation"].get<std::string>() << " |\n";
  md << "\n## Signals\n\nBound |x| <= bound for inputs within their ranges: guaranteed (L1 norm of the impulse "
        "response from each input and saturation) or, where no guarantee exists, simulated (twice the largest value "
        "on the verification chirp and step); the fixed-point format (fractional bits, one bit of headroom).\n\n"
        "| signal | kind | block | unit | bound | range | Q (16 bit) | Q (32 bit) | Q (generated) |\n"
        "|---|---|---|---|---|---|---|---|---|\n";
  auto cell = [](const nlohmann::json& j, const char* key) {
    if (!j.contains(key) || j[key].is_null()) return std::string("-");
    if (j[key].is_string()) return j[key].get<std::string>();
    return fmt::format("{:.6g}", j[key].get<double>());
  };
  for (const auto& s : r["slots"]) {
    md << "| " << s["name"].get<std::string>() << " | " << s["kind"].get<std::string>() << " | "
       << s["origin"].get<std::string>() << " | " << s["unit"].get<std::string>() << " | "
       << (s["bound"].is_null() ? std::string("unbounded") : cell(s, "bound")) << " | " << cell(s, "range") << " | "
       << cell(s, "q16") << " | " << cell(s, "q32") << " | " << cell(s, "q") << " |\n";
  }
  if (r.contains("predicted_error_bound")) {
    const auto& h = r["predicted_error_bound_horizon"];
    md << "\n## Quantisation\n\nPredicted worst case of |fixed - exact| per output (rounding and quantised "
          "coefficients, inputs within their ranges, from reset), under the hypothesis: "
       << h["hypothesis"].get<std::string>() << ".\n\n| output | over " << h["steps"].get<int>() << " steps ("
       << fmt::format("{:.6g}", h["seconds"].get<double>()) << " s) | rounding | coefficients | any number of steps |\n"
       << "|---|---|---|---|---|\n";
    for (size_t j = 0; j < r["predicted_error_bound"].size(); ++j) {
      const auto& inf = r["predicted_error_bound"][j];
      md << "| " << h["outputs"][j].get<std::string>() << " | " << fmt::format("{:.3g}", h["bound"][j].get<double>())
         << " | " << fmt::format("{:.3g}", h["rounding"][j].get<double>()) << " | "
         << fmt::format("{:.3g}", h["coefficients"][j].get<double>()) << " | "
         << (inf.is_null() ? std::string("none (a response does not decay)") : fmt::format("{:.3g}", inf.get<double>()))
         << " |\n";
    }
    md << "\nFrequency response of the quantised loop against the exact one: "
       << fmt::format("{:.3g} dB, {:.3g} deg", r["frequency_response_deviation"]["max_db"].get<double>(),
                      r["frequency_response_deviation"]["max_deg"].get<double>())
       << " at most.\n\n| pole (exact) | pole (quantised) |\n|---|---|\n";
    for (size_t k = 0; k < r["poles_exact"].size() && k < r["poles_quantised"].size(); ++k)
      md << fmt::format("| {:.10g} {:+.10g}j | {:.10g} {:+.10g}j |\n", r["poles_exact"][k][0].get<double>(),
                        r["poles_exact"][k][1].get<double>(), r["poles_quantised"][k][0].get<double>(),
                        r["poles_quantised"][k][1].get<double>());
  }
  for (const auto& w : r["warnings"]) md << "\nWarning: " << w.get<std::string>() << "\n";
  if (r.contains("verification")) {
    const auto& v = r["verification"];
    md << "\n## Verification\n\n" << v["samples"].get<int>() << " samples (chirp and step), max |generated - "
       << "interpreter| = " << v["max_abs_error"].get<double>() << ", " << v["ns_per_step"].get<double>()
       << " ns/step, compiled with `" << v["compiler"].get<std::string>() << "`.\n";
    if (v.contains("bound_check")) {
      md << "\nFixed point against the exact program (the bound over " << r["predicted_error_bound_horizon"]["steps"].get<int>()
         << " steps):\n\n| run | input scale | hypothesis | steps with a saturation block engaged (exact / fixed) | "
            "steps with a word saturated | first step breaking it | max error per output | covered steps | within |\n"
            "|---|---|---|---|---|---|---|---|---|\n";
      for (const char* run : {"full", "clamp_free"}) {
        const auto& c = v["bound_check"][run];
        if (c.is_null()) {
          if (std::string(run) == "clamp_free" && !v["bound_check"]["full"]["hypothesis_held"].get<bool>())
            md << "| " << run << " | - | no scaled input down to 2^-40 keeps every saturation block idle | | | | | | |\n";
          continue;
        }
        std::string errs;
        for (const auto& e : c["max_error"]) errs += (errs.empty() ? "" : ", ") + fmt::format("{:.3g}", e.get<double>());
        md << "| " << run << " | " << fmt::format("{:.6g}", c["scale"].get<double>()) << " | "
           << (c["hypothesis_held"].get<bool>() ? "held" : "not held") << " | " << c["clamp_steps_exact"].get<long>()
           << " / " << c["clamp_steps_fixed"].get<long>() << " | " << c["saturation_steps"].get<long>() << " | "
           << (c["first_violation"].get<int>() < 0 ? std::string("-") : std::to_string(c["first_violation"].get<int>()))
           << " | " << errs << " | " << c["covered_steps"].get<int>() << " | "
           << (c["covered_steps"].get<int>() == 0 ? "-" : c["within"].get<bool>() ? "yes" : "NO")
           << " |\n";
      }
    }
  }
  const std::string text = md.str();
  dmbd::write_file_atomic(base + ".md", std::vector<unsigned char>(text.begin(), text.end()));
}

int run_codegen(const std::string& diagram, const std::string& tf, bool tf_given, const std::string& rate_text,
                const std::string& method_text, const std::vector<std::string>& block_methods,
                const std::string& scalar_text, const std::string& word_text, const std::string& input_range, std::string name,
                const std::string& out_dir, const std::vector<std::string>& param_list, bool verify) {
  namespace cg = dmbd::codegen;
  const b::ParameterMap params = parse_params(param_list);
  if (diagram.empty() != tf_given) throw InputError(tf_given ? "give either a diagram file or --tf, not both" : "give a diagram file or --tf EXPR");
  cg::LowerOptions lo;
  lo.rate_hz = parse_number(rate_text, "--rate", params);
  if (!(lo.rate_hz > 0.0) || !std::isfinite(lo.rate_hz)) throw InputError("--rate '" + rate_text + "': expected a rate > 0 Hz");
  lo.method = b::parse_c2d_method(method_text.empty() ? "tustin" : method_text);
  for (const std::string& bm : block_methods) {
    const auto eq = bm.find('=');
    if (eq == std::string::npos) throw InputError("--block-method '" + bm + "': expected BLOCK=METHOD");
    lo.block_methods.push_back({bm.substr(0, eq), b::parse_c2d_method(bm.substr(eq + 1))});
  }
  cg::Scalar scalar = cg::Scalar::Double;
  const bool fixed = scalar_text == "fixed";
  if (scalar_text == "float") {
    scalar = cg::Scalar::Float;
  } else if (scalar_text != "double" && !fixed) {
    throw InputError("--scalar '" + scalar_text + "': expected double, float or fixed");
  }
  if (word_text != "32" && word_text != "16") throw InputError("--word '" + word_text + "': expected 16 or 32");
  const int word_bits = word_text == "32" ? 32 : 16;
  if (!std::filesystem::is_directory(out_dir)) throw InputError("--out '" + out_dir + "': the folder does not exist");
  std::optional<std::pair<double, double>> range;
  if (!input_range.empty()) {
    const auto parts = split(input_range, ':');
    if (parts.size() != 2) throw InputError("--input-range '" + input_range + "': expected LO:HI");
    range = std::make_pair(parse_number(parts[0], "--input-range", params), parse_number(parts[1], "--input-range", params));
    if (!(range->first < range->second)) throw InputError("--input-range '" + input_range + "': LO must be below HI");
  }
  cg::LoopProgram program;
  std::vector<std::pair<double, double>> ranges;
  std::string source;
  if (tf_given) {
    b::TransferFunction g = [&] {
      try {
        return b::TransferFunction::parse(tf, params);
      } catch (const InputError& e) {
        throw InputError("--tf '" + tf + "': " + e.what());
      }
    }();
    if (name.empty()) name = "tf";
    program = cg::lower(g, name, lo);
    ranges.push_back(range.value_or(std::make_pair(-1.0, 1.0)));
    source = "the transfer function " + tf;
  } else {
    const auto d = dmbd::diagrams::Diagram::load(diagram, params);
    // The diagram's own `discretization` unless --method is given.
    if (method_text.empty() && d->discretization()) lo.method = *d->discretization();
    program = cg::lower(*d, lo);
    if (!name.empty()) program.name = name;
    for (const auto& in : d->inputs())
      for (int k = 0; k < in.size; ++k) ranges.push_back(in.range.value_or(range.value_or(std::make_pair(-1.0, 1.0))));
    source = "the diagram " + diagram;
  }
  for (char c : program.name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_'))
      throw InputError("--name '" + program.name + "': expected a C++ identifier");
  const std::string header = (std::filesystem::path(out_dir) / (program.name + ".hpp")).string();
  std::optional<cg::FixedProgram> fx;
  if (fixed) fx = cg::make_fixed(program, ranges, word_bits);
  dmbd::write_file_atomic(header, [&] {
    const std::string text = fixed ? cg::emit_fixed_header(program, *fx, {scalar, source}) : cg::emit_header(program, {scalar, source});
    return std::vector<unsigned char>(text.begin(), text.end());
  }());
  std::cout << "wrote " << header << " (" << program.states.size() << " states, " << program.output_ops.size() + program.update_ops.size()
            << " operations per step)\n";
  for (const auto& w : program.warnings) std::cout << "warning: " << w << "\n";
  // The report: every signal's guaranteed range (L1 norms of impulse responses from the
  // input ranges) and the Q format it would take in 16- and 32-bit words.
  nlohmann::json report{{"name", program.name},
                        {"source", source},
                        {"rate_hz", program.rate_hz},
                        {"method", b::to_string(program.method)},
                        {"scalar", fixed ? "fixed " + word_text + "-bit" : std::string(cg::to_string(scalar))},
                        {"warnings", program.warnings}};
  {
    const std::vector<double> bounds = cg::slot_bounds(program, ranges);
    nlohmann::json slots = nlohmann::json::array();
    for (size_t k = 0; k < program.slots.size(); ++k) {
      const auto& sl = program.slots[k];
      const char* kind = sl.kind == cg::SlotKind::Input ? "input" : sl.kind == cg::SlotKind::Output ? "output"
                                                                   : sl.kind == cg::SlotKind::State ? "state" : "signal";
      nlohmann::json j{{"name", sl.name}, {"kind", kind}, {"origin", sl.origin}, {"unit", sl.unit}};
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
    nlohmann::json blocks = nlohmann::json::array();
    for (const auto& bi : program.blocks)
      blocks.push_back({{"path", bi.path}, {"type", bi.type}, {"fields", bi.summary}, {"realisation", bi.realisation}});
    report["blocks"] = blocks;
  }
  if (fx) {
    // What quantisation does to the loop: formats, the predicted worst-case output
    // error, the poles and the frequency response of the quantised program.
    nlohmann::json slots = report["slots"];
    for (size_t k = 0; k < program.slots.size(); ++k) {
      slots[k]["q"] = fx->q[k];
      slots[k]["range"] = fx->simulated[k] ? "simulated" : "guaranteed";
      if (fx->simulated[k]) slots[k]["bound"] = fx->bound[k];
    }
    report["slots"] = slots;
    // The worst case of |fixed - exact| per output: over any number of steps (null where
    // rounding errors accumulate without bound), and over the verification run's length.
    const cg::ErrorBound bound = cg::predicted_error_bound(program, *fx, ranges, cg::kVerifySamples);
    nlohmann::json pb = nlohmann::json::array(), names = nlohmann::json::array();
    for (double v : bound.infinite) pb.push_back(std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr));
    for (int k : program.outputs) names.push_back(program.slots[static_cast<size_t>(k)].name);
    report["predicted_error_bound"] = pb;
    report["predicted_error_bound_horizon"] = {
        {"steps", bound.horizon},
        {"seconds", bound.horizon * program.ts},
        {"outputs", names},
        {"bound", bound.over_horizon},
        {"rounding", bound.rounding},
        {"coefficients", bound.coefficients},
        {"rounding_sources", bound.sources},
        {"hypothesis", "at every step from reset, no saturation block engaged (input outside its limits) in the exact "
                       "or the fixed program and no word saturated in the fixed one; the bound then holds at every "
                       "step before the first that breaks it"}};
    const b::StateSpace exact = cg::program_state_space(program), quant = cg::program_state_space(fx->quantised);
    nlohmann::json pe = nlohmann::json::array(), pq = nlohmann::json::array();
    for (const auto& z : exact.poles()) pe.push_back({z.real(), z.imag()});
    for (const auto& z : quant.poles()) pq.push_back({z.real(), z.imag()});
    report["poles_exact"] = pe;
    report["poles_quantised"] = pq;
    const auto w = b::logspace(2 * M_PI * 0.01, M_PI * program.rate_hz * 0.999, 400);
    const auto he = b::frequency_response(exact, w), hq = b::frequency_response(quant, w);
    double db = 0.0, deg = 0.0;
    for (size_t k = 0; k < w.size(); ++k)
      for (int r = 0; r < he[k].rows(); ++r)
        for (int c = 0; c < he[k].cols(); ++c) {
          const auto a = he[k](r, c), q = hq[k](r, c);
          if (std::abs(a) == 0.0 || std::abs(q) == 0.0) continue;
          db = std::max(db, std::abs(20 * std::log10(std::abs(q) / std::abs(a))));
          deg = std::max(deg, std::abs(std::arg(q / a)) * 180 / M_PI);
        }
    report["frequency_response_deviation"] = {{"max_db", db}, {"max_deg", deg}};
  }
  if (verify) {
    const std::string work = (std::filesystem::path(out_dir) / (".verify_" + program.name)).string();
    const cg::VerifyResult v = cg::verify(program, scalar, header, work, ranges, fx ? &*fx : nullptr);
    report["verification"] = {{"samples", v.samples}, {"max_abs_error", v.max_abs_error}, {"max_output", v.max_output},
                              {"sqnr_db", std::isfinite(v.sqnr_db) ? nlohmann::json(v.sqnr_db) : nlohmann::json(nullptr)},
                              {"saturations", v.saturations}, {"ns_per_step", v.ns_per_step},
                              {"compiler", v.compiler_command}};
    std::cout << "verify: " << v.samples << " samples (chirp + step), max |generated - interpreter| = " << v.max_abs_error
              << " (outputs up to " << v.max_output << "), SQNR " << v.sqnr_db << " dB, " << v.saturations
              << " saturations, " << v.ns_per_step << " ns/step\n";
    bool exceeded = false;
    if (fx) {
      // The predicted bound per output and, on each run, whether its hypothesis held.
      auto check_json = [&](const cg::BoundCheck& c) {
        if (c.steps == 0) return nlohmann::json(nullptr);
        return nlohmann::json{{"scale", c.scale}, {"steps", c.steps}, {"hypothesis_held", c.hypothesis_held()},
                              {"clamp_steps_exact", c.clamp_steps_exact}, {"clamp_steps_fixed", c.clamp_steps_fixed},
                              {"saturation_steps", c.saturation_steps}, {"violation_steps", c.violation_steps},
                              {"first_violation", c.first_violation},
                              {"covered_steps", c.covered_steps}, {"max_error", c.max_error},
                              {"max_error_covered", c.max_error_covered}, {"within", c.within(v.bound)}};
      };
      report["verification"]["max_abs_error_vs_exact"] = v.max_abs_error_vs_exact;
      // clamp_free: the scaled run, when the hypothesis broke on the full one (null: not
      // needed, or no scaled input keeps every saturation block idle).
      report["verification"]["bound_check"] = {
          {"full", check_json(v.full)},
          {"clamp_free", v.full.hypothesis_held() ? nlohmann::json(nullptr) : check_json(v.clamp_free)}};
      const double rate = program.rate_hz;
      std::cout << fmt::format("verify: fixed point against the exact (double) program; predicted bound: the worst case "
                               "over {} steps ({:.6g} s at {:.6g} Hz) from reset, for inputs within their ranges, while no "
                               "saturation block engages in either program and no word saturates\n",
                               v.bound.horizon, v.bound.horizon / rate, rate);
      auto describe = [&](const cg::BoundCheck& c, const char* what) {
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
      };
      describe(v.full, "full-range run");
      if (!v.full.hypothesis_held()) {
        if (v.clamp_free.steps > 0)
          describe(v.clamp_free, fmt::format("clamp-free run (the input scaled by 2^{}, generated code)",
                                             static_cast<int>(std::lround(std::log2(v.clamp_free.scale))))
                                     .c_str());
        else
          std::cout << "verify: no scaled copy of the input (down to 2^-40) keeps every saturation block idle\n";
      }
      for (size_t j = 0; j < program.outputs.size(); ++j) {
        const auto& sl = program.slots[static_cast<size_t>(program.outputs[j])];
        std::string line = fmt::format("verify:   {}{}: bound {:.3g} over {} steps (infinite horizon: {})", sl.name,
                                       sl.unit.empty() ? "" : " [" + sl.unit + "]", v.bound.over_horizon[j], v.bound.horizon,
                                       std::isfinite(v.bound.infinite[j]) ? fmt::format("{:.3g}", v.bound.infinite[j])
                                                                          : std::string("none, a response does not decay"));
        auto part = [&](const cg::BoundCheck& c, const char* what) {
          line += fmt::format("; {}: max error {:.3g}", what, c.max_error[j]);
          if (c.hypothesis_held()) {
            line += c.max_error[j] <= v.bound.over_horizon[j] ? " (within)" : " (EXCEEDED)";
          } else {
            line += c.covered_steps == 0 ? std::string(" (not covered)")
                                         : fmt::format(", {:.3g} over the covered steps{}", c.max_error_covered[j],
                                                       c.max_error_covered[j] <= v.bound.over_horizon[j] ? " (within)"
                                                                                                          : " (EXCEEDED)");
          }
        };
        part(v.full, "full run");
        if (!v.full.hypothesis_held() && v.clamp_free.steps > 0) part(v.clamp_free, "clamp-free run");
        std::cout << line << "\n";
      }
      exceeded = !v.full.within(v.bound) || (v.clamp_free.steps > 0 && !v.clamp_free.within(v.bound));
    }
    std::filesystem::remove_all(work);
    write_report(report, out_dir, program.name);
    {
      if (v.max_abs_error != 0.0) {
        std::cerr << "dmbd: error: generated code differs from the interpreter (it must be bit-identical)\n";
        return 1;
      }
      if (exceeded) {
        std::cerr << "dmbd: error: the fixed-point error exceeds its predicted bound on steps where the bound's "
                     "hypothesis held (a defect of the generator or of the bound)\n";
        return 1;
      }
    }
  }
  if (!verify) write_report(report, out_dir, program.name);
  return 0;
}

struct AnalyzeArgs {
  std::string diagram, from, to, loop_at, sweep;
  std::string tf;
  bool tf_given = false;
  std::vector<std::string> params;
  bool json = false;
  std::string freq, freq_range, step, c2d, ts, prewarp, bode, step_plot;
};

int run_analyze(const AnalyzeArgs& a) {
  const b::ParameterMap params = parse_params(a.params);

  dmbd::apps::AnalyzeRequest req;
  if (a.diagram.empty() != a.tf_given)
    throw InputError(!a.tf_given ? "give a diagram file or --tf EXPR" : "give either a diagram file or --tf, not both");
  double ts = 0.0;
  if (!a.ts.empty()) {
    ts = parse_number(a.ts, "--ts", params);
    if (!(ts > 0.0) || !std::isfinite(ts)) throw InputError("--ts '" + a.ts + "': the sample time must be > 0 s");
  }
  bool discrete = false;
  std::optional<b::Siso> tf;
  std::shared_ptr<const dmbd::diagrams::Diagram> diagram;
  std::optional<dmbd::apps::DiagramTransfer> dt;
  if (a.tf_given) {
    if (!a.from.empty() || !a.to.empty() || !a.loop_at.empty() || !a.sweep.empty())
      throw InputError("--from, --to, --loop-at and --sweep apply to a diagram, not to --tf");
    const b::Expression expr = [&] {
      try {
        return b::Expression::parse(a.tf);
      } catch (const b::ExpressionError& e) {
        throw InputError("--tf '" + a.tf + "': " + e.what());
      }
    }();
    discrete = expr.uses('z');
    if (discrete && expr.uses('s')) throw InputError("--tf '" + a.tf + "': uses both s and z");
    if (discrete && ts == 0.0) throw InputError("--tf '" + a.tf + "': an expression in z needs --ts SECONDS");
    if (!a.ts.empty() && !discrete && a.c2d.empty())
      throw InputError("--ts is used with --c2d or with an expression in z");
    try {
      tf = b::Siso::from_tf(b::TransferFunction::parse(a.tf, params, discrete ? ts : 0.0));
    } catch (const b::ExpressionError& e) {
      throw InputError("--tf '" + a.tf + "': " + e.what());
    } catch (const InputError& e) {
      throw InputError("--tf '" + a.tf + "': " + e.what());
    }
    req.title = a.tf;
  } else {
    if (a.loop_at.empty() && (a.from.empty() || a.to.empty()))
      throw InputError("a diagram needs --from SIGNAL and --to SIGNAL (or --loop-at SIGNAL)");
    if (!a.loop_at.empty() && (!a.from.empty() || !a.to.empty()))
      throw InputError("give either --loop-at or --from/--to");
    diagram = dmbd::diagrams::Diagram::load(a.diagram, params);
    discrete = diagram->is_discrete();
    if (!a.ts.empty() && a.c2d.empty()) throw InputError("--ts is used with --c2d");
    dt = dmbd::apps::diagram_transfer(*diagram, a.from, a.to, a.loop_at);
    tf = dt->transfer;
    req.title = a.loop_at.empty() ? diagram->name() + ": " + a.from + " -> " + a.to : diagram->name() + ": loop at " + a.loop_at;
  }
  if (discrete && !a.c2d.empty()) throw InputError("--c2d: the system is already discrete");
  if (!a.c2d.empty()) {
    req.c2d = b::parse_c2d_method(a.c2d);
    if (ts == 0.0) throw InputError("--c2d " + a.c2d + " needs --ts SECONDS");
    req.c2d_ts = ts;
  }
  if (!a.prewarp.empty()) {
    if (!req.c2d || *req.c2d != b::C2dMethod::Tustin) throw InputError("--prewarp is used with --c2d tustin");
    req.prewarp_hz = parse_number(a.prewarp, "--prewarp", params);
    if (!(req.prewarp_hz > 0.0) || req.prewarp_hz >= 0.5 / ts)
      throw InputError("--prewarp '" + a.prewarp + "': expected a frequency between 0 and the Nyquist frequency " +
                       std::to_string(0.5 / ts) + " Hz");
  }
  const b::Siso& g = *tf;
  if (discrete) ts = g.ts();

  if (!a.freq.empty() && !a.freq_range.empty()) throw InputError("give either --freq or --freq-range, not both");
  const double nyquist_hz = discrete ? 0.5 / ts : INFINITY;
  auto check_freq = [&](double f, const std::string& opt, const std::string& text) {
    if (!(f > 0.0) || !std::isfinite(f)) throw InputError(opt + " '" + text + "': frequencies must be > 0 Hz");
    if (f > nyquist_hz)
      throw InputError(opt + " '" + text + "': above the Nyquist frequency " + std::to_string(nyquist_hz) + " Hz");
  };
  if (!a.freq.empty()) {
    for (const std::string& f : split(a.freq, ',')) {
      if (f.empty()) throw InputError("--freq '" + a.freq + "': expected F1,F2,... in Hz");
      req.freq_hz.push_back(parse_number(f, "--freq", params));
      check_freq(req.freq_hz.back(), "--freq", a.freq);
    }
  }
  if (!a.freq_range.empty()) {
    const auto parts = split(a.freq_range, ':');
    if (parts.size() != 3) throw InputError("--freq-range '" + a.freq_range + "': expected LO:HI:N (Hz, log-spaced)");
    const double lo = parse_number(parts[0], "--freq-range", params), hi = parse_number(parts[1], "--freq-range", params);
    const int n = parse_count(parts[2], "--freq-range");
    check_freq(lo, "--freq-range", a.freq_range);
    check_freq(hi, "--freq-range", a.freq_range);
    if (hi < lo) throw InputError("--freq-range '" + a.freq_range + "': HI must not be below LO");
    req.freq_hz = b::logspace(lo, hi, n);
  }
  if (!a.step.empty()) {
    const auto parts = split(a.step, ':');
    if (parts.size() != 2) throw InputError("--step '" + a.step + "': expected T_END:N (seconds, samples)");
    const double t_end = parse_number(parts[0], "--step", params);
    if (!(t_end > 0.0) || !std::isfinite(t_end)) throw InputError("--step '" + a.step + "': T_END must be > 0 s");
    const int n = parse_count(parts[1], "--step");
    if (n < 2) throw InputError("--step '" + a.step + "': N must be at least 2 samples");
    req.step = std::make_pair(t_end, n);
  }
  req.bode_png = a.bode;
  req.step_png = a.step_plot;
  // Sweep: NAME=LO:HI:N[:log], re-evaluating the diagram at each value.
  std::string sweep_name;
  std::vector<double> sweep_values;
  if (!a.sweep.empty()) {
    const auto eq = a.sweep.find('=');
    const auto parts = split(eq == std::string::npos ? "" : a.sweep.substr(eq + 1), ':');
    if (eq == std::string::npos || (parts.size() != 3 && parts.size() != 4) || (parts.size() == 4 && parts[3] != "log" && parts[3] != "lin"))
      throw InputError("--sweep '" + a.sweep + "': expected NAME=LO:HI:N or NAME=LO:HI:N:log");
    sweep_name = a.sweep.substr(0, eq);
    if (!diagram->parameters().count(sweep_name))
      throw InputError("--sweep '" + a.sweep + "': the diagram has no parameter '" + sweep_name + "'");
    const double lo = parse_number(parts[0], "--sweep", params), hi = parse_number(parts[1], "--sweep", params);
    const int n = parse_count(parts[2], "--sweep");
    const bool log = parts.size() == 4 && parts[3] == "log";
    if (log && !(lo > 0.0 && hi > 0.0)) throw InputError("--sweep '" + a.sweep + "': a log sweep needs LO, HI > 0");
    if (log) {
      sweep_values = b::logspace(lo, hi, n);
    } else {
      for (int k = 0; k < n; ++k) sweep_values.push_back(n == 1 ? lo : lo + (hi - lo) * k / (n - 1));
    }
  }

  nlohmann::json report = dmbd::apps::analyze(g, req);
  if (diagram) {
    report["diagram"] = a.diagram;
    dmbd::apps::add_interconnection(report, *dt);
    if (a.loop_at.empty()) {
      report["from"] = a.from;
      report["to"] = a.to;
    } else {
      report["loop_at"] = a.loop_at;
    }
    nlohmann::json ps;
    for (const auto& name : diagram->parameter_order()) ps[name] = diagram->parameters().at(name);
    report["parameters"] = ps;
  } else {
    report["expression"] = a.tf;
    report["parameters"] = params;
  }
  if (!sweep_values.empty()) {
    nlohmann::json sw = nlohmann::json::array();
    for (double v : sweep_values) {
      b::ParameterMap p = params;
      p[sweep_name] = v;
      const auto dv = dmbd::diagrams::Diagram::load(a.diagram, p);
      nlohmann::json point = dmbd::apps::sweep_point(dmbd::apps::diagram_transfer(*dv, a.from, a.to, a.loop_at));
      point["value"] = v;
      sw.push_back(point);
    }
    report["sweep_parameter"] = sweep_name;
    report["sweep"] = sw;
  }
  dmbd::apps::write_plots(g, report, req);
  if (a.json) {
    std::cout << report.dump() << "\n";
  } else {
    std::cout << dmbd::apps::summary(report);
    if (report.contains("sweep")) {
      int unstable = 0;
      double worst = -INFINITY;
      for (const auto& p : report["sweep"]) {
        unstable += p["stable"].get<bool>() ? 0 : 1;
        if (!p["max_real_pole"].is_null()) worst = std::max(worst, p["max_real_pole"].get<double>());
      }
      std::cout << "sweep of " << sweep_name << " over " << report["sweep"].size() << " values: "
                << (unstable ? std::to_string(unstable) + " unstable" : std::string("all stable"))
                << ", largest real part of a pole " << worst << "\n";
    }
    if (!req.bode_png.empty()) std::cout << "wrote " << req.bode_png << "\n";
    if (!req.step_png.empty()) std::cout << "wrote " << req.step_png << "\n";
  }
  return 0;
}

}  // namespace

// "dmbd analize": CLI11 would say only that a subcommand is required. One line naming
// the word, the commands and the closest one.
std::string unknown_command(CLI::App& app, int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') return "";
  const std::string word = argv[1];
  std::string names, closest;
  std::size_t best = std::string::npos;
  for (const CLI::App* c : app.get_subcommands([](CLI::App*) { return true; })) {
    if (c->get_name() == word) return "";
    names += (names.empty() ? "" : ", ") + c->get_name();
    // Edit distance (Levenshtein) to suggest the closest name.
    const std::string& n = c->get_name();
    std::vector<std::size_t> d(n.size() + 1);
    for (std::size_t j = 0; j <= n.size(); ++j) d[j] = j;
    for (std::size_t i = 1; i <= word.size(); ++i) {
      std::size_t prev = d[0];
      d[0] = i;
      for (std::size_t j = 1; j <= n.size(); ++j) {
        const std::size_t cur = d[j];
        d[j] = std::min({d[j] + 1, d[j - 1] + 1, prev + (word[i - 1] == n[j - 1] ? 0 : 1)});
        prev = cur;
      }
    }
    if (d[n.size()] < best) best = d[n.size()], closest = n;
  }
  return "dmbd: error: unknown command '" + word + "' (expected one of: " + names + ")" +
         (best <= 2 ? "; did you mean '" + closest + "'?" : "");
}

int main(int argc, char** argv) {
  CLI::App app{"draco-mbd: model-based design for legged robots (block diagrams, analysis, code generation, "
               "simulation of the DRACO biped)",
               "dmbd"};
  app.set_version_flag("--version", std::string("dmbd ") + dmbd::kVersion);
  app.require_subcommand(1);

  AnalyzeArgs an;
  CLI::App* analyze = app.add_subcommand("analyze", "Poles, zeros, DC gain, margins, bandwidth, Bode, step response and "
                                                    "discretisation of a transfer function");
  analyze->add_option("diagram", an.diagram, "A diagram file (YAML, docs/diagram-format.md)");
  analyze->add_option("--tf", an.tf, "Rational expression in s (or z with --ts), e.g. '1/((s/wc)^2 + sqrt(2)*s/wc + 1)'");
  analyze->add_option("--from", an.from, "Diagram signal where the input is injected (an input, block.port, ...)");
  analyze->add_option("--to", an.to, "Diagram signal that is measured");
  analyze->add_option("--loop-at", an.loop_at, "Loop transfer at a break point (block.port), for margins");
  analyze->add_option("--sweep", an.sweep, "NAME=LO:HI:N[:log]: stability over a parameter range (diagrams)");
  analyze->add_option("--param", an.params, "NAME=VALUE (VALUE may use earlier parameters: wc=2*pi*fc); repeatable");
  analyze->add_flag("--json", an.json, "Print one JSON object instead of the summary");
  analyze->add_option("--freq", an.freq, "Frequencies for the Bode report, F1,F2,... (Hz)");
  analyze->add_option("--freq-range", an.freq_range, "Log-spaced Bode frequencies LO:HI:N (Hz)");
  analyze->add_option("--step", an.step, "Step response T_END:N (N samples from 0 to T_END seconds)");
  analyze->add_option("--c2d", an.c2d, "Discretise: tustin, zoh or backward-euler (needs --ts)");
  analyze->add_option("--ts", an.ts, "Sample time in seconds (for --c2d, or for an expression in z)");
  analyze->add_option("--prewarp", an.prewarp, "Tustin pre-warp frequency (Hz)");
  analyze->add_option("--bode", an.bode, "Write a Bode plot (PNG)");
  analyze->add_option("--step-plot", an.step_plot, "Write a step-response plot (PNG)");

  std::string draw_file, draw_out;
  std::vector<std::string> draw_params;
  CLI::App* draw = app.add_subcommand("draw", "Draw a block diagram as a PNG (layered layout, feedback routed below)");
  draw->add_option("diagram", draw_file, "A diagram file (YAML)")->required();
  draw->add_option("--out", draw_out, "PNG file to write")->required();
  draw->add_option("--param", draw_params, "NAME=VALUE parameter override; repeatable");

  struct {
    std::string diagram, from, to, p, d, gm = "6", overshoot = "0.5", wn_hz;
    std::vector<std::string> params;
    bool json = false;
  } tn;
  CLI::App* tune = app.add_subcommand(
      "tune", "Tune a PD position loop by the paper's procedure (raise D to the stability limit less a gain margin, "
              "then the highest P without overshoot), or to critical damping at a natural frequency");
  tune->add_option("diagram", tn.diagram, "A diagram file (YAML)")->required();
  tune->add_option("--from", tn.from, "Reference signal of the closed loop (e.g. q_d)")->required();
  tune->add_option("--to", tn.to, "Measured signal of the closed loop (e.g. q)")->required();
  tune->add_option("--p", tn.p, "Parameter name of the proportional gain")->required();
  tune->add_option("--d", tn.d, "Parameter name of the derivative gain")->required();
  tune->add_option("--gain-margin-db", tn.gm, "Back-off of D from its stability limit (dB, default 6)");
  tune->add_option("--max-overshoot", tn.overshoot, "Largest step overshoot that counts as none (%, default 0.5)");
  tune->add_option("--natural-frequency-hz", tn.wn_hz,
                   "Critical damping at this closed-loop natural frequency instead (controller 3 of the paper)");
  tune->add_option("--param", tn.params, "NAME=VALUE parameter override; repeatable");
  tune->add_flag("--json", tn.json, "Print one JSON object");

  struct {
    std::string diagram, tf, rate, method, scalar = "double", word = "32", input_range, name, out = ".";
    std::vector<std::string> params, block_methods;
    bool verify = false, tf_given = false;
  } cg;
  CLI::App* codegen = app.add_subcommand("codegen", "Generate a C++ control loop from a diagram or a transfer function");
  codegen->add_option("diagram", cg.diagram, "A diagram file (YAML)");
  codegen->add_option("--tf", cg.tf, "A transfer function instead of a diagram");
  codegen->add_option("--rate", cg.rate, "Loop rate in Hz")->required();
  codegen->add_option("--method", cg.method,
                      "Discretisation of continuous blocks: tustin, zoh, backward-euler (default: the diagram's "
                      "`discretization`, else tustin)");
  codegen->add_option("--block-method", cg.block_methods, "BLOCK=METHOD: another method for one block; repeatable");
  codegen->add_option("--scalar", cg.scalar, "double (default), float or fixed");
  codegen->add_option("--word", cg.word, "Fixed-point word: 16 or 32 bits (default 32)");
  codegen->add_option("--input-range", cg.input_range, "LO:HI of every input where the diagram gives none (verification)");
  codegen->add_option("--name", cg.name, "Namespace and file name (default: the diagram's name, or 'tf')");
  codegen->add_option("--out", cg.out, "Output folder (default .)");
  codegen->add_option("--param", cg.params, "NAME=VALUE parameter override; repeatable");
  codegen->add_flag("--verify", cg.verify, "Compile the header and compare it with the interpreter on a chirp and a step");

  dmbd::apps::ModelCommand model_cmd(app);  // dmbd model info
  dmbd::apps::SimulateCommand simulate_cmd(app);  // dmbd simulate
  dmbd::apps::ReportCommand report_cmd(app);      // dmbd report

  if (const std::string unknown = unknown_command(app, argc, argv); !unknown.empty()) {
    std::cerr << unknown << "\n";
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string msg = e.what();
    std::replace(msg.begin(), msg.end(), '\n', ' ');
    std::cerr << "dmbd: error: " << msg << " (see dmbd --help)\n";
    return 2;
  }

  try {
    an.tf_given = analyze->get_option("--tf")->count() > 0;
    if (*analyze) return run_analyze(an);
    if (model_cmd.selected()) return model_cmd.run();
    if (simulate_cmd.selected()) return simulate_cmd.run();
    if (report_cmd.selected()) return report_cmd.run();
    if (*tune) {
      const b::ParameterMap params = parse_params(tn.params);
      const double overshoot = parse_number(tn.overshoot, "--max-overshoot");
      if (!(overshoot >= 0.0)) throw InputError("--max-overshoot must be >= 0 %");
      dmbd::diagrams::PdTuningResult r;
      if (!tn.wn_hz.empty()) {
        const double f = parse_number(tn.wn_hz, "--natural-frequency-hz", params);
        if (!(f > 0.0)) throw InputError("--natural-frequency-hz must be > 0");
        r = dmbd::diagrams::tune_critical({tn.diagram, tn.from, tn.to, tn.p, tn.d, params, 2 * M_PI * f, overshoot});
      } else {
        const double gm = parse_number(tn.gm, "--gain-margin-db");
        if (!(gm >= 0.0)) throw InputError("--gain-margin-db must be >= 0");
        r = dmbd::diagrams::tune_pd({tn.diagram, tn.from, tn.to, tn.p, tn.d, params, gm, overshoot});
      }
      nlohmann::json j{{"diagram", tn.diagram},
                       {"p_param", tn.p},
                       {"d_param", tn.d},
                       {"p", r.p},
                       {"d", r.d},
                       {"stable", r.figures.stable},
                       {"overshoot_pct", r.figures.overshoot_pct},
                       {"natural_frequency_hz", r.figures.natural_frequency_rad_s / (2 * M_PI)},
                       {"rise_time_s", r.figures.rise_time_s},
                       {"evaluations", r.evaluations}};
      if (tn.wn_hz.empty()) j["d_critical"] = r.d_critical;
      if (tn.json) {
        std::cout << j.dump() << "\n";
      } else {
        if (tn.wn_hz.empty())
          std::cout << tn.d << " at the stability limit (" << tn.p << " = 0): " << r.d_critical << "\n";
        std::cout << tn.p << " = " << r.p << ", " << tn.d << " = " << r.d << "\n"
                  << "closed loop " << tn.from << " -> " << tn.to << ": " << (r.figures.stable ? "stable" : "NOT stable")
                  << ", overshoot " << r.figures.overshoot_pct << " %, natural frequency "
                  << r.figures.natural_frequency_rad_s / (2 * M_PI) << " Hz, rise time " << r.figures.rise_time_s * 1e3
                  << " ms (" << r.evaluations << " evaluations)\n";
      }
      return 0;
    }
    if (*codegen) {
      cg.tf_given = codegen->get_option("--tf")->count() > 0;
      return run_codegen(cg.diagram, cg.tf, cg.tf_given, cg.rate, cg.method, cg.block_methods, cg.scalar, cg.word,
                         cg.input_range, cg.name, cg.out, cg.params, cg.verify);
    }
    if (*draw) {
      const b::ParameterMap params = parse_params(draw_params);
      if (fs_parent_missing(draw_out)) throw InputError("--out '" + draw_out + "': the folder does not exist");
      if (std::filesystem::path(draw_out).extension() != ".png")
        throw InputError("--out '" + draw_out + "': dmbd draw writes PNG images (expected a file name ending in .png)");
      const auto d = dmbd::diagrams::Diagram::load(draw_file, params);
      dmbd::viz::save_diagram_png(dmbd::apps::diagram_picture(*d), draw_out);
      std::cout << "wrote " << draw_out << "\n";
      return 0;
    }
  } catch (const dmbd::diagrams::DiagramError& e) {
    for (const auto& d : e.diagnostics()) std::cerr << d.str() << "\n";
    return 2;
  } catch (const InputError& e) {
    std::string msg = e.what();
    std::replace(msg.begin(), msg.end(), '\n', ' ');
    std::cerr << "dmbd: error: " << msg << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "dmbd: internal error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
