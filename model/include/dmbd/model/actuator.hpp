#pragma once
// DRACO's liquid-cooled viscoelastic actuators (VLCA), as data plus the closed-form
// pieces that do not need a multibody engine: the linkage that turns actuator travel
// into joint rotation, and the per-joint parameter table. The Simbody coupling lives in
// model/src/plant*.cpp. Units are SI; N_m is in radians of motor per metre of
// ball-screw travel (see docs/paper-actuators.md, "Units").

#include "dmbd/base/number_parser.hpp"
#include "dmbd/model/sensors.hpp"
#include "dmbd/model/thermal.hpp"

#include <string>
#include <vector>

namespace dmbd::model {

// Actuator between two pivots. Pivot A is fixed in the parent link at distance a_m from
// the joint axis, pivot B in the child link at distance b_m; both lie in the plane
// normal to the joint axis. The angle between the two pivot arms is
// gamma(q) = gamma0_rad + sign * q, and the actuator length (pivot to pivot) is
//   x(q) = sqrt(a^2 + b^2 - 2 a b cos(gamma(q))).
// Its moment arm is r(q) = dx/dq = sign * a b sin(gamma) / x (m/rad) and the joint-side
// ratio of the paper is N_l(q) = dq/dx = 1 / r(q) (rad/m). The joint torque from an
// actuator force F (pushing the pivots apart, N) is tau = F * r(q).
struct LinkageGeometry {
  double a_m = 0.05;
  double b_m = 0.30;
  double gamma0_rad = 0.5;
  double sign = 1.0;  // +1 or -1

  double length_m(double q) const;
  double moment_arm_m(double q) const;       // dx/dq
  double dmoment_arm_dq_m(double q) const;   // d2x/dq2
  double N_l(double q) const;                // dq/dx = 1 / moment_arm
  // The joint angle whose length change x(q) - x(0) is dx, by Newton's method from
  // `guess` (the firmware's lookup from actuator travel to joint angle, done exactly).
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
  RFSEA,  // elastomer between the housing (reaction mass M_r) and the parent link; hips, knees
  FSEA    // elastomer between the ball-screw nut and the output; ankles (no reaction mass)
};

struct ActuatorParams {
  std::string joint;                 // URDF joint it drives, e.g. "l_knee"
  ActuatorKind kind = ActuatorKind::RFSEA;
  double J_m_kgm2 = 1.6e-5;          // rotor inertia (Table I)
  double B_m_Nms = 2.0e-4;           // rotor damping, N m s/rad (Table I)
  double N_m_rad_per_m = 6632;       // motor rad per m of screw travel
  double K_s_N_per_m = 9.5e6;        // elastomer stiffness (K_r in Table I)
  double B_s_Ns_per_m = 1.6e4;       // elastomer damping (B_r)
  double M_r_kg = 1.3;               // reaction mass on the elastomer (RFSEA only)
  double B_l_Ns_per_m = 2.0e4;       // output-side damping along the actuator (Table I B_l)
  double k_tau_Nm_per_A = 0.0448;
  double current_limit_A = 22;
  double force_limit_N = 8000;
  double efficiency = 0.9;           // drive efficiency: the motor torque reaching the screw is efficiency x k_tau i
  LinkageGeometry linkage;
  ThermalParams thermal;
  EncoderParams motor_encoder;       // on the rotor
  EncoderParams spring_encoder;      // on the elastomer deflection (linear, counts per m)
  PotentiometerParams potentiometer; // joint angle

  // Reflected rotor mass J_m N_m^2 (kg) and damping B_m N_m^2 (N s/m), and the motor
  // force per ampere k_tau N_m (N/A).
  double reflected_mass_kg() const { return J_m_kgm2 * N_m_rad_per_m * N_m_rad_per_m; }
  double reflected_damping_Ns_per_m() const { return B_m_Nms * N_m_rad_per_m * N_m_rad_per_m; }
  double force_per_amp_N_per_A() const { return k_tau_Nm_per_A * N_m_rad_per_m; }
};

// Reads the per-joint table (robots/draco/actuators.yaml for DRACO) with the located
// YAML reader (dmbd/base/yaml_reader.hpp). Throws ModelError naming the file, the line
// and column, and what was expected: every problem, one line each. Numbers are read by
// `numbers`: plain numbers unless a caller above model supplies expressions
// (blocks::expression_numbers()).
std::vector<ActuatorParams> load_actuators(const std::string& yaml_path, const NumberParser& numbers = plain_number);

}  // namespace dmbd::model
