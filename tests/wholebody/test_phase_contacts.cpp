// What the contact-phase state machine (phase_machine.hpp) gives the whole-body QP per
// foot: α = ½(1 − cos πt/T) at 0, ½ and 1; the moving foot blended stance → swing through
// lift and swing → stance through landing (F_max 550 ↔ 0 N, tangential weight 1 ↔ 5,
// normal weight 0.01 ↔ 0.5, slack weight 1000 ↔ 0.001), out of contact in swing, both
// feet at stance values in double support and in the optional weight shift; the F_max
// ramp 5 → 300 N of the body lift; parameters that are rejected.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "dmbd/base/error.hpp"
#include "dmbd/wholebody/phase_machine.hpp"

namespace dmbd::wholebody::testing {
namespace {

constexpr double kDt = 0.001;
constexpr double kPi = 3.14159265358979323846;
// α is formed from a clock that is a sum of dt (off by ≲ 1e-15 s within a phase), so
// α is good to ~1e-13 and F_max (≤ 550 N) to ~1e-10 N: 1e-12 on α, 1e-9 on the values.
constexpr double kAlphaTol = 1e-12;
constexpr double kValueTol = 1e-9;

const ContactValues kStance{550.0, 1.0, 0.01, 1000.0};
const ContactValues kSwing{0.0, 5.0, 0.5, 0.001};

std::vector<PhaseInfo> run(PhaseMachine& m, int ticks) {
  std::vector<PhaseInfo> trace;
  for (int k = 0; k < ticks; ++k) trace.push_back(m.update(kDt, 0.0, 0.0));
  return trace;
}

// The first tick of the n-th phase p (n from 0) in the trace.
int first_tick_of(const std::vector<PhaseInfo>& trace, Phase p, int n) {
  for (int k = 0; k < static_cast<int>(trace.size()); ++k)
    if (trace[k].phase == p && trace[k].events.phase_started && n-- == 0) return k;
  return -1;
}

void expect_values(const ContactValues& got, const ContactValues& want, const std::string& where) {
  EXPECT_NEAR(got.max_normal_force_N, want.max_normal_force_N, kValueTol) << where;
  EXPECT_NEAR(got.tangential_force_weight, want.tangential_force_weight, kValueTol) << where;
  EXPECT_NEAR(got.normal_force_weight, want.normal_force_weight, kValueTol) << where;
  EXPECT_NEAR(got.slack_weight, want.slack_weight, kValueTol) << where;
}

// Exactly (no tolerance): at α = 0 and 1 the blend must give the end values themselves.
void expect_exact(const ContactValues& got, const ContactValues& want, const std::string& where) {
  EXPECT_EQ(got.max_normal_force_N, want.max_normal_force_N) << where;
  EXPECT_EQ(got.tangential_force_weight, want.tangential_force_weight) << where;
  EXPECT_EQ(got.normal_force_weight, want.normal_force_weight) << where;
  EXPECT_EQ(got.slack_weight, want.slack_weight) << where;
}

TEST(PhaseContacts, BlendIsAHalfCosineFromZeroToOne) {
  EXPECT_EQ(contact_blend(0.0, 0.03), 0.0);
  EXPECT_NEAR(contact_blend(0.015, 0.03), 0.5, 1e-15);
  EXPECT_EQ(contact_blend(0.03, 0.03), 1.0);
  EXPECT_NEAR(contact_blend(0.0075, 0.03), 0.5 * (1.0 - std::sqrt(0.5)), 1e-15);  // t = T/4
  EXPECT_EQ(contact_blend(-0.01, 0.03), 0.0);  // clamped
  EXPECT_EQ(contact_blend(0.05, 0.03), 1.0);
  // (1 − α) a + α b at α = ¼: 412.5 N, 2, 0.1325, 750.00025.
  expect_values(blend(kStance, kSwing, 0.25), {412.5, 2.0, 0.1325, 750.00025}, "blend at 1/4");
}

TEST(PhaseContacts, LiftTakesTheSwingFootFromStanceToSwingValues) {
  PhaseMachine m;
  const std::vector<PhaseInfo> trace = run(m, 4000 + 2 * 380);
  for (int step = 0; step < 2; ++step) {
    const int k0 = first_tick_of(trace, Phase::Lift, step);
    ASSERT_GE(k0, 0);
    const Side swing = trace[k0].swing_side, stance = other(swing);
    EXPECT_EQ(swing, step == 0 ? Side::Left : Side::Right);
    // α = 0 on the lift's first tick: the stance values exactly.
    EXPECT_EQ(trace[k0].alpha, 0.0);
    expect_exact(trace[k0].foot(swing).values, kStance, "lift, t = 0");
    // α = ½ at t = T/2 = 0.015 s: halfway, 275 N, 3, 0.255, 500.0005.
    EXPECT_NEAR(trace[k0 + 15].alpha, 0.5, kAlphaTol);
    expect_values(trace[k0 + 15].foot(swing).values, {275.0, 3.0, 0.255, 500.0005}, "lift, t = T/2");
    // Every tick of the lift: the half-cosine blend, the foot still in contact; the
    // stance foot at stance values.
    for (int j = 0; j < 30; ++j) {
      const PhaseInfo& i = trace[k0 + j];
      ASSERT_EQ(i.phase, Phase::Lift);
      const double alpha = 0.5 * (1.0 - std::cos(kPi * j / 30.0));
      EXPECT_NEAR(i.alpha, alpha, kAlphaTol) << "lift tick " << j;
      EXPECT_TRUE(i.foot(swing).in_contact);
      expect_values(i.foot(swing).values, blend(kStance, kSwing, alpha), "lift tick " + std::to_string(j));
      EXPECT_TRUE(i.foot(stance).in_contact);
      expect_exact(i.foot(stance).values, kStance, "stance foot in lift");
    }
    // α = 1 at the lift's end (t = T): the swing's first tick has the swing values, out
    // of contact.
    const PhaseInfo& swing_start = trace[k0 + 30];
    ASSERT_EQ(swing_start.phase, Phase::Swing);
    EXPECT_FALSE(swing_start.foot(swing).in_contact);
    expect_exact(swing_start.foot(swing).values, kSwing, "swing");
  }
}

TEST(PhaseContacts, LandingTakesTheSwingFootFromSwingBackToStanceValues) {
  PhaseMachine m;
  const std::vector<PhaseInfo> trace = run(m, 4000 + 2 * 380 + 1);
  for (int step = 0; step < 2; ++step) {
    const int k0 = first_tick_of(trace, Phase::Landing, step);
    ASSERT_GE(k0, 0);
    const Side swing = trace[k0].swing_side, stance = other(swing);
    EXPECT_EQ(trace[k0].alpha, 0.0);
    expect_exact(trace[k0].foot(swing).values, kSwing, "landing, t = 0");
    EXPECT_TRUE(trace[k0].foot(swing).in_contact);  // a contact again, with F_max 0 N
    EXPECT_NEAR(trace[k0 + 5].alpha, 0.5, kAlphaTol);  // t = T/2 = 0.005 s
    expect_values(trace[k0 + 5].foot(swing).values, {275.0, 3.0, 0.255, 500.0005}, "landing, t = T/2");
    for (int j = 0; j < 10; ++j) {
      const PhaseInfo& i = trace[k0 + j];
      ASSERT_EQ(i.phase, Phase::Landing);
      const double alpha = 0.5 * (1.0 - std::cos(kPi * j / 10.0));
      EXPECT_NEAR(i.alpha, alpha, kAlphaTol) << "landing tick " << j;
      expect_values(i.foot(swing).values, blend(kSwing, kStance, alpha), "landing tick " + std::to_string(j));
      expect_exact(i.foot(stance).values, kStance, "stance foot in landing");
    }
    // α = 1 at the landing's end: the next double support has both feet at stance values.
    const PhaseInfo& ds = trace[k0 + 10];
    ASSERT_EQ(ds.phase, Phase::DoubleSupport);
    for (const Side s : {Side::Left, Side::Right}) {
      EXPECT_TRUE(ds.foot(s).in_contact);
      expect_exact(ds.foot(s).values, kStance, "double support");
    }
  }
}

TEST(PhaseContacts, InSwingOnlyTheStanceFootIsInContact) {
  PhaseMachine m;
  const std::vector<PhaseInfo> trace = run(m, 4000 + 2 * 380);
  int swing_ticks = 0;
  for (const PhaseInfo& i : trace) {
    if (i.phase != Phase::Swing) continue;
    ++swing_ticks;
    EXPECT_FALSE(i.foot(i.swing_side).in_contact);
    EXPECT_EQ(i.foot(i.swing_side).values.max_normal_force_N, 0.0);
    EXPECT_TRUE(i.foot(other(i.swing_side)).in_contact);
    EXPECT_EQ(i.foot(other(i.swing_side)).values.max_normal_force_N, 550.0);
    EXPECT_EQ(i.alpha, 0.0);
  }
  EXPECT_EQ(swing_ticks, 2 * 330);
}

TEST(PhaseContacts, BodyLiftRampsTheMaxNormalForceOfBothFeet) {
  PhaseMachine m;
  const std::vector<PhaseInfo> trace = run(m, 4001);
  for (int k = 0; k < 2000; ++k)  // the joint move: the ramp's start value
    for (const Side s : {Side::Left, Side::Right}) {
      ASSERT_TRUE(trace[k].foot(s).in_contact);
      ASSERT_EQ(trace[k].foot(s).values.max_normal_force_N, 5.0) << "tick " << k;
    }
  // Body lift tick j: 5 + 295 j/2000 N (linear), stance weights.
  const int k0 = first_tick_of(trace, Phase::BodyLift, 0);
  ASSERT_EQ(k0, 2000);
  for (int j = 0; j < 2000; ++j)
    for (const Side s : {Side::Left, Side::Right}) {
      const FootContact& f = trace[k0 + j].foot(s);
      ASSERT_TRUE(f.in_contact);
      ASSERT_NEAR(f.values.max_normal_force_N, 5.0 + 295.0 * j / 2000.0, kValueTol) << "tick " << j;
      ASSERT_EQ(f.values.tangential_force_weight, 1.0);
      ASSERT_EQ(f.values.normal_force_weight, 0.01);
      ASSERT_EQ(f.values.slack_weight, 1000.0);
    }
  EXPECT_EQ(trace[k0].foot(Side::Left).values.max_normal_force_N, 5.0);
  EXPECT_NEAR(trace[k0 + 1000].foot(Side::Right).values.max_normal_force_N, 152.5, kValueTol);
  EXPECT_NEAR(trace[k0 + 1999].foot(Side::Left).values.max_normal_force_N, 299.8525, kValueTol);
  EXPECT_EQ(trace[4000].phase, Phase::DoubleSupport);
  EXPECT_EQ(trace[4000].foot(Side::Left).values.max_normal_force_N, 550.0);
}

TEST(PhaseContacts, TheRampAndTheContactValuesAreConfigurable) {
  PhaseMachineParams p;
  p.body_lift_s = 1.0;
  p.body_lift_start_force_N = 10.0;
  p.body_lift_end_force_N = 210.0;
  p.stance = {500.0, 2.0, 0.02, 100.0};
  p.swing = {20.0, 4.0, 0.4, 0.01};
  PhaseMachine m(p);
  const std::vector<PhaseInfo> trace = run(m, 2000 + 1000 + 10 + 16);
  EXPECT_NEAR(trace[2000 + 500].foot(Side::Left).values.max_normal_force_N, 110.0, kValueTol);
  const PhaseInfo& mid_lift = trace[2000 + 1000 + 10 + 15];
  ASSERT_EQ(mid_lift.phase, Phase::Lift);
  expect_values(mid_lift.foot(Side::Left).values, {260.0, 3.0, 0.21, 50.005}, "configured lift, t = T/2");
}

// In the weight shift both feet are in contact with the stance values, exactly (no
// blend: the configured values themselves), from its first tick (right after the body
// lift's ramp, which ends below the stance F_max) to its last.
TEST(PhaseContacts, WeightShiftHasBothFeetAtStanceValues) {
  PhaseMachineParams p;
  p.weight_shift_s = 0.2;
  p.stance = {500.0, 2.0, 0.02, 100.0};
  PhaseMachine m(p);
  const std::vector<PhaseInfo> trace = run(m, 4000 + 200 + 1);
  ASSERT_EQ(first_tick_of(trace, Phase::WeightShift, 0), 4000);
  for (int k = 4000; k < 4200; ++k) {
    ASSERT_EQ(trace[k].phase, Phase::WeightShift) << "tick " << k;
    for (const Side s : {Side::Left, Side::Right}) {
      EXPECT_TRUE(trace[k].foot(s).in_contact) << "tick " << k;
      expect_exact(trace[k].foot(s).values, p.stance, "weight shift tick " + std::to_string(k));
    }
  }
  EXPECT_LT(trace[3999].foot(Side::Left).values.max_normal_force_N, 300.0);  // the body lift before it
  EXPECT_EQ(trace[4200].phase, Phase::DoubleSupport);
}

TEST(PhaseContacts, RejectsParametersThatCannotBeUsed) {
  const auto rejects = [](auto change, const std::string& name) {
    PhaseMachineParams p;
    change(p);
    try {
      PhaseMachine m(p);
      ADD_FAILURE() << name << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  };
  rejects([](PhaseMachineParams& p) { p.swing_s = 0.0; }, "swing_s");
  rejects([](PhaseMachineParams& p) { p.lift_s = -0.03; }, "lift_s");
  rejects([](PhaseMachineParams& p) { p.landing_s = std::nan(""); }, "landing_s");
  rejects([](PhaseMachineParams& p) { p.joint_move_s = std::numeric_limits<double>::infinity(); }, "joint_move_s");
  rejects([](PhaseMachineParams& p) { p.body_lift_end_force_N = -1.0; }, "body_lift_end_force_N");
  rejects([](PhaseMachineParams& p) { p.stance.max_normal_force_N = -550.0; }, "stance.max_normal_force_N");
  rejects([](PhaseMachineParams& p) { p.swing.slack_weight = 0.0; }, "swing.slack_weight");
  rejects([](PhaseMachineParams& p) { p.touch_down_ankle_velocity_rad_s = std::nan(""); },
          "touch_down_ankle_velocity_rad_s");
  rejects([](PhaseMachineParams& p) { p.touch_down_height_max_m = 0.0; }, "touch_down_height_max_m");
  rejects([](PhaseMachineParams& p) { p.touch_down_height_max_m = std::nan(""); }, "touch_down_height_max_m");
  rejects([](PhaseMachineParams& p) { p.weight_shift_s = -0.1; }, "weight_shift_s");
  rejects([](PhaseMachineParams& p) { p.weight_shift_s = std::nan(""); }, "weight_shift_s");
  rejects([](PhaseMachineParams& p) { p.weight_shift_s = std::numeric_limits<double>::infinity(); }, "weight_shift_s");
  EXPECT_NO_THROW(PhaseMachine{PhaseMachineParams{}});
}

}  // namespace
}  // namespace dmbd::wholebody::testing
