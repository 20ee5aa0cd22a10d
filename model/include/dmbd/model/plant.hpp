#pragma once
// The simulated robot: the URDF's multibody tree plus its actuators (DRACO's series-
// elastic VLCAs: rotor, ball screw, elastomer, linkage; geared rotary motors, rigid or
// with a torsion spring), joint limits and damping, and compliant ground contact of every
// collision shape, in generalized coordinates without constraints. Eigen types only; Simbody
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

// Contact of every collision shape of every link with the ground, a plane through the
// origin with unit normal PlantOptions::ground_normal (model/src/contact.hpp,
// rim_contact.hpp; docs/model.md, "Contact"). Spheres: Hunt-Crossley on the Hertz law.
// Boxes (8 corners) and meshes (their convex hull's vertices, at most 64): point
// contacts with a linear Hunt-Crossley law F = k x (1 + d xdot). Cylinders: each rim an
// elastic ring, kappa per unit length, integrated in closed form. Friction at every
// point as a spring-damper to an anchor on the ground, both in proportion to the normal
// force, capped by the Coulomb cone (sticks without creeping, slides beyond mu F_n); a
// rim's anchor follows its material contact point, so rolling feels no friction.
struct ContactParams {
  double stiffness_Pa = 1e7;                  // spheres: plane-strain modulus E of the Hertz law
  double dissipation_s_per_m = 2.0;           // spheres: Hunt-Crossley d, F = F_hertz (1 + 1.5 d xdot)
  double friction = 0.8;                      // Coulomb coefficient mu (every shape)
  double stiction_displacement_m = 1e-3;      // tangential stiffness mu F_n / this
  double stiction_velocity_m_s = 0.01;        // tangential damping mu F_n / this (regularised Coulomb's slope)
  double point_stiffness_N_per_m = 1e5;       // box corners, mesh hull vertices: k (1 mm under 100 N)
  double point_dissipation_s_per_m = 2.0;     // points and rims: Hunt-Crossley d, F = k x (1 + d xdot)
  double rim_stiffness_N_per_m2 = 1e6;        // cylinder rims: kappa, N/m per m of rim
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
  bool contact = true;                     // the ground under every collision shape
  ContactParams contact_params;
  // The ground plane through the origin, its upward normal (normalised; n.z > 0 or the
  // plant refuses it). Gravity stays along -z world: a tilted normal makes a slope.
  Eigen::Vector3d ground_normal = Eigen::Vector3d::UnitZ();
  bool joint_limits = true;                // URDF limits as stiff one-sided stops
  double limit_stiffness_Nm_per_rad = 5e3;
  double limit_dissipation_s_per_rad = 1.0;
  bool joint_damping = true;               // URDF <dynamics damping>
  // URDF <limit effort>: a joint without an actuator takes at most its effort (N m, or N
  // for a prismatic joint) of the ideal torque set_joint_torques gives it (none given or
  // 0: no limit); each clamped value is counted (effort_clamp_events).
  bool effort_limits = true;
  Integration integration = Integration::Accurate;
  double accuracy = 1e-5;                  // Accurate: relative accuracy
  double step_s = 5e-4;                    // Fixed: the largest step
};

// One per colliding collision shape: links in order, shapes in URDF order within a link
// (a mesh whose file did not load is not listed).
struct ContactReading {
  int link = -1;                  // RobotDescription link index
  int shape = -1;                 // index into links[link].collisions
  Geometry::Kind kind = Geometry::Kind::Sphere;
  // Sphere: its lowest point along the ground normal. Other shapes: the centre of
  // pressure of their normal forces (their lowest point while not touching).
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d force_W = Eigen::Vector3d::Zero();  // on the robot, summed over the shape's contacts
  double penetration_m = 0;       // the largest of its contacts (0 while not touching)
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

  // State. reset() puts every joint at 0 (floating: torso orientation from X_WB, placed on
  // the ground as place_on_ground() does), zero velocities, springs unloaded, time 0. The
  // set_* calls keep the springs' deflections and make the rotor angles consistent.
  void reset();
  void set_joint_positions(const Eigen::VectorXd& q);
  void set_joint_velocities(const Eigen::VectorXd& v);
  void set_base_pose(const Eigen::Isometry3d& X_WB);       // floating only
  // Floating base with contact: moves the base along the ground normal so that the static
  // normal forces of the contacts sum to the weight's normal component (the lowest ones
  // sharing it; reset() does this for the zero posture; call it after setting an initial
  // posture). No-op otherwise.
  void place_on_ground();
  void lock_joint(int joint, double q);                    // hold a joint (locked output)
  void unlock_joint(int joint);

  // Inputs (held until changed).
  void set_currents(const Eigen::VectorXd& current_A);     // per actuator, clamped to ActuatorParams::applied_current_limit_A()
  // Per joint, added to an actuator's torque; a joint without an actuator clamped to its
  // URDF effort limit (PlantOptions::effort_limits).
  void set_joint_torques(const Eigen::VectorXd& tau);
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
  // The same readings into storage the caller keeps (sized num_joints(), num_actuators(),
  // or resized once for contacts): nothing allocated, for loops that read them every tick.
  void joint_positions(Eigen::Ref<Eigen::VectorXd> q) const;
  void joint_velocities(Eigen::Ref<Eigen::VectorXd> v) const;
  void actuator_forces(Eigen::Ref<Eigen::VectorXd> f) const;
  void spring_deflections(Eigen::Ref<Eigen::VectorXd> s) const;
  void motor_angles(Eigen::Ref<Eigen::VectorXd> a) const;
  void applied_currents(Eigen::Ref<Eigen::VectorXd> i) const;
  void contacts(std::vector<ContactReading>& out) const;
  Eigen::Vector3d com_position() const;
  double total_mass_kg() const;                            // robot incl. actuator masses
  double kinetic_energy() const;
  double potential_energy() const;                         // gravity + springs + contact
  Eigen::Vector3d imu_angular_velocity_B() const;          // torso, in torso frame
  Eigen::Vector3d imu_specific_force_B() const;            // torso origin, in torso frame
  long long integrator_steps() const;                      // accepted steps since the last reset()
  // Per joint: how many values set_joint_torques clamped to the effort limit since the
  // last reset() (0 for a joint with an actuator or without a limit).
  const std::vector<long long>& effort_clamp_events() const;
  // Per joint: its URDF effort limit as applied (0: none, or the joint has an actuator).
  const std::vector<double>& effort_limits() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dmbd::model
