// The contact-phase state machine's sequence (phase_machine.hpp), tick by tick: the
// start-up then the step cycle with exact tick counts at 1 kHz, the rounding rule
// (⌈(T − 1e-9 s)/dt⌉ ticks, at least one) at other ticks and durations, the swinging side
// alternating from the configured first side, the early touch-down (never before the
// tick after mid-swing, only on the swing ankle, strictly below the threshold), and the
// events (swing started, mid-swing once per swing, touch-down early or not); the optional
// weight shift between the body lift and the first step (its ticks, its rounding, skipped
// at 0 s, its names).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "dmbd/base/error.hpp"
#include "dmbd/wholebody/phase_machine.hpp"

namespace dmbd::wholebody::testing {
namespace {

constexpr double kDt = 0.001;  // 1 kHz
// Clocks are sums of dt: 10,000 additions of 0.001 s are off by ≲ 1e-12 s.
constexpr double kTimeTol_s = 1e-9;

// The ankles' joint velocities (left, right) for a tick, from the machine's state before it.
using AnkleVelocities = std::function<std::array<double, 2>(const PhaseInfo& before)>;

std::vector<PhaseInfo> run(PhaseMachine& m, int ticks, double dt_s, const AnkleVelocities& ankles = nullptr) {
  std::vector<PhaseInfo> trace;
  trace.reserve(ticks);
  for (int k = 0; k < ticks; ++k) {
    const std::array<double, 2> v = ankles ? ankles(m.info()) : std::array<double, 2>{0.0, 0.0};
    trace.push_back(m.update(dt_s, v[0], v[1]));
  }
  return trace;
}

// A run of ticks with the same phase, side and step.
struct Segment {
  std::string name;
  int first_tick = 0;
  int ticks = 0;
};

std::vector<Segment> segments(const std::vector<PhaseInfo>& trace) {
  std::vector<Segment> out;
  for (int k = 0; k < static_cast<int>(trace.size()); ++k) {
    const PhaseInfo& i = trace[k];
    const bool same = k > 0 && trace[k - 1].phase == i.phase && trace[k - 1].swing_side == i.swing_side &&
                      trace[k - 1].step == i.step;
    if (same)
      ++out.back().ticks;
    else
      out.push_back({i.name, k, 1});
  }
  return out;
}

std::vector<std::string> names(const std::vector<Segment>& segs) {
  std::vector<std::string> out;
  for (const Segment& s : segs) out.push_back(s.name);
  return out;
}

std::vector<int> lengths(const std::vector<Segment>& segs) {
  std::vector<int> out;
  for (const Segment& s : segs) out.push_back(s.ticks);
  return out;
}

// Both ankles at v (rad/s) on every tick.
AnkleVelocities both_ankles(double v) {
  return [v](const PhaseInfo&) { return std::array<double, 2>{v, v}; };
}

// The swing ankle at v_swing and the other at v_stance, on every tick.
AnkleVelocities swing_ankle(double v_swing, double v_stance) {
  return [=](const PhaseInfo& before) {
    return before.swing_side == Side::Left ? std::array<double, 2>{v_swing, v_stance}
                                           : std::array<double, 2>{v_stance, v_swing};
  };
}

constexpr int kStartUpTicks = 4000;  // 2.0 s + 2.0 s at 1 kHz
constexpr int kStepTicks = 380;      // 10 + 30 + 330 + 10

TEST(PhaseMachine, BeforeAndOnTheFirstTickItIsTheJointMoveAtTimeZero) {
  PhaseMachine m;
  EXPECT_EQ(m.info().phase, Phase::JointMove);
  EXPECT_STREQ(m.info().name, "JS");
  const PhaseInfo& first = m.update(kDt, 0.0, 0.0);
  EXPECT_EQ(first.phase, Phase::JointMove);
  EXPECT_EQ(first.time_in_phase_s, 0.0);  // the first tick's dt is not added
  EXPECT_EQ(first.time_s, 0.0);
  EXPECT_DOUBLE_EQ(first.phase_duration_s, 2.0);
  EXPECT_EQ(first.step, 0);
  EXPECT_TRUE(first.events.phase_started);
  EXPECT_EQ(first.swing_side, Side::Left);  // the default first swing side
  EXPECT_NEAR(m.update(kDt, 0.0, 0.0).time_in_phase_s, kDt, kTimeTol_s);
  EXPECT_FALSE(m.info().events.phase_started);
}

TEST(PhaseMachine, StartUpThenTheStepCycleWithExactTickCountsAt1kHz) {
  PhaseMachine m;
  const std::vector<PhaseInfo> trace = run(m, kStartUpTicks + 3 * kStepTicks + 1, kDt);
  const std::vector<Segment> segs = segments(trace);
  ASSERT_EQ(segs.size(), 15u);  // JS, BL, three steps of four phases, the fourth step's DS
  const std::vector<std::string> expected_names = {"JS",   "BL",   "DS", "LF-L", "SW-L", "LN-L", "DS", "LF-R",
                                                   "SW-R", "LN-R", "DS", "LF-L", "SW-L", "LN-L", "DS"};
  const std::vector<int> expected_ticks = {2000, 2000, 10, 30, 330, 10, 10, 30, 330, 10, 10, 30, 330, 10, 1};
  EXPECT_EQ(names(segs), expected_names);
  EXPECT_EQ(lengths(segs), expected_ticks);
  // Each phase starts at time 0, advances by dt, and reports its nominal duration; the
  // step number is 0 in the start-up and 1, 2, 3, 4 for the steps.
  for (std::size_t s = 0; s < segs.size(); ++s) {
    const int step = s < 2 ? 0 : 1 + static_cast<int>(s - 2) / 4;
    for (int j = 0; j < segs[s].ticks; ++j) {
      const PhaseInfo& i = trace[segs[s].first_tick + j];
      ASSERT_NEAR(i.time_in_phase_s, j * kDt, kTimeTol_s) << segs[s].name << " tick " << j;
      ASSERT_EQ(i.events.phase_started, j == 0) << segs[s].name << " tick " << j;
      ASSERT_EQ(i.step, step) << segs[s].name;
      ASSERT_NEAR(i.time_s, (segs[s].first_tick + j) * kDt, kTimeTol_s);
    }
  }
  const double durations_s[] = {2.0, 2.0, 0.01, 0.03, 0.33, 0.01};
  for (const Segment& s : segs)
    EXPECT_DOUBLE_EQ(trace[s.first_tick].phase_duration_s, durations_s[static_cast<int>(trace[s.first_tick].phase)]);
  EXPECT_EQ(trace.back().touch_downs, 3);
}

// The rounding rule: a phase of duration T lasts ⌈(T − 1e-9 s)/dt⌉ ticks, at least one.
TEST(PhaseMachine, RoundingRuleForDurationsThatAreNotWholeTicks) {
  PhaseMachineParams p;
  p.joint_move_s = 0.0015;          // 1.5 ticks → 2
  p.body_lift_s = 0.0004;           // under a tick → 1
  p.double_support_s = 0.0105;      // 10.5 → 11
  p.lift_s = 0.0300000000004;       // 30 + 4e-10 ticks: within 1e-9 s → 30
  p.swing_s = 0.330002;             // 330 + 0.002 ticks: beyond 1e-9 s → 331
  p.landing_s = 0.01;               // 10
  PhaseMachine m(p);
  const std::vector<Segment> segs = segments(run(m, 2 + 1 + 11 + 30 + 331 + 10 + 1, kDt));
  EXPECT_EQ(lengths(segs), (std::vector<int>{2, 1, 11, 30, 331, 10, 1}));
}

TEST(PhaseMachine, RoundingRuleAtOtherTickRates) {
  PhaseMachineParams p;
  p.joint_move_s = 0.1;
  p.body_lift_s = 0.1;
  {
    PhaseMachine m(p);  // 500 Hz: every default is a whole number of ticks
    const std::vector<Segment> segs = segments(run(m, 50 + 50 + 5 + 15 + 165 + 5 + 1, 0.002));
    EXPECT_EQ(lengths(segs), (std::vector<int>{50, 50, 5, 15, 165, 5, 1}));
  }
  {
    // 0.003 s ticks: 0.1 → 33.3 → 34; 0.01 → 3.3 → 4; 0.03 and 0.33 are 10 and 110 ticks
    // but their sums of 0.003 are off by rounding: the 1e-9 s tolerance keeps 10 and 110.
    PhaseMachine m(p);
    const std::vector<Segment> segs = segments(run(m, 34 + 34 + 4 + 10 + 110 + 4 + 1, 0.003));
    EXPECT_EQ(lengths(segs), (std::vector<int>{34, 34, 4, 10, 110, 4, 1}));
  }
}

TEST(PhaseMachine, SwingSideAlternatesFromTheConfiguredFirstSide) {
  for (const Side first : {Side::Left, Side::Right}) {
    PhaseMachineParams p;
    p.first_swing_side = first;
    PhaseMachine m(p);
    EXPECT_EQ(m.info().swing_side, first);
    const std::vector<PhaseInfo> trace = run(m, kStartUpTicks + 4 * kStepTicks, kDt);
    std::vector<Side> swings;
    for (const PhaseInfo& i : trace)
      if (i.events.swing_started) swings.push_back(i.swing_side);
    const Side second = other(first);
    EXPECT_EQ(swings, (std::vector<Side>{first, second, first, second})) << to_string(first);
    // A step's four phases share its side: the DS before a lift already names the side
    // about to swing.
    for (const PhaseInfo& i : trace) {
      if (i.step == 0) continue;
      ASSERT_EQ(i.swing_side, i.step % 2 == 1 ? first : second) << i.name;
    }
  }
}

TEST(PhaseMachine, EarlyTouchDownOnlyOnTheTickAfterMidSwingAtTheEarliest) {
  PhaseMachine m;
  // Both ankles far below −2.8 rad/s on every tick: DS, lift and landing ignore it; the
  // swing reaches mid-swing (its tick at 0.165 s) and ends on the next tick, 0.166 s.
  const std::vector<PhaseInfo> trace = run(m, kStartUpTicks + 2 * (10 + 30 + 166 + 10) + 1, kDt, both_ankles(-10.0));
  const std::vector<Segment> segs = segments(trace);
  EXPECT_EQ(lengths(segs), (std::vector<int>{2000, 2000, 10, 30, 166, 10, 10, 30, 166, 10, 1}));
  for (const Segment& s : segs) {
    const PhaseInfo& first = trace[s.first_tick];
    if (first.phase != Phase::Landing) continue;
    const PhaseInfo& last_swing = trace[s.first_tick - 1];
    EXPECT_NEAR(last_swing.time_in_phase_s, 0.165, kTimeTol_s);  // exactly half the swing
    EXPECT_TRUE(first.events.touch_down);
    EXPECT_TRUE(first.events.touch_down_early);
    EXPECT_EQ(first.time_in_phase_s, 0.0);
    EXPECT_DOUBLE_EQ(first.phase_duration_s, 0.01);
  }
}

TEST(PhaseMachine, EarlyTouchDownWhenTheSwingAnkleDropsLaterInTheSwing) {
  PhaseMachine m;
  // The swing ankle drops to −3 rad/s on the swing tick at 0.250 s.
  const AnkleVelocities drop = [](const PhaseInfo& before) {
    const bool late = before.phase == Phase::Swing && before.time_in_phase_s > 0.2485;
    const double v = late ? -3.0 : 0.0;
    return before.swing_side == Side::Left ? std::array<double, 2>{v, 0.0} : std::array<double, 2>{0.0, v};
  };
  const std::vector<PhaseInfo> trace = run(m, kStartUpTicks + 2 * (10 + 30 + 250 + 10), kDt, drop);
  const std::vector<Segment> segs = segments(trace);
  EXPECT_EQ(lengths(segs), (std::vector<int>{2000, 2000, 10, 30, 250, 10, 10, 30, 250, 10}));
  EXPECT_TRUE(trace[segs[5].first_tick].events.touch_down_early);
  EXPECT_TRUE(trace[segs[9].first_tick].events.touch_down_early);
  EXPECT_EQ(trace.back().touch_downs, 2);
}

// The height gate (touch_down_height_max_m, issue 27): the ankle trigger from the swing's
// 0.250 s on, the foot 0.05 m up until 0.300 s and 0.01 m after; with a 0.015 m gate the
// swing ends on the first tick down there (300 ticks), without one at 0.250 s.
TEST(PhaseMachine, TheHeightGateHoldsTheTriggerWhileTheSwingFootIsUp) {
  const auto run_gated = [](double gate_m, double height_up_m) {
    PhaseMachineParams p;
    p.touch_down_height_max_m = gate_m;
    PhaseMachine m(p);
    std::vector<PhaseInfo> trace;
    for (int k = 0; k < kStartUpTicks + 10 + 30 + 330 + 10; ++k) {
      const PhaseInfo& b = m.info();
      const bool swinging = b.phase == Phase::Swing;
      const double v = swinging && b.time_in_phase_s > 0.2485 ? -3.0 : 0.0;
      const double h = swinging && b.time_in_phase_s < 0.2985 ? height_up_m : 0.01;
      trace.push_back(m.update(kDt, v, 0.0, h));
    }
    return lengths(segments(trace));
  };
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(run_gated(0.015, 0.05), (std::vector<int>{2000, 2000, 10, 30, 300, 10, 10, 20}));
  EXPECT_EQ(run_gated(inf, 0.05), (std::vector<int>{2000, 2000, 10, 30, 250, 10, 10, 30, 40}));
  EXPECT_EQ(run_gated(0.015, std::nan("")), (std::vector<int>{2000, 2000, 10, 30, 300, 10, 10, 20}));  // NaN only while up
  EXPECT_EQ(run_gated(0.06, 0.05), (std::vector<int>{2000, 2000, 10, 30, 250, 10, 10, 30, 40}));  // 0.05 m passes a 0.06 m gate
}

TEST(PhaseMachine, OnlyTheSwingAnkleStrictlyBelowTheThresholdTriggers) {
  const int ticks = kStartUpTicks + 2 * kStepTicks;
  const std::vector<int> nominal = {2000, 2000, 10, 30, 330, 10, 10, 30, 330, 10};
  {
    PhaseMachine m;  // the stance ankle far below, the swing ankle at rest: no trigger
    const std::vector<PhaseInfo> trace = run(m, ticks, kDt, swing_ankle(0.0, -10.0));
    const std::vector<Segment> segs = segments(trace);
    EXPECT_EQ(lengths(segs), nominal);
    EXPECT_TRUE(trace[segs[5].first_tick].events.touch_down);  // the swing ran its time
    EXPECT_FALSE(trace[segs[5].first_tick].events.touch_down_early);
  }
  {
    PhaseMachine m;  // exactly at −2.8 rad/s is not below it
    EXPECT_EQ(lengths(segments(run(m, ticks, kDt, swing_ankle(-2.8, 0.0)))), nominal);
  }
  {
    PhaseMachineParams p;  // a configured threshold: −3 no longer triggers, −5.5 does
    p.touch_down_ankle_velocity_rad_s = -5.0;
    PhaseMachine m(p), n(p);
    EXPECT_EQ(lengths(segments(run(m, ticks, kDt, swing_ankle(-3.0, 0.0)))), nominal);
    EXPECT_EQ(lengths(segments(run(n, kStartUpTicks + 10 + 30 + 166 + 1, kDt, swing_ankle(-5.5, 0.0)))),
              (std::vector<int>{2000, 2000, 10, 30, 166, 1}));
  }
}

// Events of a run: swing started on each swing's first tick, mid-swing once per swing at
// t = T/2 and before its touch-down, touch-down on each landing's first tick.
void expect_events_in_place(const std::vector<PhaseInfo>& trace, bool early) {
  int swings = 0, mids = 0, touch_downs = 0;
  for (std::size_t k = 0; k < trace.size(); ++k) {
    const PhaseInfo& i = trace[k];
    const bool swing_start = i.phase == Phase::Swing && i.events.phase_started;
    const bool landing_start = i.phase == Phase::Landing && i.events.phase_started;
    ASSERT_EQ(i.events.swing_started, swing_start) << "tick " << k;
    ASSERT_EQ(i.events.touch_down, landing_start) << "tick " << k;
    ASSERT_EQ(i.events.touch_down_early, landing_start && early) << "tick " << k;
    if (i.events.mid_swing) {
      ASSERT_EQ(i.phase, Phase::Swing) << "tick " << k;
      EXPECT_NEAR(i.time_in_phase_s, 0.165, kTimeTol_s);
      ASSERT_EQ(mids, swings - 1) << "a second mid-swing in one swing, at tick " << k;
      ++mids;
    }
    if (swing_start) ++swings;
    if (landing_start) {
      ASSERT_EQ(mids, swings) << "a touch-down before mid-swing, at tick " << k;
      ++touch_downs;
    }
  }
  EXPECT_EQ(mids, swings);
  EXPECT_EQ(touch_downs, swings);
  EXPECT_EQ(trace.back().touch_downs, touch_downs);
  EXPECT_GE(swings, 6);
}

TEST(PhaseMachine, MidSwingOncePerSwingAndTheOtherEventsOnTheirTicks) {
  PhaseMachine nominal, early;  // each run ends on a step's last tick
  expect_events_in_place(run(nominal, kStartUpTicks + 6 * kStepTicks, kDt), false);
  expect_events_in_place(run(early, kStartUpTicks + 10 * (10 + 30 + 166 + 10), kDt, both_ankles(-10.0)), true);
}

TEST(PhaseMachine, OverlayNamesAndPhaseNames) {
  PhaseMachineParams p;
  p.first_swing_side = Side::Right;
  PhaseMachine m(p);
  std::vector<std::string> seen = names(segments(run(m, kStartUpTicks + 2 * kStepTicks, kDt)));
  EXPECT_EQ(seen, (std::vector<std::string>{"JS", "BL", "DS", "LF-R", "SW-R", "LN-R", "DS", "LF-L", "SW-L", "LN-L"}));
  EXPECT_STREQ(to_string(Phase::Swing), "swing");
  EXPECT_STREQ(to_string(Side::Right), "R");
  EXPECT_EQ(other(Side::Right), Side::Left);
}

// The weight shift (weight_shift_s > 0) between the body lift and the first step: 0.5 s
// is 500 ticks at 1 kHz, named "WS", step 0, its time from 0 by dt, its nominal
// duration reported; the first double support (step 1) follows it.
TEST(PhaseMachine, WeightShiftComesBetweenTheBodyLiftAndTheFirstStep) {
  PhaseMachineParams p;
  p.weight_shift_s = 0.5;
  PhaseMachine m(p);
  const std::vector<PhaseInfo> trace = run(m, kStartUpTicks + 500 + kStepTicks + 1, kDt);
  const std::vector<Segment> segs = segments(trace);
  EXPECT_EQ(names(segs), (std::vector<std::string>{"JS", "BL", "WS", "DS", "LF-L", "SW-L", "LN-L", "DS"}));
  EXPECT_EQ(lengths(segs), (std::vector<int>{2000, 2000, 500, 10, 30, 330, 10, 1}));
  ASSERT_EQ(segs.size(), 8u);
  for (int j = 0; j < 500; ++j) {
    const PhaseInfo& i = trace[kStartUpTicks + j];
    ASSERT_EQ(i.phase, Phase::WeightShift) << "tick " << j;
    ASSERT_EQ(i.step, 0) << "tick " << j;
    ASSERT_EQ(i.events.phase_started, j == 0) << "tick " << j;
    ASSERT_NEAR(i.time_in_phase_s, j * kDt, kTimeTol_s);
    ASSERT_EQ(i.phase_duration_s, 0.5);
    ASSERT_EQ(i.alpha, 0.0);
  }
  const PhaseInfo& ds = trace[kStartUpTicks + 500];
  EXPECT_EQ(ds.phase, Phase::DoubleSupport);
  EXPECT_TRUE(ds.events.phase_started);
  EXPECT_EQ(ds.step, 1);
  EXPECT_EQ(trace.back().step, 2);
  EXPECT_EQ(trace.back().touch_downs, 1);
}

// The weight shift follows the rounding rule of every phase: ⌈(T − 1e-9 s)/dt⌉ ticks, at
// least one (0.0105 s → 11 ticks; 1e-10 s, under the 1e-9 s tolerance → 1 tick).
TEST(PhaseMachine, WeightShiftFollowsTheRoundingRule) {
  for (const auto& [duration_s, ticks] : {std::pair{0.0105, 11}, std::pair{1e-10, 1}}) {
    PhaseMachineParams p;
    p.weight_shift_s = duration_s;
    PhaseMachine m(p);
    const std::vector<Segment> segs = segments(run(m, kStartUpTicks + ticks + 1, kDt));
    EXPECT_EQ(names(segs), (std::vector<std::string>{"JS", "BL", "WS", "DS"})) << duration_s;
    EXPECT_EQ(lengths(segs), (std::vector<int>{2000, 2000, ticks, 1})) << duration_s;
  }
}

// weight_shift_s = 0 (the default) skips the phase: a phase of 0 s would otherwise last
// one tick (the rounding rule's "at least one"); here the body lift is followed on tick
// 4000 by the first double support, as without the option.
TEST(PhaseMachine, ZeroWeightShiftSkipsThePhase) {
  PhaseMachineParams p;
  p.weight_shift_s = 0.0;
  PhaseMachine m(p);
  const std::vector<PhaseInfo> trace = run(m, kStartUpTicks + kStepTicks + 1, kDt);
  const std::vector<Segment> segs = segments(trace);
  EXPECT_EQ(names(segs), (std::vector<std::string>{"JS", "BL", "DS", "LF-L", "SW-L", "LN-L", "DS"}));
  EXPECT_EQ(lengths(segs), (std::vector<int>{2000, 2000, 10, 30, 330, 10, 1}));
  for (const PhaseInfo& i : trace) ASSERT_NE(i.phase, Phase::WeightShift);
  EXPECT_EQ(trace[kStartUpTicks].step, 1);
}

// "weight shift" by name; "WS" whichever side swings first; the enum's earlier values
// keep their numbers (WeightShift was added last).
TEST(PhaseMachine, WeightShiftNames) {
  EXPECT_STREQ(to_string(Phase::WeightShift), "weight shift");
  EXPECT_EQ(static_cast<int>(Phase::Landing), 5);
  EXPECT_EQ(static_cast<int>(Phase::WeightShift), 6);
  PhaseMachineParams p;
  p.weight_shift_s = 0.1;
  p.first_swing_side = Side::Right;
  PhaseMachine m(p);
  const std::vector<Segment> segs = segments(run(m, kStartUpTicks + 100 + 11, kDt));
  EXPECT_EQ(names(segs), (std::vector<std::string>{"JS", "BL", "WS", "DS", "LF-R"}));
}

TEST(PhaseMachine, ResetStartsOver) {
  PhaseMachine m;
  run(m, kStartUpTicks + 100, kDt);
  ASSERT_EQ(m.info().phase, Phase::Swing);
  m.reset();
  EXPECT_EQ(m.info().phase, Phase::JointMove);
  EXPECT_EQ(m.info().step, 0);
  const PhaseInfo& first = m.update(kDt, 0.0, 0.0);
  EXPECT_EQ(first.time_s, 0.0);
  EXPECT_TRUE(first.events.phase_started);
  EXPECT_EQ(lengths(segments(run(m, kStartUpTicks, kDt))), (std::vector<int>{1999, 2000, 1}));
}

TEST(PhaseMachine, RejectsANegativeOrNonFiniteTick) {
  PhaseMachine m;
  EXPECT_THROW(m.update(-0.001, 0.0, 0.0), InputError);
  EXPECT_THROW(m.update(std::nan(""), 0.0, 0.0), InputError);
  EXPECT_NO_THROW(m.update(0.0, 0.0, 0.0));
}

}  // namespace
}  // namespace dmbd::wholebody::testing
