#pragma once
// The simulated robot: the URDF's multibody tree plus its actuators (DRACO's series-
// elastic VLCAs: rotor, ball screw, elastomer, linkage; geared rotary motors, rigid or
// with a torsion spring), joint limits and damping, and compliant foot contact, in generalized coordinates without constraints. Eigen types only; Simbody
// stays in model/src/ (it realises the tree's kinematics).
//
// Inputs are held constant between calls to advance_to() (zero-order hold, as a
// sampled controller drives it): motor currents for actuated joints, joint torques for
// joints without an actuator (or every joint when actuators are off).
//
// An actuator with a spring adds one coordinate, its spring deflection s: for an RFSEA
// the elastomer compression x_r under the housing (the reaction mass M_r, a point mass
// on the parent link's axis), for an FSEA the nut-to-output deflection, for a ROTARY_SEA
// the torsion spring's twist (rad). A ROTARY adds none. The rigid transmission makes the
// rotor angle theta_m = N_m (travel(q) + s), travel(q) = x(q) - x(0) the change of the
// linkage length or q itself for a gear, so the rotor's inertia J_m N_m^2 enters the mass
// matrix analytically (model/src/actuator_terms.hpp, docs/model.md section 6).
//
// Two integrators share these equations: Accurate (error-controlled Dormand-Prince 5(4),
// for identification and frequency responses) and Fixed (a semi-implicit step in which
// the stiff terms -- springs and dampers, joint, output and gear damping, the gear's
// Coulomb friction inside its regularisation, limits, contact normal and sticking
// friction -- enter the linear solve
// (M + h D + h^2 K) dv = h (f - c) - h^2 K v; no allocation per step).

#include "dmbd/model/actuator.hpp"
#include "dmbd/model/dynamics.hpp"
#include "dmbd/model/robot_description.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <memory>
#include <string>
#include <vector>

namespace dmbd::model {

// Sphere/ground contact on every collision sphere of the robot (model/src/contact.hpp):
// Hunt-Crossley normal force on the Hertz law; friction as a spring-damper to an anchor
// on the ground, both in proportion to the normal force, capped by the Coulomb cone
// (sticks without creeping, slides beyond mu F_n).
struct ContactParams {
  double stiffness_Pa = 1e7;                  // plane-strain modulus E of the Hertz law
  double dissipation_s_per_m = 2.0;           // Hunt-Crossley d: F = F_hertz (1 + 1.5 d xdot)
  double friction = 0.8;                      // Coulomb coefficient mu
  double stiction_displacement_m = 1e-3;      // tangential stiffness mu F_n / this
  double stiction_velocity_m_s = 0.01;        // tangential damping mu F_n / this (regularised Coulomb's slope)
};

enum class Integration {
  Accurate,  // error-controlled (Dormand-Prince 5(4)), relative accuracy `accuracy`
  Fixed      // semi-implicit fixed step `step_s` (steps shortened to land on each advance_to time)
};

struct PlantOptions {
  BaseMode base = BaseMode::Floating;
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();  // root pose when fixed
  double gravity_m_s2 = 9.81;
  std::vector<ActuatorParams> actuators;   // one per actuated joint (check_actuators_against); the others: ideal torques
  bool contact = true;                     // ground z = 0 under the collision spheres
  ContactParams contact_params;
  bool joint_limits = true;                // URDF limits as stiff one-sided stops
  double limit_stiffness_Nm_per_rad = 5e3;
  double limit_dissipation_s_per_rad = 1.0;
  bool joint_damping = true;               // URDF <dynamics damping>
  Integration integration = Integration::Accurate;
  double accuracy = 1e-5;                  // Accurate: relative accuracy
  double step_s = 5e-4;                    // Fixed: the largest step
};

struct ContactReading {
  int link = -1;                  // RobotDescription link index
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();  // sphere bottom point in world
  Eigen::Vector3d force_W = Eigen::Vector3d::Zero();  // on the robot
  double penetration_m = 0;
};

class Plant {
 public:
  Plant(const RobotDescription& robot, const PlantOptions& options = {});
  ~Plant();
  Plant(const Plant&) = delete;
  Plant& operator=(const Plant&) = delete;

  const RobotDescription& description() const;
  const PlantOptions& options() const;
  int num_joints() const;                                  // 1-dof joint coordinates
  const std::vector<std::string>& joint_names() const;
  int joint_index(const std::string& name) const;           // or -1
  // Actuator k drives joint actuated_joint(k); -1 for a joint without actuator.
  int num_actuators() const;
  int actuator_of_joint(int joint) const;
  const ActuatorParams& actuator(int k) const;

  // State. reset() puts every joint at 0 (floating: torso orientation from X_WB, its
  // height such that the lowest collision spheres sink by the static deflection of their
  // share of the weight), zero velocities, springs unloaded, time 0. The set_* calls
  // keep the springs' deflections and make the rotor angles consistent.
  void reset();
  void set_joint_positions(const Eigen::VectorXd& q);
  void set_joint_velocities(const Eigen::VectorXd& v);
  void set_base_pose(const Eigen::Isometry3d& X_WB);       // floating only
  // Floating base with contact: moves the base vertically so that the lowest collision
  // spheres sink by the static deflection of their share of the weight (reset() does this
  // for the zero posture; call it after setting an initial posture). No-op otherwise.
  void place_on_ground();
  void lock_joint(int joint, double q);                    // hold a joint (locked output)
  void unlock_joint(int joint);

  // Inputs (held until changed).
  void set_currents(const Eigen::VectorXd& current_A);     // per actuator, clamped to ActuatorParams::applied_current_limit_A()
  void set_joint_torques(const Eigen::VectorXd& tau);      // per joint, added to actuator torque
  void set_external_force(int link, const Eigen::Vector3d& p_L, const Eigen::Vector3d& f_W);
  void clear_external_forces();

  // Integrates to time t (s). Throws ModelError when the integrator fails or the state
  // becomes non-finite ("simulation diverged at t = ..."). In Fixed mode a call
  // allocates nothing.
  void advance_to(double t);
  double time() const;

  // Readings.
  Eigen::VectorXd joint_positions() const;
  Eigen::VectorXd joint_velocities() const;
  Eigen::Isometry3d base_pose() const;
  Eigen::Matrix<double, 6, 1> base_velocity() const;       // [omega_W; v_W]
  // Per actuator. "Force" is along the travel: N for a VLCA, N m for the rotary kinds.
  // Spring kinds: the sensed spring force K_s s. ROTARY: the drive's torque estimate from
  // the applied current, efficiency k_tau N i (N m; friction and the rotor's inertia not
  // subtracted).
  Eigen::VectorXd actuator_forces() const;
  Eigen::VectorXd spring_deflections() const;              // s: x_r (RFSEA), theta/N_m - dx (FSEA), m; twist (ROTARY_SEA), rad; 0 (ROTARY)
  Eigen::VectorXd motor_angles() const;                    // N_m (travel(q) + s), rad
  Eigen::VectorXd motor_velocities() const;                // rad/s
  Eigen::VectorXd applied_currents() const;                // after clamping, A
  // The joint torque a controller estimates from the sensed force: actuator_forces() x
  // moment_arm(q) (exact in statics; in motion the screw force also accelerates the
  // reaction mass).
  Eigen::VectorXd joint_torque_estimates() const;          // N m, per joint (0 where no actuator)
  std::vector<Eigen::Isometry3d> link_poses() const;       // X_WL per description link
  std::vector<ContactReading> contacts() const;
  Eigen::Vector3d com_position() const;
  double total_mass_kg() const;                            // robot incl. actuator masses
  double kinetic_energy() const;
  double potential_energy() const;                         // gravity + springs + contact
  Eigen::Vector3d imu_angular_velocity_B() const;          // torso, in torso frame
  Eigen::Vector3d imu_specific_force_B() const;            // torso origin, in torso frame
  long long integrator_steps() const;                      // accepted steps since the last reset()

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dmbd::model
