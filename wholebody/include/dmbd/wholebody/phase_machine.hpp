#pragma once
// The contact-phase state machine of the balancing controller (issue 15; the figures of
// ../shared/draco-facts.md, "The balancing controller in detail"). It says, every control
// tick, which phase the robot is in and what the whole-body QP should ask of each foot:
//
//   start-up:  joint move (2.0 s, joint-space move to the stance posture)
//              → body lift (2.0 s, both feet's F_max ramped linearly 5 → 300 N)
//              → weight shift (weight_shift_s, 0 by default: skipped; not in the
//                authors' controller: the CoM swayed onto the stepping orbit, both feet
//                in contact with the stance values)
//   per step:  double support (0.01 s) → lift (0.03 s) → swing (0.33 s) → landing (0.01 s),
//              the swinging side alternating (the first one configurable, left by default).
//
// Contact values per foot (F_max, weights on tangential and normal force and on the
// contact-acceleration slack): stance 550 N / 1 / 0.01 / 1000, swing 0 N / 5 / 0.5 / 0.001.
// In lift the moving foot goes stance → swing, in landing swing → stance, blended by
// α = ½(1 − cos πt/T); in swing it is not in contact; in double support both feet have
// the stance values; in the start-up both feet are in contact with the stance weights and
// F_max at the ramp's value (its start, 5 N, during the joint move).
//
// Touch-down: the swing ends when its time is up, or earlier when the swing ankle's joint
// velocity is below −2.8 rad/s (the facts' sign convention), but only on a tick after the
// mid-swing tick (the first with t ≥ T/2): never in the first half. With
// touch_down_height_max_m set (not the authors'; issue 27), the trigger counts only while
// the swing foot is at most that high above the ground (the caller's estimate, from the
// joint encoders' kinematics): a foot reversing fast in the air turns its ankle as fast as
// one striking the ground, and a swing declared over 5 cm up drops the robot onto a foot
// still moving (the push map's falls).
//
// Ticks and rounding: update() is called once per control tick. The first call is the
// machine's first tick, at time 0 (its dt_s is not added); each later call advances the
// clock by dt_s. A phase starts at time 0 on its first tick and holds every tick whose
// time in the phase is below T − 1e-9 s; the tick that reaches T (to 1e-9 s) is the first
// of the next phase. So at a constant tick dt a phase of duration T lasts
// ⌈(T − 1e-9 s) / dt⌉ ticks, at least one (1 kHz: 2000, 2000, then 10, 30, 330, 10 per
// step; 0.0105 s lasts 11 ticks); the time left over at a phase's end is dropped, so
// every phase starts at exactly t = 0 (α = 0). At most one phase change per tick.
//
// Allocation-free: update() only writes into the PhaseInfo the machine holds.
#include <array>
#include <limits>

namespace dmbd::wholebody {

enum class Side { Left = 0, Right = 1 };
Side other(Side s);
const char* to_string(Side s);  // "L", "R"

// WeightShift last: the others keep the numbers they had before it was added.
enum class Phase { JointMove, BodyLift, DoubleSupport, Lift, Swing, Landing, WeightShift };
const char* to_string(Phase p);  // "joint move", "body lift", "double support", ..., "weight shift"

// What the whole-body QP is given for one foot contact.
struct ContactValues {
  double max_normal_force_N = 0.0;
  double tangential_force_weight = 0.0;
  double normal_force_weight = 0.0;
  double slack_weight = 0.0;  // on the contact-acceleration slack
};

// (1 − α) a + α b, each value.
ContactValues blend(const ContactValues& a, const ContactValues& b, double alpha);

// α = ½(1 − cos πt/T), t clamped to [0, T]: 0 at t = 0, ½ at T/2, 1 at T.
double contact_blend(double t_s, double duration_s);

struct PhaseMachineParams {
  double joint_move_s = 2.0;
  double body_lift_s = 2.0;
  double body_lift_start_force_N = 5.0;  // F_max of both feet at the body lift's start
  double body_lift_end_force_N = 300.0;  // ... and at its end (linear ramp)
  double weight_shift_s = 0.0;           // 0: no weight shift
  double double_support_s = 0.01;
  double lift_s = 0.03;
  double swing_s = 0.33;
  double landing_s = 0.01;  // the paper's 0.01 s (the authors' code: 0.03 s)
  // The swing ends early when the swing ankle's joint velocity is below this.
  double touch_down_ankle_velocity_rad_s = -2.8;
  // ... and only while the swing foot is at most this high above the ground (infinite:
  // at any height, the authors' rule).
  double touch_down_height_max_m = std::numeric_limits<double>::infinity();
  Side first_swing_side = Side::Left;
  ContactValues stance{550.0, 1.0, 0.01, 1000.0};
  ContactValues swing{0.0, 5.0, 0.5, 0.001};
  // One step, touch-down to touch-down: double support, lift, swing and landing.
  double step_period_s() const { return double_support_s + lift_s + swing_s + landing_s; }
};

struct FootContact {
  bool in_contact = true;
  ContactValues values;
};

// What happened on this tick (all false on the ticks between).
struct PhaseEvents {
  bool phase_started = false;     // this tick is a phase's first (also the machine's first)
  bool swing_started = false;     // the swing's first tick
  bool mid_swing = false;         // the first swing tick with t ≥ T/2: the TVR replan point
  bool touch_down = false;        // the swing ended: this tick is the landing's first
  bool touch_down_early = false;  // ... on the ankle-velocity trigger, before its time
};

struct PhaseInfo {
  Phase phase = Phase::JointMove;
  // The side that swings in the current step (during the start-up: the one that will
  // swing first).
  Side swing_side = Side::Left;
  double time_in_phase_s = 0.0;
  double phase_duration_s = 0.0;  // nominal (a swing ended early keeps its nominal T)
  double time_s = 0.0;            // since the machine's first tick
  int step = 0;                   // the current step, from 1; 0 during the start-up
  int touch_downs = 0;            // swings ended so far
  double alpha = 0.0;             // ½(1 − cos πt/T) in lift and landing, else 0
  std::array<FootContact, 2> feet{};  // indexed by Side
  PhaseEvents events;
  const char* name = "JS";  // "JS", "BL", "WS", "DS", "LF-L", "SW-L", "LN-L", "LF-R", ...

  const FootContact& foot(Side s) const { return feet[static_cast<int>(s)]; }
};

class PhaseMachine {
 public:
  // Throws InputError for a duration that is not positive, a force below zero, a weight
  // that is not positive, or a value that is not finite.
  explicit PhaseMachine(const PhaseMachineParams& params = PhaseMachineParams());

  // One control tick: advances by dt_s (not on the first call), checks the touch-down
  // trigger with the ankles' joint velocities and the swing foot's height above the
  // ground (0 for a caller that does not know it: the height gate then always passes),
  // and returns the phase of this tick. Throws InputError for a negative or non-finite dt_s.
  const PhaseInfo& update(double dt_s, double left_ankle_velocity_rad_s, double right_ankle_velocity_rad_s,
                          double swing_foot_height_m = 0.0);

  const PhaseInfo& info() const { return info_; }  // the last tick's (before any: the first's)
  const PhaseMachineParams& params() const { return params_; }
  // Back to the state before the first tick.
  void reset();

 private:
  bool touch_down_triggered(double left_ankle_velocity_rad_s, double right_ankle_velocity_rad_s,
                            double swing_foot_height_m) const;
  void next_phase();
  void enter(Phase p);
  void end_swing(bool early);
  double duration_s(Phase p) const;
  void refresh();  // alpha, feet and name from phase, side and time
  void set_feet(const ContactValues& swing_foot, bool swing_foot_in_contact, const ContactValues& stance_foot);

  PhaseMachineParams params_;
  PhaseInfo info_;
  bool started_ = false;
  bool mid_swing_reached_ = false;
};

}  // namespace dmbd::wholebody
