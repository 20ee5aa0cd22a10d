// The push-recovery map (experiments/src/push_map.cpp) on the synthetic balancing log of
// push_log.hpp, whose capture intervals are worked out by hand: an unpushed reference
// and pushes of 4 ms starting 1 ms into the log (a trigger's time) at phase 0, all
// ending at 5 ms where the capture point sits 1 mm inside the sagittal interval's top
// and mid-way laterally. The analytic boundary at phase 0 is where a push's shift
// F (e^{ωτ} − 1)/(m ω²) takes the capture point to the interval's edge. Tolerance:
// 1e-6 N (the intervals are exact to 1e-12 m; one newton shifts the point ~1e-5 m).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "dmbd/base/error.hpp"
#include "dmbd/control/balance_controller.hpp"
#include "dmbd/scenario/evaluate.hpp"
#include "dmbd/scenario/scenario.hpp"
#include "push_log.hpp"

namespace {

using namespace push_log;

constexpr double kTrigger = 0.001, kTau = 0.004;

// A run of the map: the push log with its trigger's logged start, in group `ideal`.
dmbd::sim::VariantResult map_log(const std::string& name) {
  const dmbd::sim::VariantResult src = log(false);
  dmbd::sim::VariantResult r = src;
  r.name = name;
  r.axes = {{"joints", "ideal"}, {"push", name}};
  r.log = dmbd::sim::Log();
  for (int c = 1; c < static_cast<int>(src.log.columns()); ++c) r.log.add_column(src.log.name(c), src.log.unit(c));
  const int start = r.log.add_column("forces.0.start_s", "s");
  for (std::size_t k = 0; k < src.log.rows(); ++k) {
    r.log.begin_row(src.log.time()[k]);
    for (int c = 1; c < static_cast<int>(src.log.columns()); ++c) r.log.set(c, src.log.column(c)[k]);
    r.log.set(start, kTrigger);
  }
  return r;
}

// One variant per direction (deg; NaN: the unpushed reference), 100 N for 4 ms from the
// trigger on the touch-down count (after 0 s).
dmbd::scenario::Scenario map_scenario(const std::vector<double>& directions) {
  dmbd::scenario::Scenario s;
  s.file = "map.yaml";
  s.experiment.file = "map.yaml";
  s.experiment.type = "push_map";
  s.experiment.number = {{"start_s", 0.0}, {"map_margin_m", 0.0005}, {"map_min_pushes", 2}};
  s.experiment.text = {{"group_axis", "joints"}};
  dmbd::control::BalanceSetup b;
  b.tvr.com_height_m = kHeight;
  b.tvr.gravity_m_s2 = kG;
  for (double deg : directions) {
    auto& v = s.variants.emplace_back();
    v.name = std::isnan(deg) ? "ref" : "d" + std::to_string(static_cast<int>(deg));
    v.duration_s = 1.0;
    v.bus_controllers.push_back(std::make_shared<dmbd::control::BalanceSetup>(b));
    dmbd::sim::ForceSpec f;
    f.link = "torso";
    const double a = deg * M_PI / 180.0;
    f.direction_W = std::isnan(deg) ? Eigen::Vector3d::Zero() : Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
    f.source.kind = dmbd::sim::Source::Kind::Steps;
    f.source.steps = {{0.0, 100.0}, {kTau, 0.0}};
    f.trigger = dmbd::sim::ForceSpec::Trigger{"balance.touch_downs", 1, 0.0};
    v.forces.push_back(f);
  }
  return s;
}

std::vector<dmbd::sim::VariantResult> logs(const dmbd::scenario::Scenario& s) {
  std::vector<dmbd::sim::VariantResult> out;
  for (const auto& v : s.variants) out.push_back(map_log(v.name));
  return out;
}

TEST(PushMap, TheBoundaryIsWhereThePushTakesTheCapturePointToTheIntervalsEdge) {
  const auto s = map_scenario({NAN, 0, 90, 180});
  const auto res = dmbd::scenario::evaluate_experiment(s, logs(s));
  const auto& m = res.metrics.at("push_map").at("ideal");
  const auto& bnd = m.at("boundary");
  EXPECT_EQ(bnd.at("reference").get<std::string>(), "ref");
  EXPECT_NEAR(bnd.at("trigger_time_s").get<double>(), kTrigger, 1e-12);
  const double per_newton = (std::exp(kOmega * kTau) - 1.0) / (kMass * kOmega * kOmega);
  const double ex = kAx.hi - 1e-3, ey = 0.5 * (kAy.lo + kAy.hi);
  EXPECT_NEAR(bnd.at("by_direction").at("0").at(0).get<double>(), (kAx.hi - ex) / per_newton, 1e-6);     // ~ 1 mm of room
  EXPECT_NEAR(bnd.at("by_direction").at("180").at(0).get<double>(), (ex - kAx.lo) / per_newton, 1e-6);  // the whole interval
  EXPECT_NEAR(bnd.at("by_direction").at("90").at(0).get<double>(), (kAy.hi - ey) / per_newton, 1e-6);
  // Per direction, at the pushes' phase 0: the same boundary; no push survived (the log
  // ends 0.6 s in, before 3 s after the push).
  const auto& d0 = m.at("directions").at("0");
  EXPECT_TRUE(d0.at("largest_force_survived_at_every_phase_N").is_null());
  EXPECT_NEAR(d0.at("by_phase").at(0).at("boundary_N").get<double>(), (kAx.hi - ex) / per_newton, 1e-6);
  EXPECT_EQ(d0.at("by_phase").at(0).at("largest_survived_N").get<double>(), 0.0);
  // The swing foot's peaks come from the runs that stood: the reference only (its foot
  // rests at (−0.05, 0.25) through the swing).
  EXPECT_EQ(m.at("swing_foot").at("runs").get<int>(), 1);
  EXPECT_EQ(m.at("swing_foot").at("peak_speed_m_s").get<double>(), 0.0);
}

TEST(PushMap, EachPushIsJudgedInItsOwnRunAndTheCertifiedSetDecides) {
  const auto s = map_scenario({NAN, 0, 90, 180});
  const auto res = dmbd::scenario::evaluate_experiment(s, logs(s));
  const auto& m = res.metrics.at("push_map").at("ideal");
  const auto& p = m.at("pushes");
  ASSERT_EQ(p.size(), 3u);  // the reference is not a push
  for (const auto& push : p) {
    EXPECT_NEAR(push.at("phase_s").get<double>(), 0.0, 1e-9);
    EXPECT_NEAR(push.at("force_N").get<double>(), 100.0, 1e-12);
    EXPECT_TRUE(push.at("capturable").get<bool>());
    EXPECT_NEAR(push.at("margin_m").get<double>(), 1e-3, 1e-9);  // its own log: x 1 mm inside
    EXPECT_FALSE(push.at("survived").get<bool>());
  }
  EXPECT_EQ(p[1].at("direction_deg").get<double>(), 90.0);
  // Three capturable with >= 0.5 mm of margin, none survived: enough to decide, and it fails.
  const auto& c = m.at("certified");
  EXPECT_EQ(c.at("pushes").get<int>(), 3);
  EXPECT_EQ(c.at("survived").get<int>(), 0);
  EXPECT_EQ(c.at("verdict").get<std::string>(), "fails");
  // With a 2 mm margin none qualifies: too few to decide.
  auto strict = map_scenario({NAN, 0, 90, 180});
  strict.experiment.number["map_margin_m"] = 0.002;
  const auto r2 = dmbd::scenario::evaluate_experiment(strict, logs(strict));
  EXPECT_EQ(r2.metrics.at("push_map").at("ideal").at("certified").at("verdict").get<std::string>(), "undecided");
  ASSERT_EQ(res.figures.size(), 1u);
  EXPECT_EQ(res.figures[0].first, "push_map_ideal.png");
  EXPECT_EQ(res.figures[0].second.axes().size(), 3u);  // one panel per direction
}

TEST(PushMap, WithoutAReferenceNoBoundaryIsDrawnAndItSaysSo) {
  const auto s = map_scenario({0, 90});
  const auto res = dmbd::scenario::evaluate_experiment(s, logs(s));
  EXPECT_TRUE(res.metrics.at("push_map").at("ideal").at("boundary").is_null());
  ASSERT_FALSE(res.warnings.empty());
  EXPECT_NE(res.warnings[0].find("no unpushed run"), std::string::npos) << res.warnings[0];
}

TEST(PushMap, AGroupAxisThatIsNotAMatrixAxisIsNamed) {
  auto s = map_scenario({NAN, 0});
  s.experiment.text["group_axis"] = "model";
  try {
    dmbd::scenario::evaluate_experiment(s, logs(s));
    FAIL() << "expected an InputError";
  } catch (const dmbd::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("map.yaml: experiment push_map: group_axis 'model' is not a matrix axis of run 'ref'"), std::string::npos)
        << e.what();
  }
}

}  // namespace

namespace {

std::string error_of(const dmbd::scenario::Scenario& s) {
  try {
    dmbd::scenario::evaluate_experiment(s, logs(s));
  } catch (const dmbd::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(PushMap, ItsOwnKeysOutsideTheirRangesAreNamed) {
  auto s = map_scenario({NAN, 0});
  s.experiment.number["map_survived_at_least"] = 1.5;
  EXPECT_NE(error_of(s).find("map_survived_at_least: expected a fraction in (0, 1], got 1.5"), std::string::npos) << error_of(s);
  s = map_scenario({NAN, 0});
  s.experiment.number["map_min_pushes"] = 2.5;
  EXPECT_NE(error_of(s).find("map_min_pushes: expected a whole number of pushes, at least 1"), std::string::npos) << error_of(s);
  s = map_scenario({NAN, 0});
  s.experiment.number["map_margin_m"] = -0.01;
  EXPECT_NE(error_of(s).find("map_margin_m: expected a margin of 0 m or more"), std::string::npos) << error_of(s);
}

TEST(PushMap, APushThatNeverCameIsNotTakenForTheReference) {
  // The first run's force has a direction but its trigger never fired (no logged start):
  // it is left out with a warning, and the unpushed run after it is the reference.
  auto s = map_scenario({0, NAN, 90});
  auto runs = logs(s);
  dmbd::sim::VariantResult unfired = log(false);
  unfired.name = runs[0].name;
  unfired.axes = runs[0].axes;
  runs[0] = unfired;  // no forces.0.start_s column: never started
  const auto res = dmbd::scenario::evaluate_experiment(s, runs);
  const auto& m = res.metrics.at("push_map").at("ideal");
  EXPECT_EQ(m.at("boundary").at("reference").get<std::string>(), "ref");
  EXPECT_EQ(m.at("pushes").size(), 1u);
  ASSERT_FALSE(res.warnings.empty());
  EXPECT_NE(res.warnings[0].find("variant 'd0': its push was never applied"), std::string::npos) << res.warnings[0];
}

TEST(PushMap, PushesFromDifferentPhaseOriginsGetNoSharedBoundary) {
  auto s = map_scenario({NAN, 0, 90});
  s.variants[2].forces[0].source.steps = {{0.0, 100.0}, {0.002, 0.0}};  // 2 ms instead of 4
  const auto res = dmbd::scenario::evaluate_experiment(s, logs(s));
  EXPECT_TRUE(res.metrics.at("push_map").at("ideal").at("boundary").is_null());
  ASSERT_FALSE(res.warnings.empty());
  EXPECT_NE(res.warnings[0].find("do not share one phase origin and duration"), std::string::npos) << res.warnings[0];
}

}  // namespace
