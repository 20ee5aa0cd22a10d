#pragma once
// Actuators as data plus the closed-form pieces that do not need a multibody engine:
// DRACO's liquid-cooled viscoelastic actuators (VLCA: ball screw on a two-pivot
// linkage, RFSEA and FSEA) and geared rotary motors (ROTARY, rigid, and ROTARY_SEA, with
// a torsion spring), the linkage that turns screw travel into joint rotation, and the
// per-joint parameter table (the actuator file, docs/actuator-format.md). The Simbody
// coupling lives in model/src/plant*.cpp. Units are SI; N_m is in radians of motor per
// metre of ball-screw travel for the VLCAs (see docs/paper-actuators.md, "Units") and
// radians of motor per radian of gear output (the gear ratio) for the rotary kinds.

#include "dmbd/base/number_parser.hpp"
#include "dmbd/model/sensors.hpp"
#include "dmbd/model/thermal.hpp"

#include <limits>
#include <string>
#include <vector>

namespace dmbd::model {

struct RobotDescription;

// Actuator between two pivots. Pivot A is fixed in the parent link at distance a_m from
// the joint axis, pivot B in the child link at distance b_m; both lie in the plane
// normal to the joint axis. The angle between the two pivot arms is
// gamma(q) = gamma0_rad + sign * q, and the actuator length (pivot to pivot) is
//   x(q) = sqrt(a^2 + b^2 - 2 a b cos(gamma(q))).
// Its moment arm is r(q) = dx/dq = sign * a b sin(gamma) / x (m/rad) and the joint-side
// ratio of the paper is N_l(q) = dq/dx = 1 / r(q) (rad/m). The joint torque from an
// actuator force F (pushing the pivots apart, N) is tau = F * r(q).
// The linkage at one joint angle: its length x (m), moment arm dx/dq (m/rad) and
// d2x/dq2 (m/rad^2).
struct LinkagePoint {
  double length_m = 0;
  double moment_arm_m = 0;
  double dmoment_arm_dq_m = 0;
};

struct LinkageGeometry {
  double a_m = 0.05;
  double b_m = 0.30;
  double gamma0_rad = 0.5;
  double sign = 1.0;  // +1 or -1

  double length_m(double q) const;
  double moment_arm_m(double q) const;       // dx/dq
  double dmoment_arm_dq_m(double q) const;   // d2x/dq2
  double N_l(double q) const;                // dq/dx = 1 / moment_arm
  LinkagePoint at(double q) const;           // the three above at once
  // The joint angle whose length change x(q) - x(0) is dx, in closed form on the branch
  // of gamma nearest `guess` (the firmware's lookup from actuator travel to joint
  // angle, done exactly).
  double angle_for_length_change(double dx, double guess) const;
};

// The robot's lookup table: N_l sampled on a uniform grid over the joint range,
// interpolated by a natural cubic spline (what the firmware stores).
class LinkageTable {
 public:
  LinkageTable() = default;
  LinkageTable(const LinkageGeometry& g, double q_lo, double q_hi, int samples);
  double N_l(double q) const;  // clamped to the table's range
  double q_lo() const { return q_lo_; }
  double q_hi() const { return q_hi_; }
  const std::vector<double>& values() const { return n_; }

 private:
  double q_lo_ = 0, q_hi_ = 0, h_ = 1;
  std::vector<double> n_, m_;  // samples and spline second derivatives
};

enum class ActuatorKind {
  RFSEA,      // VLCA, elastomer between the housing (reaction mass M_r) and the parent link; hips, knees
  FSEA,       // VLCA, elastomer between the ball-screw nut and the output; ankles (no reaction mass)
  ROTARY,     // geared rotary motor on the joint, rigid: no spring, no extra coordinate
  ROTARY_SEA  // geared rotary motor with a torsion spring (and damper) between the gear output and the joint
};

// One actuated joint. The TRANSMISSION maps the joint angle q to the motor side's
// travel: a VLCA's linkage (travel x(q) - x(0) in m, moment arm r(q) = dx/dq in m/rad)
// or a gear (travel q in rad, r = 1). The motor angle is theta_m = N_m (travel(q) + s),
// s the spring deflection (0 for ROTARY). Callers use the uniform methods below, not
// `linkage`. For the rotary kinds a "force" along the travel is a torque (N m) and a
// spring deflection an angle (rad): the fields keep their names and change unit, as
// each comment says. Defaults: DRACO's knee (Table I), except where a comment says.
struct ActuatorParams {
  std::string joint;                 // URDF joint it drives, e.g. "l_knee"
  ActuatorKind kind = ActuatorKind::RFSEA;
  std::string where;                 // "file:line:column" of its entry in the actuator file ("" when built in code)

  // ---- motor and transmission, every kind
  double J_m_kgm2 = 1.6e-5;          // rotor inertia, kg m^2 (Table I)
  double B_m_Nms = 2.0e-4;           // rotor damping at the rotor, N m s/rad (Table I; rotary kinds: optional, 0)
  double N_m_rad_per_m = 6632;       // VLCA: motor rad per m of screw travel; rotary: the gear ratio N, motor rad per rad of gear output
  double k_tau_Nm_per_A = 0.0448;    // motor torque constant
  double current_limit_A = 22;       // the drive's current limit
  double efficiency = 0.9;           // drive efficiency: the motor torque reaching the screw or gear output is efficiency x k_tau i

  // ---- spring (RFSEA, FSEA: the elastomer along the screw; ROTARY_SEA: the torsion spring; unused for ROTARY)
  double K_s_N_per_m = 9.5e6;        // stiffness: N/m (K_r in Table I); N m/rad for ROTARY_SEA
  double B_s_Ns_per_m = 1.6e4;       // damping: N s/m (B_r); N m s/rad for ROTARY_SEA
  double M_r_kg = 1.3;               // reaction mass on the elastomer (RFSEA only), kg

  // ---- limits
  double force_limit_N = 8000;       // VLCA: screw force rating, N (data for controllers; the plant does not clamp it)
  double torque_limit_Nm = std::numeric_limits<double>::infinity();  // rotary: output torque limit, N m (the plant clamps the current to it)

  // ---- gear friction, rotary kinds only, at the gear's OUTPUT (the joint for ROTARY, the
  // spring's gear side for ROTARY_SEA): what back-driving the unpowered joint measures.
  double viscous_friction_Nms = 0;       // N m s/rad
  double coulomb_friction_Nm = 0;        // N m
  double coulomb_velocity_rad_s = 1e-3;  // w_s: Coulomb is the slope tau_c / w_s below w_s (docs/actuator-format.md)

  // ---- output-side load terms (the file's `load:` map): properties of what the actuator
  // drives, which differ between a test stand and the robot.
  double B_l_Ns_per_m = 2.0e4;       // output damping: N s/m along the actuator (VLCA, Table I B_l); N m s/rad at the joint (rotary)
  // Other load terms for the same actuator, by name (the file's `load_sets:`; e.g. the
  // robot's where `load:` holds the test stand's): select_load_set() puts one in place.
  struct LoadSet {
    std::string name;
    double B_l_Ns_per_m = 0;
    std::string where;               // "file:line:column" of the set's entry
  };
  std::vector<LoadSet> load_sets;

  LinkageGeometry linkage;           // RFSEA, FSEA only (use moment_arm() etc., not this)
  ThermalParams thermal;
  EncoderParams motor_encoder;       // on the rotor, counts per motor rad
  EncoderParams spring_encoder;      // on the spring deflection: counts per m (VLCA), per rad (ROTARY_SEA); unused for ROTARY
  PotentiometerParams potentiometer; // joint angle
  bool has_potentiometer = true;     // false: none fitted (the rotary kinds may omit it)

  // ---- the transmission, uniform over the kinds
  double moment_arm(double q) const;       // r(q): linkage dx/dq (m/rad), or 1
  double dmoment_arm_dq(double q) const;   // r'(q): linkage d2x/dq2 (m/rad^2), or 0
  double N_l(double q) const;              // 1 / moment_arm(q): rad/m, or 1
  double travel(double q) const;           // x(q) - x(0) (m), or q (rad)
  // moment_arm and dmoment_arm_dq at once (length_m: the linkage's length; a gear's q).
  LinkagePoint transmission(double q) const;
  // The joint angle whose travel is dx (the inverse of travel(); for a linkage on the
  // branch nearest `guess`).
  double angle_for_travel(double dx, double guess) const;
  bool has_spring() const { return kind != ActuatorKind::ROTARY; }  // RFSEA, FSEA, ROTARY_SEA
  bool is_rotary() const { return kind == ActuatorKind::ROTARY || kind == ActuatorKind::ROTARY_SEA; }

  // Reflected rotor J_m N_m^2 (VLCA: kg along the screw; rotary: kg m^2 at the gear
  // output), rotor damping B_m N_m^2 (N s/m; N m s/rad) and the motor force per ampere
  // k_tau N_m (N/A; N m/A), efficiency not included.
  double reflected_mass_kg() const { return J_m_kgm2 * N_m_rad_per_m * N_m_rad_per_m; }
  double reflected_damping_Ns_per_m() const { return B_m_Nms * N_m_rad_per_m * N_m_rad_per_m; }
  double force_per_amp_N_per_A() const { return k_tau_Nm_per_A * N_m_rad_per_m; }
  // The current the plant applies at most: current_limit_A (VLCA), and for the rotary
  // kinds min(current_limit_A, torque_limit_Nm / (efficiency k_tau N)), so that the output
  // torque efficiency k_tau N i stays within +-torque_limit_Nm.
  double applied_current_limit_A() const;
  // The force rating along the travel: force_limit_N (N) or torque_limit_Nm (N m).
  double force_limit() const { return is_rotary() ? torque_limit_Nm : force_limit_N; }
};

// The kind as the actuator file writes it: "rfsea", "fsea", "rotary", "rotary_sea".
const char* kind_name(ActuatorKind kind);

// Reads an actuator file (format: docs/actuator-format.md; DRACO's is
// robots/draco/actuators.yaml) with the located YAML reader (dmbd/base/yaml_reader.hpp).
// Throws ModelError naming the file, the line and column, and what was expected: every
// problem, one line each. Numbers are read by `numbers`: plain numbers unless a caller
// above model supplies expressions (blocks::expression_numbers()).
std::vector<ActuatorParams> load_actuators(const std::string& yaml_path, const NumberParser& numbers = plain_number);

// Puts each entry's load set `name` (its `load_sets:`) in place of its `load:` terms.
// Throws ModelError (one line, at the first such entry's `where`, naming every entry
// without it and the sets the table has) when an entry has no set of that name: a set
// chosen for a robot applies to every actuator of the table, or the choice is a mistake.
void select_load_set(std::vector<ActuatorParams>& table, const std::string& name);

// The parameters scale_parameter() accepts, by symbol (docs/actuator-format.md,
// "Scaling"): J_m, B_m, K_s, B_s, M_r, B_l, k_tau, viscous_friction, coulomb_friction.
const std::vector<std::string>& scalable_parameters();
// Multiplies parameter `symbol` of every entry by `factor` (a sweep or a robustness
// study: "every joint's B_l at s times its own value"). Throws ModelError for an unknown
// symbol, a negative or non-finite factor, or 0 for a parameter that must stay positive
// (J_m, K_s, k_tau).
void scale_parameter(std::vector<ActuatorParams>& table, const std::string& symbol, double factor);

// The table against the robot it is for: throws ModelError, one line per problem at
// the entry's `where`, for a joint the robot does not have and for a joint that cannot
// carry an actuator (fixed, or not revolute/continuous: every kind's travel is a
// function of a joint angle).
void check_actuators_against(const std::vector<ActuatorParams>& table, const RobotDescription& robot);

// The robot's moving 1-dof joints (revolute, continuous, prismatic) without an entry in
// the table, in the description's order: the plant drives them by ideal joint torques.
std::vector<std::string> joints_without_actuator(const std::vector<ActuatorParams>& table, const RobotDescription& robot);

}  // namespace dmbd::model
