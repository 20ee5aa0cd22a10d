// Step and tracking metrics of the experiments (dmbd/sim/experiments.hpp) on responses
// with closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "dmbd/sim/experiments.hpp"

namespace {

using dmbd::sim::rms_error;
using dmbd::sim::step_metrics;

constexpr double kPi = 3.14159265358979323846;

struct Record {
  std::vector<double> t, r, y;
};

// A unit step at t = 1 s (from 0), sampled every dt = 1 / rate to t_end (t_k = k / rate:
// the sample at 1 s is exactly 1.0); y(t) = response(t - 1).
template <class F>
Record step_record(F response, double dt, double t_end) {
  Record rec;
  const double rate = std::round(1.0 / dt);
  for (int k = 0;; ++k) {
    const double t = k / rate;
    if (t > t_end + 1e-12) break;
    rec.t.push_back(t);
    rec.r.push_back(t >= 1.0 ? 1.0 : 0.0);
    rec.y.push_back(t >= 1.0 ? response(t - 1.0) : 0.0);
  }
  return rec;
}

// First order, time constant tau: no overshoot, 10-90 % rise tau ln 9, and a final
// error exp(-t) whose mean over the last 20 % of the window is known in closed form.
TEST(SimStepMetrics, FirstOrderLag) {
  const double tau = 0.05, dt = 1e-5;
  const Record rec = step_record([&](double s) { return 1.0 - std::exp(-s / tau); }, dt, 1.3);
  const auto m = step_metrics(rec.t, rec.r, rec.y, 1.0, 1.3);
  EXPECT_EQ(m.overshoot_pct, 0.0);
  // The 10 % and 90 % crossings are each found at the first sample past them: within
  // one sample of tau ln 9.
  EXPECT_NEAR(m.rise_time_s, tau * std::log(9.0), dt);
  // Mean of exp(-s/tau) over s in [0.24, 0.3): (tau/0.06)(e^{-0.24/tau} - e^{-0.3/tau});
  // the sampled mean differs by O(dt / tau) relative: 1e-3.
  const double expected = tau / 0.06 * (std::exp(-0.24 / tau) - std::exp(-0.3 / tau));
  EXPECT_NEAR(m.steady_state_error, expected, 1e-3 * expected);
}

// Second order with zeta = 0.3: overshoot exp(-pi zeta / sqrt(1 - zeta^2)).
TEST(SimStepMetrics, SecondOrderOvershoot) {
  const double zeta = 0.3, wn = 40.0, wd = wn * std::sqrt(1 - zeta * zeta), dt = 1e-5;
  const Record rec = step_record(
      [&](double s) {
        return 1.0 - std::exp(-zeta * wn * s) * (std::cos(wd * s) + zeta / std::sqrt(1 - zeta * zeta) * std::sin(wd * s));
      },
      dt, 2.0);
  const auto m = step_metrics(rec.t, rec.r, rec.y, 1.0, 2.0);
  const double expected = 100.0 * std::exp(-kPi * zeta / std::sqrt(1 - zeta * zeta));
  // The sampled peak is within (wd dt)^2 / 2 relative of the true one: 1e-7 % here.
  EXPECT_NEAR(m.overshoot_pct, expected, 1e-4);
}

// The window is half-open: a reference that steps back to 0 exactly at t_end (as in
// position_controllers.yaml, whose step ends at 2.0 s) does not enter the
// steady-state error with that sample.
TEST(SimStepMetrics, ReferenceSteppingBackAtTheWindowEndIsExcluded) {
  const double dt = 1e-3;
  Record rec = step_record([](double) { return 0.99; }, dt, 2.5);  // 1 % steady-state error
  for (std::size_t k = 0; k < rec.t.size(); ++k)
    if (rec.t[k] >= 2.0 - 1e-12) rec.r[k] = 0.0;  // back at t = 2.0; y has not moved yet
  const auto m = step_metrics(rec.t, rec.r, rec.y, 1.0, 2.0);
  EXPECT_NEAR(m.steady_state_error, 0.01, 1e-12);
  EXPECT_EQ(m.overshoot_pct, 0.0);
}

// RMS of a sine error over whole periods: amplitude / sqrt(2) (exact for samples
// evenly spread over whole periods, but for rounding).
TEST(SimRmsError, SineOverWholePeriods) {
  std::vector<double> t, r, y;
  for (int k = 0; k < 1000; ++k) {
    t.push_back(k / 1000.0);
    r.push_back(0.5);
    y.push_back(0.5 + 0.2 * std::sin(2 * kPi * 4.0 * k / 1000.0));
  }
  EXPECT_NEAR(rms_error(t, r, y, 0.0, 0.999), 0.2 / std::sqrt(2.0), 1e-12);
  EXPECT_TRUE(std::isnan(rms_error(t, r, y, 5.0, 6.0)));  // no samples in the window
}

}  // namespace

namespace {

// A synthetic floating-base log: the torso at z0 - drop(t), tilting tilt(t).
template <class Z, class Tilt>
dmbd::sim::VariantResult torso_log(Z z, Tilt tilt, double t_end) {
  dmbd::sim::VariantResult r;
  r.name = "base";
  for (const char* c : {"base.y", "base.z", "base.tilt"}) r.log.add_column(c, "");
  for (int k = 0; k <= static_cast<int>(t_end * 100); ++k) {
    const double t = k / 100.0;
    r.log.begin_row(t);
    r.log.set(1, 0.0);
    r.log.set(2, z(t));
    r.log.set(3, tilt(t));
  }
  return r;
}

dmbd::sim::Scenario standing_scenario() {
  dmbd::sim::Scenario s;
  s.file = "standing.yaml";
  s.experiment.type = "standing";
  return s;
}

// Issue 12's standing metrics: fell when the torso drops more than 0.2 m or tilts beyond
// 0.5 rad; the largest tilt, the largest drop below the start, the tilt at the end.
TEST(SimStandingMetrics, FellByDropOrTiltAndTheFiguresOfTheRun) {
  const auto s = standing_scenario();
  const auto stands = torso_log([](double t) { return 1.0 - 0.01 * std::sin(t); }, [](double t) { return 0.1 * std::exp(-t); }, 5);
  auto m = dmbd::sim::evaluate_experiment(s, {stands}).metrics["standing"];
  EXPECT_FALSE(m["fell"].get<bool>());
  EXPECT_NEAR(m["max_tilt_rad"].get<double>(), 0.1, 1e-12);                 // at t = 0
  EXPECT_NEAR(m["final_tilt_rad"].get<double>(), 0.1 * std::exp(-5.0), 1e-12);
  EXPECT_NEAR(m["torso_height_drop_m"].get<double>(), 0.01, 1e-6);           // sin peaks at t = pi/2 (sampled at 1.57)
  const auto sinks = torso_log([](double t) { return 1.0 - 0.05 * t; }, [](double) { return 0.0; }, 5);  // 0.25 m
  EXPECT_TRUE(dmbd::sim::evaluate_experiment(s, {sinks}).metrics["standing"]["fell"].get<bool>());
  const auto topples = torso_log([](double) { return 1.0; }, [](double t) { return 0.11 * t; }, 5);  // 0.55 rad
  EXPECT_TRUE(dmbd::sim::evaluate_experiment(s, {topples}).metrics["standing"]["fell"].get<bool>());
  const auto leans = torso_log([](double) { return 1.0; }, [](double t) { return 0.09 * t; }, 5);  // 0.45 rad
  EXPECT_FALSE(dmbd::sim::evaluate_experiment(s, {leans}).metrics["standing"]["fell"].get<bool>());
}

}  // namespace

namespace {

// Two variants' synthetic step responses of l_ankle (q_d steps at 0.5 s to 1).
std::vector<dmbd::sim::VariantResult> ankle_runs(double t_end) {
  std::vector<dmbd::sim::VariantResult> runs(2);
  for (int v = 0; v < 2; ++v) {
    auto& r = runs[static_cast<std::size_t>(v)];
    r.name = v ? "slow" : "fast";
    r.log.add_column("q_d", "rad");
    r.log.add_column("l_ankle.q", "rad");
    for (int k = 0; k <= static_cast<int>(t_end * 1000); ++k) {
      const double t = k / 1000.0, step = t >= 0.5 ? 1.0 : 0.0;
      r.log.begin_row(t);
      r.log.set(1, step);
      r.log.set(2, step * (1 - std::exp(-(t - 0.5) / (v ? 0.2 : 0.05))));
    }
  }
  return runs;
}

dmbd::sim::Scenario ankle_step() {
  dmbd::sim::Scenario s;
  s.file = "ankle.yaml";
  s.experiment.type = "step_response";
  s.experiment.joint = "l_ankle";
  s.experiment.number = {{"step_start_s", 0.5}, {"step_end_s", 2.0}, {"sine_start_s", 2.0}, {"sine_end_s", 3.0}};
  return s;
}

// Issue 13, items 6 and 7: the figures name the experiment's joint (not "Knee"); a
// variant keeps its colour in every figure (here it is first after the reference in one
// axes and first outright in another); a run shorter than the windows is a warning.
TEST(SimStepExperiment, TitlesColoursAndShortRuns) {
  const auto res = dmbd::sim::evaluate_experiment(ankle_step(), ankle_runs(3.0));
  ASSERT_EQ(res.figures.size(), 2u);
  EXPECT_NE(res.figures[0].second.title.find("l_ankle"), std::string::npos) << res.figures[0].second.title;
  EXPECT_EQ(res.figures[0].second.title.find("Knee"), std::string::npos);
  auto colour_of = [](const dmbd::plot::Axes& a, const std::string& label) {
    for (const auto& s : a.series)
      if (s.label == label) return s.color;
    ADD_FAILURE() << "no series " << label;
    return dmbd::plot::Color{};
  };
  const auto& step_axes = res.figures[0].second.axes()[0];
  const auto& error_axes = res.figures[1].second.axes()[1];
  for (const char* v : {"fast", "slow"}) {
    const auto a = colour_of(step_axes, v), b = colour_of(error_axes, v);
    EXPECT_TRUE(a.r == b.r && a.g == b.g && a.b == b.b) << v;
    EXPECT_FALSE(a.r == 0 && a.g == 0 && a.b == 0) << v << " has an automatic colour";
  }
  EXPECT_TRUE(res.warnings.empty());
  const auto short_run = dmbd::sim::evaluate_experiment(ankle_step(), ankle_runs(1.0));
  ASSERT_EQ(short_run.warnings.size(), 2u);
  EXPECT_NE(short_run.warnings[0].find("ends at 1 s"), std::string::npos) << short_run.warnings[0];
}

}  // namespace
