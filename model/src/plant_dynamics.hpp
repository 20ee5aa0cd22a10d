#pragma once
// Internal to model/: the plant's equations of motion in generalized coordinates
//   Q = [q (tree), s (one spring deflection per actuator with a spring)],  V = [v (tree), s'],
//   M(Q) V' = f(Q, V, t) - c(Q, V),
// and their stiff parts for the fixed stepper. Terms (docs/model.md, section 6):
//   - the tree (TreeKernel: mass matrix, Coriolis and gravity);
//   - each actuator's rotor, motor, dampers, friction and spring (actuator_terms.hpp);
//     an actuator adds 0 (ROTARY) or 1 (RFSEA, FSEA, ROTARY_SEA) spring coordinate;
//   - each RFSEA housing: a point mass M_r at the donor link's centre of mass, moved
//     by s along the link's z axis (the leg's long axis): exact point-mass terms
//     M_r J_h^T J_h and M_r J_h^T (g - Jdot_h V) with its Jacobian J_h over (tree, s);
//   - URDF joint limits (Hunt-Crossley stops) and joint damping;
//   - ground contact of every collision shape (contact_elements.hpp: spheres, box
//     corners and mesh hull vertices by contact.hpp, cylinder rims by rim_contact.hpp;
//     plant_contacts.cpp) and external point forces; input joint torques.
// assemble(h) writes A = M + h D + h^2 K, r = f - c and kv = K V, where K and D are the
// stiff forces' negative position and velocity derivatives (h = 0: A = M). A's terms
// are added to its lower triangle only (the tree's mass matrix is written whole): the
// solves factor that triangle and read nothing above it, as Eigen's LLT did, so a
// contact's unsymmetric stiffness enters the step through its lower half.
// Nothing here allocates after construction.
#include "contact.hpp"
#include "contact_elements.hpp"
#include "ground_frame.hpp"
#include "rim_contact.hpp"
#include "tree_kernel.hpp"

#include "dmbd/model/plant.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

namespace dmbd::model::detail {

struct HousingMass {
  int actuator = -1;
  int body = -1;                 // donor link's body
  Eigen::Vector3d p_B, u_B;      // point (the donor's CoM) and slide axis in the body frame
  double mass_kg = 0;
};

// The friction anchor of a sphere or a point contact.
struct SphereAnchor {
  bool active = false;
  Eigen::Vector2d anchor = Eigen::Vector2d::Zero();  // on the ground (its tangent coordinates)
};

// A rim's friction: the material point of the body where the deflection is measured
// (re-seated at the centre of pressure after every step) and the ground anchor it is
// tied to; offset = tangent(material point) - anchor, capped at delta_s.
struct RimFriction {
  bool active = false;
  Eigen::Vector3d material_B = Eigen::Vector3d::Zero();
  Eigen::Vector2d anchor = Eigen::Vector2d::Zero();
};

// A rim's contact at the current state: the ring's penetration, its normal force's
// Hunt-Crossley factor at the centre of pressure, and the friction at the material point.
struct RimContact {
  RimPenetration ring;
  double factor = 0;                                     // 1 + d xdot_cop, 0 when separating fast
  double normal_force_N = 0;                             // kappa R load factor
  Eigen::Vector3d material_W = Eigen::Vector3d::Zero();  // where the friction acts
  ContactForce friction;                                 // world; its normal part is zero
  double potential_J = 0;                                // ring and tangential spring
};

struct PointForce {
  int body = -1;
  Eigen::Vector3d p_B = Eigen::Vector3d::Zero();
  Eigen::Vector3d f_W = Eigen::Vector3d::Zero();
};

struct JointStop {
  int joint = -1;                // joint coordinate
  bool limited = false;
  double lower = 0, upper = 0, damping = 0;
  double armature = 0;           // kg m² (kg) on the joint's diagonal of the mass matrix
};

class PlantDynamics {
 public:
  PlantDynamics(const RobotDescription& robot, const PlantOptions& options);

  const TreeKernel& kernel() const { return kernel_; }
  int nq() const { return ntq_ + ns_; }
  int nv() const { return ntv_ + ns_; }
  int tree_nq() const { return ntq_; }
  int tree_nv() const { return ntv_; }
  int num_actuators() const { return na_; }
  int num_springs() const { return ns_; }  // spring coordinates: Q.tail(ns), V.tail(ns), in actuator order
  // Actuator k's spring coordinate in Q and in V, or -1 (ROTARY: no spring).
  int spring_q(int k) const { return spring_[static_cast<std::size_t>(k)] < 0 ? -1 : ntq_ + spring_[static_cast<std::size_t>(k)]; }
  int spring_v(int k) const { return spring_[static_cast<std::size_t>(k)] < 0 ? -1 : ntv_ + spring_[static_cast<std::size_t>(k)]; }
  // Actuator k's spring deflection and rate at the current state (0 without a spring).
  double spring_deflection(int k) const { return spring_q(k) < 0 ? 0.0 : Q_[spring_q(k)]; }
  double spring_rate(int k) const { return spring_v(k) < 0 ? 0.0 : V_[spring_v(k)]; }
  int num_joints() const { return static_cast<int>(kernel_.joint_names().size()); }
  const ActuatorParams& actuator(int k) const { return acts_[static_cast<std::size_t>(k)]; }
  int actuator_joint(int k) const { return act_joint_[static_cast<std::size_t>(k)]; }  // joint coordinate
  int actuator_of_joint(int joint) const { return act_of_joint_[static_cast<std::size_t>(joint)]; }
  int joint_q(int joint) const { return kernel_.joint_q(joint); }
  int joint_v(int joint) const { return kernel_.joint_v(joint); }
  const std::vector<ContactSphere>& spheres() const { return contact_.spheres; }
  const ContactElements& contact_elements() const { return contact_; }
  const GroundFrame& ground() const { return ground_; }
  double total_mass_kg() const { return kernel_.total_mass_kg() + housing_mass_; }

  // The state the terms are evaluated at.
  void set_state(const Eigen::Ref<const Eigen::VectorXd>& Q, const Eigen::Ref<const Eigen::VectorXd>& V);
  const Eigen::VectorXd& Q() const { return Q_; }
  const Eigen::VectorXd& V() const { return V_; }

  // Inputs, held by the caller's choice.
  Eigen::VectorXd currents;                // applied (clamped), per actuator
  Eigen::VectorXd joint_torques;           // per joint coordinate
  std::vector<PointForce> external;        // reserved: no allocation for a few forces
  std::vector<SphereAnchor> anchors;       // per sphere
  std::vector<SphereAnchor> point_anchors; // per point contact
  std::vector<RimFriction> rim_friction;   // per rim

  void assemble(double h);
  const Eigen::MatrixXd& A() const { return A_; }
  const Eigen::VectorXd& r() const { return r_; }
  const Eigen::VectorXd& kv() const { return kv_; }

  // Friction anchors after a step (the return map at the current state); clearing them.
  void update_anchors();
  void reset_anchors();
  // A contact element's force at the current state (anchors unchanged), world; and its
  // contact point.
  SphereContact sphere_contact_now(int sphere, Eigen::Vector3d* p_W = nullptr) const;
  ContactForce point_contact_now(int point, Eigen::Vector3d* p_W = nullptr) const;
  RimContact rim_contact_now(int rim) const;
  // The reading of contact_elements().shapes[shape] (Plant::contacts()).
  ContactReading contact_reading(int shape) const;
  // Placing on the ground: the lowest height of any contact element above the ground,
  // and the sum of the elements' static normal forces with every element lifted by
  // `lift` (m) along the ground normal.
  double lowest_contact_height() const;
  double static_contact_load(double lift_m) const;
  // Point of a body in world at the current state.
  Eigen::Vector3d world_point(int body, const Eigen::Vector3d& p_B) const;

  Eigen::Vector3d housing_moment() const;  // sum of the housings' M_r p_h (kg m)
  double kinetic_energy();                 // 1/2 V^T M V (assembles)
  double potential_energy() const;         // gravity, springs, contact, limits

 private:
  void add_tree();
  void add_joint_terms(double h);
  void add_actuators(double h);
  void add_housings();
  void add_contacts(double h);
  void add_sphere_contacts(double h);
  void add_point_contacts(double h);
  void add_rim_contacts(double h);
  void add_contact_potential(double& e) const;  // e += each element's energy, in order
  // Fills G_'s first columns with the point Jacobian of `body` at p_W; returns its velocity.
  Eigen::Vector3d point_columns(int body, const Eigen::Vector3d& p_W);
  // The same for a point p_W of a rim (centre c, axis a) that moves with the rim's centre
  // and tilt but not with its spin about a: the ring's force does not change when it
  // spins, so its stiffness and damping must not resist rolling.
  Eigen::Vector3d rim_columns(int body, const Eigen::Vector3d& c, const Eigen::Vector3d& a, const Eigen::Vector3d& p_W);
  void add_external();
  // A(idx, idx) += G^T W G, r(idx) += G^T f, kv(idx) += G^T k (G V) for a point term whose
  // Jacobian has the columns `idx` (G is 3 x idx.size()).
  void add_point_term(const std::vector<int>& idx, int cols, const Eigen::Vector3d& f, const Eigen::Matrix3d& W,
                      const Eigen::Matrix3d* K = nullptr, const Eigen::Vector3d* Gv = nullptr);
  void add_point_mass_term(const std::vector<int>& idx, int cols, const Eigen::Vector3d& f, double mass);
  // Point terms of one body gathered at a point o of it, as wrenches [moment about o;
  // force] and a 6 x 6 W6 on the spatial velocity [omega; v_o]: a point term at p (f, W,
  // k) adds B^T f, B^T W B, B^T k with B = [-[p - o]x, I] (v_p = B [omega; v_o]).
  struct BodyTerms {
    int body = -1;
    Eigen::Vector3d o = Eigen::Vector3d::Zero();
    Eigen::Matrix<double, 6, 6> W6 = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> f6 = Eigen::Matrix<double, 6, 1>::Zero(), k6 = Eigen::Matrix<double, 6, 1>::Zero();
    bool any = false;
    void add(const Eigen::Vector3d& p, const Eigen::Vector3d& f, const Eigen::Matrix3d& W, const Eigen::Vector3d& k);
  };
  // A(idx, idx) += J^T W6 J, r(idx) += J^T f6, kv(idx) += J^T k6 with J the body's frame
  // Jacobian at o (6 x its mobilities): the body's point terms projected at once.
  void add_body_terms(const BodyTerms& t);
  // Starts gathering t on `body` (add_body_terms of what t held), unless t is on it.
  void gather_on(BodyTerms& t, int body);

  TreeKernel kernel_;
  PlantOptions opt_;
  std::vector<ActuatorParams> acts_;
  std::vector<int> act_joint_, act_of_joint_;
  std::vector<int> spring_;                // per actuator: its index among the springs, or -1
  std::vector<HousingMass> housings_;
  GroundFrame ground_;
  ContactElements contact_;
  std::vector<double> sphere_hertz_;       // per contact sphere: its Hertz constant (N/m^1.5)
  std::vector<JointStop> stops_;
  double housing_mass_ = 0;
  int ntq_ = 0, ntv_ = 0, na_ = 0, ns_ = 0;
  Eigen::VectorXd Q_, V_;
  bool kernel_set_ = false;                // the kernel holds Q_'s and V_'s tree part
  Eigen::MatrixXd A_;
  Eigen::VectorXd r_, kv_, c_tree_;
  Eigen::Matrix3Xd G_, WG_;                // scratch: compact point Jacobian, W times it
  Eigen::Matrix<double, 6, Eigen::Dynamic> J6_, WJ6_;  // scratch: compact frame Jacobian, W6 times it
  std::vector<int> idx_;                   // scratch: columns of a point term
};

}  // namespace dmbd::model::detail
