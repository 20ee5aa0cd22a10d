// `sweep_plots` (docs/scenario-format.md): a metric against a numeric matrix axis, the
// runs grouped into lines by their other axes, the sampled values where the conditions
// hold, and the mistakes located. The metric comes from an experiment registered here
// that reports each run's duration (so every value is known exactly); the runs are not
// simulated: evaluate_experiment gets them by name.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "dmbd/base/error.hpp"
#include "dmbd/experiments/registry.hpp"
#include "dmbd/scenario/evaluate.hpp"
#include "dmbd/scenario/scenario.hpp"
#include "sim_test_support.hpp"

namespace {

namespace sc = dmbd::scenario;
using dmbd::sim::test::TempDir;
using dmbd::sim::test::write_text;

// metrics: {"d": {RUN: its duration in s}}; a run named ".../nan" gets NaN.
class Duration : public dmbd::experiments::Experiment {
 public:
  std::map<std::string, dmbd::experiments::KeyKind> keys() const override { return {}; }
  dmbd::experiments::ExperimentResult evaluate(const dmbd::experiments::ExperimentSetup&, const std::vector<dmbd::sim::VariantResult>&,
                                               const std::vector<dmbd::experiments::VariantFacts>& facts) const override {
    dmbd::experiments::ExperimentResult res;
    for (const auto& f : facts) res.metrics["d"][f.name] = f.name.find("nan") != std::string::npos ? NAN : f.duration_s;
    return res;
  }
};

// x: four values (durations 0.01, 0.02, 0.03, 0.04 s as x = 1..4), other: p (as they are)
// and q (each 0.025 s: q's durations replaced). The condition: duration in ms at most 25.
std::string scenario(const std::string& sweep, const std::string& x_extra = "") {
  return "name: sweep\n"
         "robot: {name: draco, base: fixed, base_pose: {xyz: [0, 0, 1.3]}, moving: [l_knee]}\n"
         "matrix:\n"
         "  x:\n"
         "    - {name: a, value: 1, duration_s: 0.01}\n"
         "    - {name: b, value: 2, duration_s: 0.02}\n"
         "    - {name: c, value: 3, duration_s: 0.03" + x_extra + "}\n"
         "    - {name: d, value: 4, duration_s: 0.04}\n"
         "  other:\n"
         "    - {name: p}\n"
         "    - {name: q, duration_s: 0.025}\n"
         "experiment: {type: duration_metric}\n" + sweep;
}

const std::string kSweep = "sweep_plots:\n"
                           "  - file: d.png\n"
                           "    axis: x\n"
                           "    title: duration\n"
                           "    curves:\n"
                           "      - {metric: \"/d/{run}\", scale: 1000, label: duration (ms), at_most: 25}\n";

std::vector<dmbd::sim::VariantResult> runs_of(const sc::Scenario& s) {
  std::vector<dmbd::sim::VariantResult> runs(s.variants.size());
  for (std::size_t k = 0; k < runs.size(); ++k) runs[k].name = s.variants[k].name;
  return runs;
}

void register_once() {
  if (!dmbd::experiments::find_experiment("duration_metric"))
    dmbd::experiments::register_experiment("duration_metric", std::make_shared<Duration>());
}

std::string load_error(const std::string& path, const std::string& yaml) {
  write_text(path, yaml);
  try {
    sc::load_scenario(path);
  } catch (const dmbd::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(SweepPlots, LinesByTheOtherAxesAndTheSampledValuesWhereTheConditionHolds) {
  register_once();
  TempDir dir;
  write_text(dir.file("s.yaml"), scenario(kSweep));
  const sc::Scenario s = sc::load_scenario(dir.file("s.yaml"));
  ASSERT_EQ(s.variants.size(), 8u);
  EXPECT_EQ(s.variants[0].axis_values, (std::vector<std::pair<std::string, double>>{{"x", 1}}));
  const auto res = sc::evaluate_experiment(s, runs_of(s));
  const auto& p = res.metrics["sweeps"]["d"]["lines"]["p"];
  EXPECT_EQ(p["x"], (std::vector<double>{1, 2, 3, 4}));
  EXPECT_EQ(p["runs"], (std::vector<std::string>{"a/p", "b/p", "c/p", "d/p"}));
  EXPECT_EQ(p["curves"]["duration (ms)"], (std::vector<double>{10, 20, 30, 40}));
  EXPECT_EQ(p["holds"], (std::vector<bool>{true, true, false, false}));
  EXPECT_EQ(p["holds_from"], 1.0);
  EXPECT_EQ(p["holds_to"], 2.0);
  EXPECT_TRUE(p["fails_below"].is_null());
  EXPECT_EQ(p["fails_above"], 3.0);
  EXPECT_EQ(p["verdict"], "holds at the sampled values 1 to 2; fails at 3 (the edge lies between the samples)");
  const auto& q = res.metrics["sweeps"]["d"]["lines"]["q"];  // 25 ms everywhere: at the bound, it holds
  EXPECT_EQ(q["holds_at"], (std::vector<double>{1, 2, 3, 4}));
  EXPECT_EQ(q["verdict"], "holds at the sampled values 1 to 4");
  // The figure: one axes, a line each, the bound dashed; the verdicts in the notes.
  ASSERT_EQ(res.figures.size(), 1u);
  EXPECT_EQ(res.figures[0].first, "d.png");
  const auto& axes = res.figures[0].second.axes();
  ASSERT_EQ(axes.size(), 1u);
  ASSERT_EQ(axes[0].series.size(), 2u);
  EXPECT_EQ(axes[0].series[0].label, "p");
  EXPECT_EQ(axes[0].series[0].y, (std::vector<double>{10, 20, 30, 40}));
  EXPECT_EQ(axes[0].h_lines, (std::vector<double>{25}));
  ASSERT_EQ(res.notes.size(), 2u);
  EXPECT_EQ(res.notes[0], "Sweep d.png (p): duration over x: holds at the sampled values 1 to 2; fails at 3 (the edge lies between the samples).");
}

TEST(SweepPlots, AnIntervalInsideAndAGapAreSaidAsSuch) {
  register_once();
  TempDir dir;
  // at_least 15 and at_most 35 on p's 10, 20, 30, 40: holds at 2 and 3 only.
  std::string sweep = kSweep;
  sweep.replace(sweep.find("at_most: 25"), 11, "at_least: 15, at_most: 35");
  write_text(dir.file("s.yaml"), scenario(sweep));
  sc::Scenario s = sc::load_scenario(dir.file("s.yaml"));
  auto res = sc::evaluate_experiment(s, runs_of(s));
  EXPECT_EQ(res.metrics["sweeps"]["d"]["lines"]["p"]["verdict"],
            "holds at the sampled values 2 to 3; fails at 1 and 4 (the edge lies between the samples)");
  EXPECT_EQ(res.figures[0].second.axes()[0].h_lines, (std::vector<double>{35, 15}));
  // A NaN fails a condition; holding at 1, 2 and 4 but not 3 is not contiguous.
  write_text(dir.file("n.yaml"), scenario(kSweep.substr(0, kSweep.find("at_most")) + "at_most: 100}\n"));
  s = sc::load_scenario(dir.file("n.yaml"));
  auto runs = runs_of(s);
  for (auto& v : s.variants)
    if (v.name == "c/p") v.name = "c/nan_p";
  for (auto& r : runs)
    if (r.name == "c/p") r.name = "c/nan_p";
  res = sc::evaluate_experiment(s, runs);
  const auto& p = res.metrics["sweeps"]["d"]["lines"]["p"];
  EXPECT_EQ(p["holds"], (std::vector<bool>{true, true, false, true}));
  EXPECT_FALSE(p["contiguous"].get<bool>());
  EXPECT_EQ(p["verdict"], "holds at the sampled values 1 to 4 (not at every sampled value between)");
}

TEST(SweepPlots, APointerThatFindsNothingNamesTheRunAndTheEntry) {
  register_once();
  TempDir dir;
  std::string sweep = kSweep;
  sweep.replace(sweep.find("/d/{run}"), 8, "/e/{run}");
  write_text(dir.file("s.yaml"), scenario(sweep));
  const sc::Scenario s = sc::load_scenario(dir.file("s.yaml"));
  try {
    sc::evaluate_experiment(s, runs_of(s));
    FAIL() << "no error";
  } catch (const dmbd::InputError& e) {
    EXPECT_EQ(std::string(e.what()), dir.file("s.yaml") + ": sweep_plot 'd.png' (" + dir.file("s.yaml") +
                                         ":14:5): metric /e/{run}: metrics.json has no such value for any run");
  }
}

// A run without the value (a robot that fell before its figure): its point fails its
// condition, drawn as a gap, and a warning names the run.
TEST(SweepPlots, ARunWithoutTheValueFailsAndIsNamed) {
  register_once();
  TempDir dir;
  std::string sweep = kSweep;
  sweep.replace(sweep.find("/d/{run}"), 8, "/e/{run}");
  write_text(dir.file("s.yaml"), scenario(sweep));
  const sc::Scenario s = sc::load_scenario(dir.file("s.yaml"));
  auto runs = runs_of(s);
  // The experiment's metrics, and an "e" value for every run but c/p.
  class Partial : public Duration {
   public:
    dmbd::experiments::ExperimentResult evaluate(const dmbd::experiments::ExperimentSetup& e, const std::vector<dmbd::sim::VariantResult>& r,
                                                 const std::vector<dmbd::experiments::VariantFacts>& f) const override {
      auto res = Duration::evaluate(e, r, f);
      for (const auto& v : f)
        if (v.name != "c/p") res.metrics["e"][v.name] = res.metrics["d"][v.name];
      return res;
    }
  };
  if (!dmbd::experiments::find_experiment("partial_metric"))
    dmbd::experiments::register_experiment("partial_metric", std::make_shared<Partial>());
  sc::Scenario partial = s;
  partial.experiment.type = "partial_metric";
  const auto res = sc::evaluate_experiment(partial, runs);
  const auto& p = res.metrics["sweeps"]["d"]["lines"]["p"];
  EXPECT_EQ(p["holds"], (std::vector<bool>{true, true, false, false}));
  EXPECT_TRUE(p["curves"]["duration (ms)"][2].is_null() || std::isnan(p["curves"]["duration (ms)"][2].get<double>()));
  ASSERT_EQ(res.warnings.size(), 1u);
  EXPECT_EQ(res.warnings[0], "sweep_plot 'd.png': metric /e/{run} has no value for run(s) c/p: taken as not meeting its condition");
}

TEST(SweepPlots, MistakesInTheEntryAreLocated) {
  TempDir dir;
  const std::string path = dir.file("e.yaml");
  auto expect = [&](const std::string& yaml, int line, const std::string& what) {
    const std::string msg = load_error(path, yaml);
    EXPECT_EQ(msg.rfind(path + ":" + std::to_string(line) + ":", 0), 0u) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  };
  std::string y = kSweep;
  expect(scenario(y.replace(y.find("axis: x"), 7, "axis: z")), 15, "sweep_plot.axis: the matrix has no axis 'z' (its axes: x, other)");
  y = kSweep;
  expect(scenario(y.replace(y.find("axis: x"), 7, "axis: other")), 10, "matrix.other: each value needs a number 'value'");
  y = kSweep;
  expect(scenario(y.replace(y.find("/d/{run}"), 8, "/d/all")), 18, "expected {run} in the pointer");
  y = kSweep;
  expect(scenario(y.replace(y.find("/d/{run}"), 8, "d/{run}")), 18, "expected a JSON pointer into metrics.json");
  expect(scenario(kSweep + "  - {file: d.png, axis: x, curves: [{metric: \"/d/{run}\"}]}\n"), 19, "'d.png' is given twice");
  y = kSweep;
  expect(scenario(y.replace(y.find("curves:"), 7, "curvs:")), 17, "unknown key 'curvs'");
}
