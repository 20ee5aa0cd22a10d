#include <fmt/format.h>

#include <filesystem>
#include <sstream>

#include "codegen_report.hpp"
#include "dmbd/base/file.hpp"

namespace dmbd::apps {

using json = nlohmann::json;

namespace {

// The blocks and every signal's bound and formats.
void md_signals(std::ostream& md, const json& r) {
  for (const auto& b : r["blocks"])
    md << "| " << b["path"].get<std::string>() << " | " << b["type"].get<std::string>() << " | "
       << b["fields"].get<std::string>() << " | " << b["realisation"].get<std::string>() << " |\n";
  md << "\n## Signals\n\nBound |x| <= bound for inputs within their ranges: guaranteed (L1 norm of the impulse "
        "response from each input and saturation) or, where no guarantee exists, simulated (twice the largest value "
        "on the verification chirp and step); the fixed-point format (fractional bits, one bit of headroom).\n\n"
        "| signal | kind | block | unit | bound | range | Q (16 bit) | Q (32 bit) | Q (generated) |\n"
        "|---|---|---|---|---|---|---|---|---|\n";
  auto cell = [](const json& j, const char* key) {
    if (!j.contains(key) || j[key].is_null()) return std::string("-");
    if (j[key].is_string()) return j[key].get<std::string>();
    return fmt::format("{:.6g}", j[key].get<double>());
  };
  for (const auto& s : r["slots"]) {
    md << "| " << s["name"].get<std::string>() << " | " << s["kind"].get<std::string>() << " | "
       << s["origin"].get<std::string>() << " | " << s["unit"].get<std::string>() << " | "
       << (s["bound"].is_null() ? std::string("unbounded") : cell(s, "bound")) << " | " << cell(s, "range") << " | "
       << cell(s, "q16") << " | " << cell(s, "q32") << " | " << cell(s, "q")
       << (s.contains("bits") ? fmt::format(" ({}-bit)", s["bits"].get<int>()) : std::string()) << " |\n";
  }
}

// The predicted fixed-point error bound, the frequency response and poles.
void md_quantisation(std::ostream& md, const json& r) {
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

// The generated code against the interpreter, and the fixed point against the bound.
void md_verification(std::ostream& md, const json& r) {
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

}  // namespace

// <name>.report.json and a readable <name>.report.md next to the header.
void write_codegen_report(const nlohmann::json& r, const std::string& dir, const std::string& name) {
  const std::string base = (std::filesystem::path(dir) / (name + ".report")).string();
  const std::string js = r.dump(2) + "\n";
  dmbd::write_file_atomic(base + ".json", std::vector<unsigned char>(js.begin(), js.end()));
  std::ostringstream md;
  md << "# " << name << ": code generation report\n\n"
     << "Generated from " << r["source"].get<std::string>() << " at " << r["rate_hz"].get<double>() << " Hz ("
     << r["method"].get<std::string>() << "), " << r["scalar"].get<std::string>() << " arithmetic, "
     << (r.value("language", "cpp") == "c" ? "C99" : "C++11") << " code.\n\n"
     << "## Blocks\n\n| block | type | fields | realisation |\n|---|---|---|---|\n";
  md_signals(md, r);
  if (r.contains("predicted_error_bound")) md_quantisation(md, r);
  for (const auto& w : r["warnings"]) md << "\nWarning: " << w.get<std::string>() << "\n";
  if (r.contains("verification")) md_verification(md, r);
  const std::string text = md.str();
  dmbd::write_file_atomic(base + ".md", std::vector<unsigned char>(text.begin(), text.end()));
}

}  // namespace dmbd::apps
