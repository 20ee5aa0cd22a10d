// The sysid_rfsea experiment (paper Fig. 5a): current chirps on an RFSEA with the output
// locked and free; the frequency responses of force, motor angle and joint angle are
// estimated from the logs and the actuator model is fitted to them (sysid.hpp).
#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "dmbd/blocks/error.hpp"
#include "dmbd/experiments/experiment.hpp"
#include "dmbd/experiments/sysid.hpp"
#include "experiment_support.hpp"

namespace dmbd::experiments {

namespace {

using detail::number_or;
using detail::signal;

// The variant's value on the axis named `axis` ("" when it has none).
std::string axis_value(const VariantResult& r, const std::string& axis) {
  for (const auto& [a, v] : r.axes)
    if (a == axis) return v;
  return "";
}

}  // namespace

ExperimentResult sysid_rfsea(const ExperimentSetup& e, const std::vector<VariantResult>& runs) {
  const std::string J = e.joint;
  ExperimentResult res;
  // Runs grouped by their "noise" axis value (one group when there is no such axis),
  // each with a locked and a free run (by the "output" axis value).
  std::map<std::string, std::pair<const VariantResult*, const VariantResult*>> groups;
  std::vector<std::string> order;
  for (const auto& r : runs) {
    const std::string g = axis_value(r, "noise");
    const std::string o = axis_value(r, "output").empty() ? r.name : axis_value(r, "output");
    if (!groups.count(g)) order.push_back(g);
    if (o == "locked") groups[g].first = &r;
    else if (o == "free") groups[g].second = &r;
    else throw InputError(e.file + ": experiment sysid_rfsea: variant '" + r.name + "' is neither 'locked' nor 'free' on the 'output' axis");
  }
  plot::Figure bode(1200, 900);
  bode.title = "Current to force, " + J + ": simulated measurement and identified model";
  auto& mag = bode.add_axes();
  mag.y_label = "|F/i| (dB re 1 N/A)";
  mag.x_scale = plot::Scale::Log;
  mag.x_tick_labels = false;
  auto& ph = bode.add_axes();
  ph.y_label = "Phase (deg)";
  ph.x_label = "Frequency (Hz)";
  ph.x_scale = plot::Scale::Log;
  ph.y_tick_step = 45;

  for (const std::string& g : order) {
    const auto [locked, free] = groups[g];
    if (!locked || !free) throw InputError(e.file + ": experiment sysid_rfsea needs a 'locked' and a 'free' variant" + (g.empty() ? "" : " for noise '" + g + "'"));
    const auto& truth = locked->truth;
    if (!truth.count("K_r")) throw InputError(e.file + ": experiment sysid_rfsea: joint '" + J + "' has no actuator");
    RfseaSysidData data;
    // The firmware's force constant: the product sheet's k_tau times the drive efficiency.
    data.constants.k_tau = truth.at("k_tau") * truth.at("efficiency");
    data.constants.N_m = truth.at("N_m");
    data.constants.N_l = truth.at("N_l");
    const double fs = 1.0 / (locked->log.time()[1] - locked->log.time()[0]);
    data.sampling.ts_s = 1.0 / fs;
    FrfOptions fo;
    fo.baseline_s = number_or(e, "lead_in_s", 0.0);
    auto record = [&](const VariantResult& r, bool with_q) {
      RfseaRecord rec;
      rec.i = signal(r, J + ".current_applied", e.file);
      rec.F = signal(r, J + ".force", e.file);
      rec.theta_m = signal(r, J + ".motor_angle", e.file);
      if (with_q) rec.q = signal(r, J + ".q_enc", e.file);
      return rec;
    };
    const auto f_locked = log_frequencies(number_or(e, "locked_f0_hz", 0.1), number_or(e, "locked_f1_hz", 200), static_cast<int>(number_or(e, "frequencies", 60)));
    const auto f_free = log_frequencies(number_or(e, "free_f0_hz", 1.0), number_or(e, "free_f1_hz", 200), static_cast<int>(number_or(e, "frequencies", 60)));
    data.locked = rfsea_test_data(record(*locked, false), fs, f_locked, fo);
    data.free = rfsea_test_data(record(*free, true), fs, f_free, fo);
    RfseaFitOptions opt;
    opt.fixed[kK_l] = true;  // the knee axis is vertical: no gravity spring on the load
    const RfseaFit fit = identify_rfsea(data, opt);

    // The first noise condition at the top level (identified, true, rel_error), the
    // others under their name.
    const bool first = g == order.front();
    nlohmann::json& top = first ? res.metrics : res.metrics[g];
    nlohmann::json& identified = top["identified"];
    nlohmann::json& rel = top["rel_error"];
    const auto p = to_array(fit.params);
    for (int k = 0; k < kRfseaNumParams; ++k) {
      const std::string name = rfsea_param_name(k);
      if (k == kK_l) continue;
      identified[name] = p[static_cast<std::size_t>(k)];
      res.metrics["true"][name] = truth.at(name);
      rel[name] = std::abs(p[static_cast<std::size_t>(k)] / truth.at(name) - 1.0);
    }
    nlohmann::json& fitinfo = top["fit"];
    fitinfo["rms_log_error"] = fit.rms_log_error;
    fitinfo["iterations"] = fit.iterations;
    fitinfo["converged"] = fit.converged;
    if (!g.empty()) res.metrics["noise_conditions"].push_back(g);

    // Bode: measured F/i of both tests and the identified model (first group only
    // as solid lines; the others' measurements as markers).
    if (!first) continue;
    for (const auto& [test, td, fr] : {std::tuple{RfseaTest::Locked, &data.locked, &f_locked}, std::tuple{RfseaTest::Free, &data.free, &f_free}}) {
      const std::string label = test == RfseaTest::Locked ? "locked" : "free";
      std::vector<double> m, a;
      for (const auto& h : td->F.H) {
        m.push_back(20 * std::log10(std::abs(h)));
        double deg = std::arg(h) * 180 / M_PI;  // unwrapped like the model's curve
        while (!a.empty() && deg - a.back() > 180) deg -= 360;
        while (!a.empty() && deg - a.back() < -180) deg += 360;
        a.push_back(deg);
      }
      mag.series.push_back({label + " output, simulated", *fr, m, plot::Color{}, 1.0, false, true});
      ph.series.push_back({label + " output, simulated", *fr, a, plot::Color{}, 1.0, false, true});
      const auto fine = log_frequencies(fr->front(), fr->back(), 300);
      const RfseaResponse model = rfsea_response(test, fit.params, data.constants, fine, data.sampling);
      std::vector<double> mm, aa;
      double prev = 0;
      for (std::size_t k = 0; k < fine.size(); ++k) {
        mm.push_back(20 * std::log10(std::abs(model.F[k])));
        double deg = std::arg(model.F[k]) * 180 / M_PI;
        while (k > 0 && deg - prev > 180) deg -= 360;  // unwrap
        while (k > 0 && deg - prev < -180) deg += 360;
        aa.push_back(deg);
        prev = deg;
      }
      mag.series.push_back({label + " output, identified model", fine, mm});
      ph.series.push_back({label + " output, identified model", fine, aa});
    }
  }
  res.figures.emplace_back("bode_identified.png", bode);
  res.notes.push_back("Known constants: k_tau x drive efficiency and N_m (product sheets), N_l from the linkage table at the test "
                      "angle. Identified by Levenberg-Marquardt on the log-complex error of F/i, theta_m/i (and q/i free).");
  return res;
}

namespace {

}  // namespace

std::shared_ptr<const Experiment> sysid_rfsea_experiment() {
  return std::make_shared<detail::FunctionExperiment>(
      std::map<std::string, KeyKind>{{"lead_in_s", KeyKind::Number},    {"locked_f0_hz", KeyKind::Number}, {"locked_f1_hz", KeyKind::Number},
            {"free_f0_hz", KeyKind::Number},   {"free_f1_hz", KeyKind::Number},   {"frequencies", KeyKind::Number}}, true,
      [](const ExperimentSetup& e, const std::vector<VariantResult>& runs, const std::vector<VariantFacts>&) { return sysid_rfsea(e, runs); });
}

}  // namespace dmbd::experiments
