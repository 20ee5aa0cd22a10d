// Plant: the robot in Simbody with DRACO's series-elastic actuators and foot contact.
//
// Actuator realisation (docs/model.md, "Simbody coupling"): each RFSEA adds a slider
// body (the housing, reaction mass M_r) on the elastomer (MobilityLinearSpring K_s and
// MobilityLinearDamper B_s) and a pin body (the rotor, J_m, damper B_m) on the housing;
// a CoordinateCoupler keeps the rigid ball screw theta_m / N_m = dx(q) + x_r, so the
// reflected rotor inertia J_m N_m^2 appears in the joint's dynamics through the
// constraint exactly, posture-dependent through the linkage's moment arm. An FSEA adds
// only the rotor (pin on the parent link); its elastomer is a force between the nut
// position theta_m / N_m and the linkage length change dx(q). The housing's mass is
// taken from an ancestor link so the robot's total mass stays the URDF's.
#include "dmbd/model/plant.hpp"

#include "dmbd/model/error.hpp"
#include "simbody_tree.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dmbd::model {

using detail::to_eigen;
using detail::to_simtk;

namespace {

// theta / N_m - (x(q) - x0) - x_r = 0 over (q, x_r, theta): the rigid ball screw of an
// RFSEA. Scaled to metres so the constraint tolerance is a length.
class ScrewCoupling : public SimTK::Function {
 public:
  ScrewCoupling(const LinkageGeometry& g, double N_m) : g_(g), inv_n_(1.0 / N_m), x0_(g.length_m(0.0)) {}
  SimTK::Real calcValue(const SimTK::Vector& x) const override {
    return x[2] * inv_n_ - (g_.length_m(x[0]) - x0_) - x[1];
  }
  SimTK::Real calcDerivative(const SimTK::Array_<int>& c, const SimTK::Vector& x) const override {
    if (c.size() == 1) {
      if (c[0] == 0) return -g_.moment_arm_m(x[0]);
      if (c[0] == 1) return -1.0;
      return inv_n_;
    }
    if (c.size() == 2 && c[0] == 0 && c[1] == 0) return -g_.dmoment_arm_dq_m(x[0]);
    return 0.0;
  }
  int getArgumentSize() const override { return 3; }
  int getMaxDerivativeOrder() const override { return 2; }

 private:
  LinkageGeometry g_;
  double inv_n_, x0_;
};

// The rotor's mass (kg): part of the reaction mass of an RFSEA, taken from the parent
// link for an FSEA. Its value only matters for gravity and the transverse inertia.
constexpr double kRotorMass = 0.2;

struct ActuatorBodies {
  ActuatorParams p;
  int coord = -1;                     // joint coordinate it drives
  SimTK::MobilizedBodyIndex joint, housing, rotor;
  double x0 = 0;                      // linkage length at q = 0
};

// Output-side damping B_l along the actuator (joint torque -B_l r^2 qdot) and the FSEA
// elastomer between the nut and the output.
class ActuatorForces : public SimTK::Force::Custom::Implementation {
 public:
  ActuatorForces(const SimTK::SimbodyMatterSubsystem& m, const std::vector<ActuatorBodies>* a) : matter_(m), acts_(a) {}
  void calcForce(const SimTK::State& s, SimTK::Vector_<SimTK::SpatialVec>&, SimTK::Vector_<SimTK::Vec3>&,
                 SimTK::Vector& mobility) const override {
    for (const ActuatorBodies& a : *acts_) {
      const SimTK::MobilizedBody& jb = matter_.getMobilizedBody(a.joint);
      const double q = jb.getOneQ(s, 0), qd = jb.getOneU(s, 0);
      const double r = a.p.linkage.moment_arm_m(q);
      double tau = -a.p.B_l_Ns_per_m * r * r * qd;
      if (a.p.kind == ActuatorKind::FSEA) {
        const SimTK::MobilizedBody& rb = matter_.getMobilizedBody(a.rotor);
        const double n = a.p.N_m_rad_per_m;
        const double d = rb.getOneQ(s, 0) / n - (a.p.linkage.length_m(q) - a.x0);
        const double dd = rb.getOneU(s, 0) / n - r * qd;
        const double f = a.p.K_s_N_per_m * d + a.p.B_s_Ns_per_m * dd;
        tau += f * r;
        rb.applyOneMobilityForce(s, 0, -f / n, mobility);
      }
      jb.applyOneMobilityForce(s, 0, tau, mobility);
    }
  }
  SimTK::Real calcPotentialEnergy(const SimTK::State& s) const override {
    double e = 0;
    for (const ActuatorBodies& a : *acts_) {
      if (a.p.kind != ActuatorKind::FSEA) continue;
      const double q = matter_.getMobilizedBody(a.joint).getOneQ(s, 0);
      const double d = matter_.getMobilizedBody(a.rotor).getOneQ(s, 0) / a.p.N_m_rad_per_m -
                       (a.p.linkage.length_m(q) - a.x0);
      e += 0.5 * a.p.K_s_N_per_m * d * d;
    }
    return e;
  }
  bool dependsOnlyOnPositions() const override { return false; }

 private:
  const SimTK::SimbodyMatterSubsystem& matter_;
  const std::vector<ActuatorBodies>* acts_;
};

// Hertz sinkage of a sphere carrying `force_N` under SmoothSphereHalfSpaceForce's law
// F = 4/3 k sqrt(R k) x^1.5, k = E^(2/3) / 2 (its documentation).
double hertz_sinkage(double force_N, double radius_m, double E) {
  const double k = 0.5 * std::pow(E, 2.0 / 3.0);
  const double c = 4.0 / 3.0 * k * std::sqrt(radius_m * k);
  return std::pow(std::max(force_N, 0.0) / c, 2.0 / 3.0);
}

}  // namespace

struct Plant::Impl {
  RobotDescription robot;
  PlantOptions opt;
  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter{system};
  SimTK::GeneralForceSubsystem forces{system};
  SimTK::Force::Gravity gravity;
  SimTK::Force::DiscreteForces inputs;
  detail::Tree tree;
  std::vector<ActuatorBodies> acts;
  std::vector<int> act_of_coord;
  struct Sphere {
    int link;
    SimTK::Vec3 center_B;
    double radius;
    SimTK::SmoothSphereHalfSpaceForce force;
  };
  std::vector<Sphere> spheres;
  SimTK::State state;               // authoritative while the integrator is not initialised
  std::unique_ptr<SimTK::RungeKuttaMersonIntegrator> integ;
  bool ready = false;               // integ holds the current state
  bool inputs_dirty = false;
  long long steps_total = 0;  // integrator steps over every stepTo (its own count restarts on reinitialize)
  Eigen::VectorXd currents, torques;
  double robot_mass = 0;

  Impl(const RobotDescription& r, const PlantOptions& o) : robot(r), opt(o) {
    gravity = SimTK::Force::Gravity(forces, matter, -SimTK::ZAxis, o.gravity_m_s2);
    inputs = SimTK::Force::DiscreteForces(forces, matter);

    // Actuators: which joint each drives, and the link that gives up the housing's mass.
    std::vector<double> taken(r.links.size(), 0.0);
    std::vector<int> donor;
    for (const ActuatorParams& p : o.actuators) {
      const int j = r.joint_index(p.joint);
      if (j < 0) throw ModelError(r.source + ": actuator for joint '" + p.joint + "', which the robot does not have");
      int l = r.link_index(r.joints[static_cast<std::size_t>(j)].parent);
      const double m = p.kind == ActuatorKind::RFSEA ? p.M_r_kg : kRotorMass;
      if (p.kind == ActuatorKind::RFSEA && p.M_r_kg <= 2 * kRotorMass)
        throw ModelError(r.source + ": actuator of '" + p.joint + "': reaction mass M_r must exceed " + std::to_string(2 * kRotorMass) + " kg");
      // Walk towards the root until a link can give the mass and keep 0.2 kg.
      while (l >= 0 && r.links[static_cast<std::size_t>(l)].mass_kg - taken[static_cast<std::size_t>(l)] - m < 0.2) {
        const int pj = r.parent_joint_of_link(l);
        l = pj < 0 ? -1 : r.link_index(r.joints[static_cast<std::size_t>(pj)].parent);
      }
      if (l < 0) throw ModelError(r.source + ": no link can carry the " + std::to_string(m) + " kg housing of '" + p.joint + "'");
      taken[static_cast<std::size_t>(l)] += m;
      donor.push_back(l);
    }
    tree = detail::build_tree(r, matter, o.base, o.X_WB, taken);
    act_of_coord.assign(tree.coord_body.size(), -1);

    for (std::size_t k = 0; k < o.actuators.size(); ++k) {
      const ActuatorParams& p = o.actuators[k];
      ActuatorBodies a;
      a.p = p;
      for (std::size_t c = 0; c < tree.coord_joint.size(); ++c)
        if (r.joints[static_cast<std::size_t>(tree.coord_joint[c])].name == p.joint) a.coord = static_cast<int>(c);
      if (a.coord < 0) throw ModelError(r.source + ": actuated joint '" + p.joint + "' has no coordinate (fixed or welded)");
      if (act_of_coord[static_cast<std::size_t>(a.coord)] >= 0)
        throw ModelError(r.source + ": two actuators drive joint '" + p.joint + "'");
      act_of_coord[static_cast<std::size_t>(a.coord)] = static_cast<int>(k);
      a.joint = tree.coord_body[static_cast<std::size_t>(a.coord)];
      a.x0 = p.linkage.length_m(0.0);
      const Link& dl = r.links[static_cast<std::size_t>(donor[k])];
      SimTK::MobilizedBody& donor_body = matter.updMobilizedBody(tree.link_body[static_cast<std::size_t>(donor[k])]);
      // The rotor: a disc of inertia J_m about its axis and mass kRotorMass (Simbody
      // ignores the inertia of a massless body), part of M_r for an RFSEA.
      const double J = p.J_m_kgm2;
      const SimTK::Body::Rigid rotor_body(SimTK::MassProperties(kRotorMass, SimTK::Vec3(0), SimTK::Inertia(J / 2, J / 2, J)));
      if (p.kind == ActuatorKind::RFSEA) {
        // Housing on a slider along the donor's z axis (the legs' long axis), at its CoM.
        const SimTK::Transform X_DF(SimTK::Rotation(-SimTK::Pi / 2, SimTK::YAxis), to_simtk(dl.com_m));
        const double mr = p.M_r_kg - kRotorMass;
        const SimTK::Body::Rigid housing_body(SimTK::MassProperties(mr, SimTK::Vec3(0), SimTK::Inertia(1e-4 * mr)));
        SimTK::MobilizedBody::Slider housing(donor_body, X_DF, housing_body, SimTK::Transform());
        SimTK::MobilizedBody::Pin rotor(housing, SimTK::Transform(), rotor_body, SimTK::Transform());
        SimTK::Force::MobilityLinearSpring(forces, housing, SimTK::MobilizerQIndex(0), p.K_s_N_per_m, 0.0);
        SimTK::Force::MobilityLinearDamper(forces, housing, SimTK::MobilizerUIndex(0), p.B_s_Ns_per_m);
        a.housing = housing.getMobilizedBodyIndex();
        a.rotor = rotor.getMobilizedBodyIndex();
        std::vector<SimTK::MobilizedBodyIndex> bodies{a.joint, a.housing, a.rotor};
        std::vector<SimTK::MobilizerQIndex> qs(3, SimTK::MobilizerQIndex(0));
        SimTK::Constraint::CoordinateCoupler(matter, new ScrewCoupling(p.linkage, p.N_m_rad_per_m), bodies, qs);
      } else {
        SimTK::MobilizedBody::Pin rotor(donor_body, SimTK::Transform(to_simtk(dl.com_m)), rotor_body, SimTK::Transform());
        a.rotor = rotor.getMobilizedBodyIndex();
      }
      SimTK::Force::MobilityLinearDamper(forces, matter.getMobilizedBody(a.rotor), SimTK::MobilizerUIndex(0), p.B_m_Nms);
      acts.push_back(a);
    }
    if (!acts.empty()) SimTK::Force::Custom(forces, new ActuatorForces(matter, &acts));

    for (std::size_t c = 0; c < tree.coord_joint.size(); ++c) {
      const Joint& jt = r.joints[static_cast<std::size_t>(tree.coord_joint[c])];
      const SimTK::MobilizedBody& b = matter.getMobilizedBody(tree.coord_body[c]);
      if (o.joint_limits && jt.has_limits && jt.type != JointType::Continuous)
        SimTK::Force::MobilityLinearStop(forces, b, SimTK::MobilizerQIndex(0), o.limit_stiffness_Nm_per_rad,
                                         o.limit_dissipation_s_per_rad, jt.lower, jt.upper);
      if (o.joint_damping && jt.damping > 0)
        SimTK::Force::MobilityLinearDamper(forces, b, SimTK::MobilizerUIndex(0), jt.damping);
    }

    if (o.contact) {
      const SimTK::Transform X_GH(SimTK::Rotation(SimTK::Pi / 2, SimTK::YAxis), SimTK::Vec3(0));  // +x into the ground
      for (std::size_t l = 0; l < r.links.size(); ++l)
        for (const Shape& sh : r.links[l].collisions) {
          if (sh.geometry.kind != Geometry::Kind::Sphere) continue;
          SimTK::SmoothSphereHalfSpaceForce f(forces);
          const ContactParams& cp = o.contact_params;
          f.setParameters(cp.stiffness_Pa, cp.dissipation_s_per_m, cp.static_friction, cp.dynamic_friction,
                          cp.viscous_friction, cp.transition_velocity_m_s,
                          // cf enters the Hertz law as (x^2 + cf)^(3/4) (m^2): Simbody's default
                          // 1e-5 is a 3.2 mm offset, larger than the static sinkage, and made the
                          // feet push without touching and 4x too soft (DRACO toppled). bd = 1e4
                          // makes the tanh switch-on 0.1 mm wide.
                          1e-9, 1e4, 50);
          f.setContactSphereBody(matter.getMobilizedBody(tree.link_body[l]));
          const SimTK::Vec3 c = to_simtk(Eigen::Vector3d(sh.X_LG.translation()));
          f.setContactSphereLocationInBody(c);
          f.setContactSphereRadius(sh.geometry.radius_m);
          f.setContactHalfSpaceBody(matter.Ground());
          f.setContactHalfSpaceFrame(X_GH);
          spheres.push_back({static_cast<int>(l), c, sh.geometry.radius_m, f});
        }
    }

    system.setUseUniformBackground(true);
    state = system.realizeTopology();
    system.realizeModel(state);
    system.realize(state, SimTK::Stage::Position);
    robot_mass = matter.calcSystemMass(state);
    currents = Eigen::VectorXd::Zero(static_cast<int>(acts.size()));
    torques = Eigen::VectorXd::Zero(static_cast<int>(tree.coord_body.size()));
    integ = std::make_unique<SimTK::RungeKuttaMersonIntegrator>(system);
    integ->setAccuracy(o.accuracy);
    integ->setAllowInterpolation(false);
  }

  const SimTK::State& cur() const { return ready ? integ->getState() : state; }
  // A copy to edit; commit() makes it current and restarts the integrator from it.
  SimTK::State edit() const { return cur(); }
  void commit(const SimTK::State& s) {
    state = s;
    ready = false;
  }
  const SimTK::MobilizedBody& coord_body(int c) const {
    if (c < 0 || c >= static_cast<int>(tree.coord_body.size())) throw ModelError("no joint with index " + std::to_string(c));
    return matter.getMobilizedBody(tree.coord_body[static_cast<std::size_t>(c)]);
  }

  // Rotor angles consistent with the joints: theta = N_m (dx(q) + deflection).
  void make_rotors_consistent(SimTK::State& s, const std::vector<double>& deflection,
                              const std::vector<double>& deflection_rate) const {
    system.realize(s, SimTK::Stage::Instance);
    for (std::size_t k = 0; k < acts.size(); ++k) {
      const ActuatorBodies& a = acts[k];
      const SimTK::MobilizedBody& jb = matter.getMobilizedBody(a.joint);
      const double q = jb.getOneQ(s, 0), qd = jb.getOneU(s, 0);
      const double n = a.p.N_m_rad_per_m, r = a.p.linkage.moment_arm_m(q);
      const double dx = a.p.linkage.length_m(q) - a.x0;
      const SimTK::MobilizedBody& rb = matter.getMobilizedBody(a.rotor);
      rb.setOneQ(s, 0, n * (dx + deflection[k]));
      rb.setOneU(s, 0, n * (r * qd + deflection_rate[k]));
      if (a.housing.isValid()) {
        matter.getMobilizedBody(a.housing).setOneQ(s, 0, deflection[k]);
        matter.getMobilizedBody(a.housing).setOneU(s, 0, deflection_rate[k]);
      }
    }
  }
  // Sets every joint's position (or velocity), keeping the springs' deflections.
  void set_joints(const Eigen::VectorXd& x, bool velocity, const char* what) {
    const int n = static_cast<int>(tree.coord_body.size());
    if (x.size() != n)
      throw ModelError(std::string(what) + ": " + std::to_string(x.size()) + " values for " + std::to_string(n) + " joints");
    SimTK::State s = edit();
    std::vector<double> d, dd;
    deflections(s, d, dd);
    for (int c = 0; c < n; ++c) {
      if (velocity) coord_body(c).setOneU(s, 0, x[c]);
      else coord_body(c).setOneQ(s, 0, x[c]);
    }
    make_rotors_consistent(s, d, dd);
    commit(s);
  }
  void deflections(const SimTK::State& s, std::vector<double>& d, std::vector<double>& dd) const {
    d.assign(acts.size(), 0.0);
    dd.assign(acts.size(), 0.0);
    for (std::size_t k = 0; k < acts.size(); ++k) {
      const ActuatorBodies& a = acts[k];
      if (a.housing.isValid()) {
        d[k] = matter.getMobilizedBody(a.housing).getOneQ(s, 0);
        dd[k] = matter.getMobilizedBody(a.housing).getOneU(s, 0);
      } else {
        const SimTK::MobilizedBody& jb = matter.getMobilizedBody(a.joint);
        const double q = jb.getOneQ(s, 0), qd = jb.getOneU(s, 0);
        const SimTK::MobilizedBody& rb = matter.getMobilizedBody(a.rotor);
        d[k] = rb.getOneQ(s, 0) / a.p.N_m_rad_per_m - (a.p.linkage.length_m(q) - a.x0);
        dd[k] = rb.getOneU(s, 0) / a.p.N_m_rad_per_m - a.p.linkage.moment_arm_m(q) * qd;
      }
    }
  }
  SimTK::Vector input_forces;  // reused: inputs change every control step
  void write_inputs(SimTK::State& s) {
    SimTK::Vector& f = input_forces;
    if (f.size() != s.getNU()) f.resize(s.getNU());
    f = 0.0;
    for (std::size_t c = 0; c < tree.coord_body.size(); ++c)
      matter.getMobilizedBody(tree.coord_body[c]).applyOneMobilityForce(s, 0, torques[static_cast<int>(c)], f);
    for (std::size_t k = 0; k < acts.size(); ++k)
      matter.getMobilizedBody(acts[k].rotor)
          .applyOneMobilityForce(s, 0, acts[k].p.efficiency * acts[k].p.k_tau_Nm_per_A * currents[static_cast<int>(k)], f);
    inputs.setAllMobilityForces(s, f);
  }
};

Plant::Plant(const RobotDescription& robot, const PlantOptions& options)
    : impl_(std::make_unique<Impl>(robot, options)) {
  reset();
}
Plant::~Plant() = default;

const RobotDescription& Plant::description() const { return impl_->robot; }
const PlantOptions& Plant::options() const { return impl_->opt; }
int Plant::num_joints() const { return static_cast<int>(impl_->tree.coord_body.size()); }
const std::vector<std::string>& Plant::joint_names() const { return impl_->tree.joint_names; }
int Plant::joint_index(const std::string& name) const {
  const auto& n = impl_->tree.joint_names;
  const auto it = std::find(n.begin(), n.end(), name);
  return it == n.end() ? -1 : static_cast<int>(it - n.begin());
}
int Plant::num_actuators() const { return static_cast<int>(impl_->acts.size()); }
int Plant::actuator_of_joint(int joint) const {
  return joint < 0 || joint >= num_joints() ? -1 : impl_->act_of_coord[static_cast<std::size_t>(joint)];
}
const ActuatorParams& Plant::actuator(int k) const { return impl_->acts.at(static_cast<std::size_t>(k)).p; }

void Plant::reset() {
  Impl& m = *impl_;
  m.steps_total = 0;
  SimTK::State s = m.system.getDefaultState();
  m.system.realize(s, SimTK::Stage::Instance);
  if (m.tree.base_dofs) {
    m.matter.getMobilizedBody(m.tree.root).setQToFitTransform(s, to_simtk(m.opt.X_WB));
    if (!m.spheres.empty()) {
      m.system.realize(s, SimTK::Stage::Position);
      double lowest = std::numeric_limits<double>::infinity();
      for (const auto& sp : m.spheres)
        lowest = std::min(lowest, m.matter.getMobilizedBody(m.tree.link_body[static_cast<std::size_t>(sp.link)])
                                          .findStationLocationInGround(s, sp.center_B)[2] - sp.radius);
      int touching = 0;
      double radius = 0;
      for (const auto& sp : m.spheres)
        if (m.matter.getMobilizedBody(m.tree.link_body[static_cast<std::size_t>(sp.link)])
                    .findStationLocationInGround(s, sp.center_B)[2] - sp.radius < lowest + 1e-9) {
          ++touching;
          radius = sp.radius;
        }
      const double sink = hertz_sinkage(m.robot_mass * m.opt.gravity_m_s2 / touching, radius, m.opt.contact_params.stiffness_Pa);
      SimTK::Transform X = to_simtk(m.opt.X_WB);
      X.updP()[2] += -lowest - sink;
      m.matter.getMobilizedBody(m.tree.root).setQToFitTransform(s, X);
    }
  }
  m.make_rotors_consistent(s, std::vector<double>(m.acts.size(), 0.0), std::vector<double>(m.acts.size(), 0.0));
  s.setTime(0);
  m.write_inputs(s);
  m.commit(s);
}

void Plant::set_joint_positions(const Eigen::VectorXd& q) { impl_->set_joints(q, false, "set_joint_positions"); }
void Plant::set_joint_velocities(const Eigen::VectorXd& v) { impl_->set_joints(v, true, "set_joint_velocities"); }

void Plant::set_base_pose(const Eigen::Isometry3d& X_WB) {
  Impl& m = *impl_;
  if (!m.tree.base_dofs) throw ModelError("set_base_pose: the robot's base is fixed");
  SimTK::State s = m.edit();
  m.matter.getMobilizedBody(m.tree.root).setQToFitTransform(s, to_simtk(X_WB));
  m.commit(s);
}

void Plant::lock_joint(int joint, double q) {
  Impl& m = *impl_;
  Eigen::VectorXd qs = joint_positions();
  qs[joint] = q;
  set_joint_positions(qs);
  Eigen::VectorXd vs = joint_velocities();
  vs[joint] = 0;
  set_joint_velocities(vs);
  SimTK::State s = m.edit();
  m.coord_body(joint).lockAt(s, q, SimTK::Motion::Position);
  m.commit(s);
}

void Plant::unlock_joint(int joint) {
  Impl& m = *impl_;
  SimTK::State s = m.edit();
  m.coord_body(joint).unlock(s);
  m.commit(s);
}

void Plant::set_currents(const Eigen::VectorXd& current_A) {
  Impl& m = *impl_;
  if (current_A.size() != num_actuators()) throw ModelError("set_currents: " + std::to_string(current_A.size()) + " values for " + std::to_string(num_actuators()) + " actuators");
  for (int k = 0; k < num_actuators(); ++k) {
    const double lim = m.acts[static_cast<std::size_t>(k)].p.current_limit_A;
    m.currents[k] = std::clamp(current_A[k], -lim, lim);
  }
  m.inputs_dirty = true;
}

void Plant::set_joint_torques(const Eigen::VectorXd& tau) {
  Impl& m = *impl_;
  if (tau.size() != num_joints()) throw ModelError("set_joint_torques: " + std::to_string(tau.size()) + " values for " + std::to_string(num_joints()) + " joints");
  m.torques = tau;
  m.inputs_dirty = true;
}

void Plant::set_external_force(int link, const Eigen::Vector3d& p_L, const Eigen::Vector3d& f_W) {
  Impl& m = *impl_;
  if (link < 0 || link >= static_cast<int>(m.tree.link_body.size())) throw ModelError("set_external_force: no link " + std::to_string(link));
  SimTK::State& s = m.ready ? m.integ->updAdvancedState() : m.state;
  // The point's moment arm needs the body's pose: the state must be at Position. The
  // spatial force is then held (with this moment) until the next call.
  m.system.realize(s, SimTK::Stage::Position);
  m.inputs.addForceToBodyPoint(s, m.matter.getMobilizedBody(m.tree.link_body[static_cast<std::size_t>(link)]), to_simtk(p_L), to_simtk(f_W));
  if (m.ready) m.integ->reinitialize(SimTK::Stage::Dynamics, false);
}

void Plant::clear_external_forces() {
  Impl& m = *impl_;
  SimTK::State& s = m.ready ? m.integ->updAdvancedState() : m.state;
  m.inputs.clearAllBodyForces(s);
  if (m.ready) m.integ->reinitialize(SimTK::Stage::Dynamics, false);
}

void Plant::advance_to(double t) {
  Impl& m = *impl_;
  if (!m.ready) {
    m.write_inputs(m.state);
    m.integ->initialize(m.state);
    m.ready = true;
    m.inputs_dirty = false;
  } else if (m.inputs_dirty) {
    m.write_inputs(m.integ->updAdvancedState());
    m.integ->reinitialize(SimTK::Stage::Dynamics, false);
    m.inputs_dirty = false;
  }
  if (t <= m.integ->getTime()) return;
  try {
    while (m.integ->getTime() < t) {
      const long long before = m.integ->getNumStepsTaken();
      const auto status = m.integ->stepTo(t);
      m.steps_total += m.integ->getNumStepsTaken() - before;
      if (status == SimTK::Integrator::EndOfSimulation || m.integ->isSimulationOver())
        throw ModelError("simulation diverged at t = " + std::to_string(m.integ->getTime()) + " s: " +
                         SimTK::Integrator::getTerminationReasonString(m.integ->getTerminationReason()));
    }
  } catch (const ModelError&) {
    throw;
  } catch (const std::exception& e) {
    throw ModelError("simulation diverged at t = " + std::to_string(m.integ->getTime()) + " s: " + std::string(e.what()));
  }
  const SimTK::Vector& y = m.integ->getState().getY();
  for (int i = 0; i < y.size(); ++i)
    if (!std::isfinite(y[i])) throw ModelError("simulation diverged at t = " + std::to_string(m.integ->getTime()) + " s: non-finite state");
}

double Plant::time() const { return impl_->cur().getTime(); }

Eigen::VectorXd Plant::joint_positions() const {
  Eigen::VectorXd q(num_joints());
  for (int c = 0; c < num_joints(); ++c) q[c] = impl_->coord_body(c).getOneQ(impl_->cur(), 0);
  return q;
}
Eigen::VectorXd Plant::joint_velocities() const {
  Eigen::VectorXd v(num_joints());
  for (int c = 0; c < num_joints(); ++c) v[c] = impl_->coord_body(c).getOneU(impl_->cur(), 0);
  return v;
}
Eigen::Isometry3d Plant::base_pose() const {
  const Impl& m = *impl_;
  m.system.realize(m.cur(), SimTK::Stage::Position);
  return to_eigen(m.matter.getMobilizedBody(m.tree.root).getBodyTransform(m.cur()));
}
Eigen::Matrix<double, 6, 1> Plant::base_velocity() const {
  const Impl& m = *impl_;
  m.system.realize(m.cur(), SimTK::Stage::Velocity);
  const SimTK::SpatialVec v = m.matter.getMobilizedBody(m.tree.root).getBodyVelocity(m.cur());
  Eigen::Matrix<double, 6, 1> out;
  out << to_eigen(v[0]), to_eigen(v[1]);
  return out;
}
Eigen::VectorXd Plant::spring_deflections() const {
  std::vector<double> d, dd;
  impl_->deflections(impl_->cur(), d, dd);
  return Eigen::Map<const Eigen::VectorXd>(d.data(), static_cast<int>(d.size()));
}
Eigen::VectorXd Plant::actuator_forces() const {
  Eigen::VectorXd f = spring_deflections();
  for (int k = 0; k < num_actuators(); ++k) f[k] *= impl_->acts[static_cast<std::size_t>(k)].p.K_s_N_per_m;
  return f;
}
Eigen::VectorXd Plant::motor_angles() const {
  Eigen::VectorXd a(num_actuators());
  for (int k = 0; k < num_actuators(); ++k)
    a[k] = impl_->matter.getMobilizedBody(impl_->acts[static_cast<std::size_t>(k)].rotor).getOneQ(impl_->cur(), 0);
  return a;
}
Eigen::VectorXd Plant::motor_velocities() const {
  Eigen::VectorXd a(num_actuators());
  for (int k = 0; k < num_actuators(); ++k)
    a[k] = impl_->matter.getMobilizedBody(impl_->acts[static_cast<std::size_t>(k)].rotor).getOneU(impl_->cur(), 0);
  return a;
}
Eigen::VectorXd Plant::applied_currents() const { return impl_->currents; }
Eigen::VectorXd Plant::joint_torque_estimates() const {
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(num_joints());
  const Eigen::VectorXd f = actuator_forces();
  for (int k = 0; k < num_actuators(); ++k) {
    const ActuatorBodies& a = impl_->acts[static_cast<std::size_t>(k)];
    const double q = impl_->coord_body(a.coord).getOneQ(impl_->cur(), 0);
    tau[a.coord] = f[k] * a.p.linkage.moment_arm_m(q);
  }
  return tau;
}
std::vector<Eigen::Isometry3d> Plant::link_poses() const {
  const Impl& m = *impl_;
  m.system.realize(m.cur(), SimTK::Stage::Position);
  std::vector<Eigen::Isometry3d> out;
  for (const auto& b : m.tree.link_body) out.push_back(to_eigen(m.matter.getMobilizedBody(b).getBodyTransform(m.cur())));
  return out;
}
std::vector<ContactReading> Plant::contacts() const {
  const Impl& m = *impl_;
  const SimTK::State& s = m.cur();
  m.system.realize(s, SimTK::Stage::Velocity);
  std::vector<ContactReading> out;
  for (const auto& sp : m.spheres) {
    const SimTK::MobilizedBody& b = m.matter.getMobilizedBody(m.tree.link_body[static_cast<std::size_t>(sp.link)]);
    SimTK::Vector_<SimTK::SpatialVec> bf(m.matter.getNumBodies(), SimTK::SpatialVec(SimTK::Vec3(0), SimTK::Vec3(0)));
    SimTK::Vector_<SimTK::Vec3> pf(0);
    SimTK::Vector mf(s.getNU(), 0.0);
    sp.force.calcForceContribution(s, bf, pf, mf);
    ContactReading c;
    c.link = sp.link;
    const SimTK::Vec3 center = b.findStationLocationInGround(s, sp.center_B);
    c.p_W = to_eigen(center - SimTK::Vec3(0, 0, sp.radius));
    c.force_W = to_eigen(bf[b.getMobilizedBodyIndex()][1]);
    c.penetration_m = std::max(0.0, -(center[2] - sp.radius));
    out.push_back(c);
  }
  return out;
}
Eigen::Vector3d Plant::com_position() const {
  const Impl& m = *impl_;
  m.system.realize(m.cur(), SimTK::Stage::Position);
  return to_eigen(m.matter.calcSystemMassCenterLocationInGround(m.cur()));
}
double Plant::total_mass_kg() const { return impl_->robot_mass; }
double Plant::kinetic_energy() const {
  const Impl& m = *impl_;
  m.system.realize(m.cur(), SimTK::Stage::Velocity);
  return m.matter.calcKineticEnergy(m.cur());
}
double Plant::potential_energy() const {
  const Impl& m = *impl_;
  m.system.realize(m.cur(), SimTK::Stage::Dynamics);
  return m.system.calcPotentialEnergy(m.cur());
}
Eigen::Vector3d Plant::imu_angular_velocity_B() const {
  const Impl& m = *impl_;
  m.system.realize(m.cur(), SimTK::Stage::Velocity);
  const SimTK::MobilizedBody& b = m.matter.getMobilizedBody(m.tree.root);
  return to_eigen(~b.getBodyRotation(m.cur()) * b.getBodyAngularVelocity(m.cur()));
}
Eigen::Vector3d Plant::imu_specific_force_B() const {
  const Impl& m = *impl_;
  m.system.realize(m.cur(), SimTK::Stage::Acceleration);
  const SimTK::MobilizedBody& b = m.matter.getMobilizedBody(m.tree.root);
  const SimTK::Vec3 a = b.getBodyOriginAcceleration(m.cur()) + SimTK::Vec3(0, 0, m.opt.gravity_m_s2);
  return to_eigen(~b.getBodyRotation(m.cur()) * a);
}
long long Plant::integrator_steps() const { return impl_->steps_total; }

}  // namespace dmbd::model
