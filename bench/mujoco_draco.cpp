// DRACO in MuJoCo from the project's RobotDescription: MJCF generation (always built) and
// the standing run (with MuJoCo only). What each MJCF element stands for in the URDF and
// the actuator table (robots/draco/actuators.yaml, docs/model.md sections 1-3):
//   body            one per URDF link; pos/quat = the URDF joint origin X_PJ (the child
//                   frame in the parent's); the root (torso) carries a free joint
//   inertial        the link's mass, CoM and full inertia tensor (fullinertia, about the
//                   CoM in link axes, exactly as in the URDF; inertiafromgeom="false")
//   joint           a URDF revolute (continuous) joint as a hinge about its axis, with its
//                   limits (MuJoCo's default soft limit), damping and friction (both 0 here)
//   geom            only the URDF's collision spheres (4 per foot, r = 0.03 m) and a floor
//                   plane; sphere-floor pairs only, sliding friction 0.8 (torsional
//                   and rolling at MuJoCo's defaults, unused with the default condim 3),
//                   MuJoCo's default solref/solimp
//   actuator        ideal: a motor of gear 1 on each joint (control in N m, no limits);
//                   elastic: see ElasticJoint below
#include "mujoco_draco.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>

#if DMBD_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#endif

namespace dmbd::bench {
namespace {

using dmbd::model::ActuatorParams;
using dmbd::model::Geometry;
using dmbd::model::Joint;
using dmbd::model::JointType;
using dmbd::model::Link;
using dmbd::model::RobotDescription;

// Shortest text that reads back as the same double.
std::string num(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::string vec(const Eigen::Vector3d& v) { return num(v.x()) + " " + num(v.y()) + " " + num(v.z()); }

// MJCF pos (and quat, w x y z, when rotated) of a frame in its parent.
std::string frame_attrs(const Eigen::Isometry3d& X) {
  std::string s = "pos=\"" + vec(X.translation()) + "\"";
  if (!X.rotation().isIdentity(0.0)) {
    const Eigen::Quaterniond q(X.rotation());
    s += " quat=\"" + num(q.w()) + " " + num(q.x()) + " " + num(q.y()) + " " + num(q.z()) + "\"";
  }
  return s;
}

// One VLCA as an elastic joint in joint space: the actuator's travel x is mapped to a
// rotor angle x / r0 with the linkage's moment arm r0 = r(0), held constant. This is the
// elastic-joint approximation of the VLCA: constant moment arm, no reaction mass M_r
// (RFSEA) and the elastomer between rotor and output for both kinds. Per actuator:
//   armature         J_m N_m^2 r0^2   reflected rotor inertia (kg m^2 at the joint)
//   rotor damping    B_m N_m^2 r0^2   (N m s/rad)
//   spring           K_s r0^2, B_s r0^2 on the tendon q_rotor - q_joint
//   output damping   B_l r0^2 on the joint itself (plus the URDF's damping)
//   gear             efficiency k_tau N_m r0: N m at the joint per ampere
// r0 < 0 for the mirrored right hip roll and yaw: the squares do not care, and the gear's
// sign matches that of the current the task computes from r(q).
struct ElasticJoint {
  double r0, armature, rotor_damping, spring_stiffness, spring_damping, output_damping, gear;
};

ElasticJoint elastic_joint(const ActuatorParams& p) {
  const double r0 = p.linkage.moment_arm_m(0.0), r2 = r0 * r0;
  return {r0,
          p.reflected_mass_kg() * r2,
          p.reflected_damping_Ns_per_m() * r2,
          p.K_s_N_per_m * r2,
          p.B_s_Ns_per_m * r2,
          p.B_l_Ns_per_m * r2,
          p.efficiency * p.force_per_amp_N_per_A() * r0};
}

// The rotor body: tiny mass, so that its hinge's inertia is the armature.
constexpr double kRotorMassKg = 1e-4, kRotorInertiaKgm2 = 1e-8;

bool one_dof(const Joint& j) {
  return j.type == JointType::Revolute || j.type == JointType::Continuous || j.type == JointType::Prismatic;
}

class MjcfWriter {
 public:
  MjcfWriter(const RobotDescription& robot, const std::vector<ActuatorParams>* acts, const StandingTask& task)
      : robot_(robot), acts_(acts), task_(task) {
    for (const Joint& j : robot.joints) children_[j.parent].push_back(&j);
    if (acts)
      for (const ActuatorParams& a : *acts) {
        const int j = robot.joint_index(a.joint);
        if (j < 0 || !one_dof(robot.joints[static_cast<std::size_t>(j)]))
          throw std::runtime_error("MJCF: actuator '" + a.joint + "' drives no 1-dof joint of the robot");
        actuated_[a.joint] = &a;
      }
  }

  std::string text() {
    header();
    os_ << "  <worldbody>\n";
    floor();
    link(0, nullptr, 2);
    os_ << "  </worldbody>\n";
    if (acts_) tendons();
    actuators();
    os_ << "</mujoco>\n";
    return os_.str();
  }

 private:
  void header() {
    os_ << "<mujoco model=\"" << robot_.name << (acts_ ? "_elastic" : "_ideal") << "\">\n"
        << "  <!-- Generated by bench/mujoco_draco.cpp from " << robot_.source << " -->\n"
        << "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n"
        << "  <option timestep=\"" << num(task_.timestep_s) << "\" integrator=\""
        << (task_.integrator == Integrator::Euler ? "Euler" : "implicit") << "\" gravity=\"0 0 "
        << num(-task_.gravity_mps2) << "\"/>\n";
  }

  std::string friction() const { return "friction=\"" + num(task_.friction) + " 0.005 0.0001\""; }

  // The floor collides with the foot spheres only (contype 1 & conaffinity 1); the spheres
  // have contype 0, so they never collide with one another.
  void floor() {
    os_ << "    <geom name=\"floor\" type=\"plane\" size=\"10 10 0.1\" contype=\"1\" conaffinity=\"0\" "
        << friction() << "/>\n";
  }

  void link(std::size_t l, const Joint* parent_joint, int depth) {
    const Link& L = robot_.links[l];
    const std::string pad(static_cast<std::size_t>(depth) * 2, ' ');
    const Eigen::Isometry3d X = parent_joint ? parent_joint->X_PJ : root_placement();
    os_ << pad << "<body name=\"" << L.name << "\" " << frame_attrs(X) << ">\n";
    if (parent_joint) joint(*parent_joint, pad + "  ");
    else os_ << pad << "  <freejoint name=\"root\"/>\n";
    inertial(L, pad + "  ");
    spheres(L, pad + "  ");
    for (const Joint* c : children_[L.name]) rotor(*c, depth + 1);
    for (const Joint* c : children_[L.name]) link(static_cast<std::size_t>(robot_.link_index(c->child)), c, depth + 1);
    os_ << pad << "</body>\n";
  }

  // Torso upright, the bottom of the lowest foot sphere at z = 0.
  Eigen::Isometry3d root_placement() const {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.translation().z() = standing_root_height_m(robot_);
    return X;
  }

  void joint(const Joint& j, const std::string& pad) {
    if (j.type == JointType::Fixed) return;  // no joint element: welded to the parent
    if (!one_dof(j)) throw std::runtime_error("MJCF: joint '" + j.name + "' is neither fixed nor 1-dof");
    double damping = j.damping;
    if (const auto a = actuated_.find(j.name); a != actuated_.end()) damping += elastic_joint(*a->second).output_damping;
    os_ << pad << "<joint name=\"" << j.name << "\" type=\"" << (j.type == JointType::Prismatic ? "slide" : "hinge")
        << "\" axis=\"" << vec(j.axis) << "\" limited=\"" << (j.has_limits ? "true" : "false") << "\"";
    if (j.has_limits) os_ << " range=\"" << num(j.lower) << " " << num(j.upper) << "\"";
    os_ << " damping=\"" << num(damping) << "\" frictionloss=\"" << num(j.friction) << "\"/>\n";
  }

  void inertial(const Link& L, const std::string& pad) {
    if (L.mass_kg <= 0) return;
    const Eigen::Matrix3d& I = L.inertia_kgm2;
    os_ << pad << "<inertial pos=\"" << vec(L.com_m) << "\" mass=\"" << num(L.mass_kg) << "\" fullinertia=\""
        << num(I(0, 0)) << " " << num(I(1, 1)) << " " << num(I(2, 2)) << " " << num(I(0, 1)) << " "
        << num(I(0, 2)) << " " << num(I(1, 2)) << "\"/>\n";
  }

  void spheres(const Link& L, const std::string& pad) {
    for (const auto& s : L.collisions) {
      if (s.geometry.kind != Geometry::Kind::Sphere)
        throw std::runtime_error("MJCF: link '" + L.name + "' has a collision shape other than a sphere");
      os_ << pad << "<geom name=\"" << s.name << "\" type=\"sphere\" size=\"" << num(s.geometry.radius_m) << "\" "
          << frame_attrs(s.X_LG) << " contype=\"0\" conaffinity=\"1\" " << friction() << "/>\n";
    }
  }

  // The rotor of joint j's actuator: a body on j's parent link at j's frame, hinged about
  // j's axis (so its angle is the motor travel mapped to the joint, x / r0).
  void rotor(const Joint& j, int depth) {
    const auto a = actuated_.find(j.name);
    if (a == actuated_.end()) return;
    const ElasticJoint e = elastic_joint(*a->second);
    const std::string pad(static_cast<std::size_t>(depth) * 2, ' ');
    os_ << pad << "<!-- " << j.name << "'s VLCA: r0 = " << num(e.r0) << " m; armature J_m N_m^2 r0^2, damping B_m N_m^2 r0^2 -->\n"
        << pad << "<body name=\"" << j.name << "_rotor\" " << frame_attrs(j.X_PJ) << ">\n"
        << pad << "  <inertial pos=\"0 0 0\" mass=\"" << num(kRotorMassKg) << "\" diaginertia=\""
        << num(kRotorInertiaKgm2) << " " << num(kRotorInertiaKgm2) << " " << num(kRotorInertiaKgm2) << "\"/>\n"
        << pad << "  <joint name=\"" << j.name << "_rotor\" type=\"hinge\" axis=\"" << vec(j.axis)
        << "\" limited=\"false\" armature=\"" << num(e.armature) << "\" damping=\"" << num(e.rotor_damping) << "\"/>\n"
        << pad << "</body>\n";
  }

  // The elastomer: a fixed tendon of length q_rotor - q_joint, stiffness K_s r0^2 and
  // damping B_s r0^2, rest length 0 (every joint starts at 0).
  void tendons() {
    os_ << "  <tendon>\n";
    for (const ActuatorParams& a : *acts_) {
      const ElasticJoint e = elastic_joint(a);
      os_ << "    <fixed name=\"" << a.joint << "_spring\" stiffness=\"" << num(e.spring_stiffness) << "\" damping=\""
          << num(e.spring_damping) << "\" springlength=\"0\">\n"
          << "      <joint joint=\"" << a.joint << "_rotor\" coef=\"1\"/>\n"
          << "      <joint joint=\"" << a.joint << "\" coef=\"-1\"/>\n"
          << "    </fixed>\n";
    }
    os_ << "  </tendon>\n";
  }

  // Control order: the robot's 1-dof joints (ideal, N m) or the actuator table (elastic,
  // A on the rotor, gear efficiency k_tau N_m r0).
  void actuators() {
    os_ << "  <actuator>\n";
    if (acts_) {
      for (const ActuatorParams& a : *acts_)
        os_ << "    <motor name=\"" << a.joint << "_motor\" joint=\"" << a.joint << "_rotor\" gear=\""
            << num(elastic_joint(a).gear) << "\" ctrllimited=\"false\"/>\n";
    } else {
      for (const Joint& j : robot_.joints)
        if (one_dof(j))
          os_ << "    <motor name=\"" << j.name << "_motor\" joint=\"" << j.name << "\" gear=\"1\" ctrllimited=\"false\"/>\n";
    }
    os_ << "  </actuator>\n";
  }

  const RobotDescription& robot_;
  const std::vector<ActuatorParams>* acts_;
  const StandingTask& task_;
  std::map<std::string, std::vector<const Joint*>> children_;
  std::map<std::string, const ActuatorParams*> actuated_;
  std::ostringstream os_;
};

}  // namespace

std::string draco_mjcf(const RobotDescription& robot, const std::vector<ActuatorParams>* actuators_or_null,
                       const StandingTask& task) {
  return MjcfWriter(robot, actuators_or_null, task).text();
}

#if DMBD_HAVE_MUJOCO

namespace {

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

// The joints the controller reads, in control order.
std::vector<std::string> controlled_joints(const RobotDescription& robot, const std::vector<ActuatorParams>* acts) {
  std::vector<std::string> names;
  if (acts)
    for (const ActuatorParams& a : *acts) names.push_back(a.joint);
  else
    for (const Joint& j : robot.joints)
      if (one_dof(j)) names.push_back(j.name);
  return names;
}

// mj_loadXML reads from a virtual file (MuJoCo 2.2 has no load-from-string).
ModelPtr compile(const std::string& xml) {
  const char* name = "draco.xml";
  auto vfs = std::make_unique<mjVFS>();  // ~2 MB: not on the stack
  mj_defaultVFS(vfs.get());
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size() + 1)) != 0)
    throw std::runtime_error("MuJoCo: cannot make the virtual MJCF file");
  std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), name)], xml.c_str(), xml.size() + 1);
  char err[1000] = "";
  mjModel* m = mj_loadXML(name, vfs.get(), err, sizeof err);
  mj_deleteVFS(vfs.get());
  if (!m) throw std::runtime_error(std::string("MuJoCo could not compile the DRACO MJCF: ") + err);
  return ModelPtr(m);
}

struct Addresses {
  std::vector<int> q, v;  // qpos and qvel addresses of the controlled joints
};

Addresses joint_addresses(const mjModel* m, const std::vector<std::string>& names) {
  Addresses a;
  for (const std::string& n : names) {
    const int j = mj_name2id(m, mjOBJ_JOINT, n.c_str());
    if (j < 0) throw std::runtime_error("MuJoCo model has no joint '" + n + "'");
    a.q.push_back(m->jnt_qposadr[j]);
    a.v.push_back(m->jnt_dofadr[j]);
  }
  return a;
}

void gather(const mjtNum* x, const std::vector<int>& adr, std::vector<double>& out) {
  for (std::size_t i = 0; i < adr.size(); ++i) out[i] = x[adr[i]];
}

// Angle of the body z axis from vertical, from its unit quaternion (w x y z): R_zz.
double tilt_rad(const mjtNum* quat) {
  const double rzz = 1 - 2 * (quat[1] * quat[1] + quat[2] * quat[2]);
  return std::acos(std::clamp(rzz, -1.0, 1.0));
}

// MuJoCo silently resets the state to qpos0 when an acceleration, position or velocity
// blows up, which would look like standing: count those warnings as a divergence.
bool unstable(const mjData* d) {
  return d->warning[mjWARN_BADQACC].number + d->warning[mjWARN_BADQPOS].number +
             d->warning[mjWARN_BADQVEL].number > 0;
}

}  // namespace

bool mujoco_available() { return true; }
std::string mujoco_version() { return mj_versionString(); }

StandingResult run_mujoco_standing(const RobotDescription& robot, const std::vector<ActuatorParams>* actuators_or_null,
                                   const StandingTask& task) {
  const ModelPtr m = compile(draco_mjcf(robot, actuators_or_null, task));
  const DataPtr d(mj_makeData(m.get()));  // qpos = qpos0: the placement written in the MJCF
  const std::vector<std::string> names = controlled_joints(robot, actuators_or_null);
  const Addresses adr = joint_addresses(m.get(), names);
  const int root = m->jnt_qposadr[mj_name2id(m.get(), mjOBJ_JOINT, "root")];
  const int substeps = static_cast<int>(std::lround(task.control_period_s / task.timestep_s));
  const long long ticks = std::llround(task.duration_s / task.control_period_s);
  const double z0 = d->qpos[root + 2];
  std::vector<double> q(names.size()), qd(names.size());

  StandingResult r;
  const auto t0 = std::chrono::steady_clock::now();
  for (long long k = 0; k < ticks && !r.diverged; ++k) {
    gather(d->qpos, adr.q, q);
    gather(d->qvel, adr.v, qd);
    const std::vector<double> u = actuators_or_null ? standing_currents(*actuators_or_null, q, qd, task)
                                                    : standing_torques(names, q, qd, task);
    std::copy(u.begin(), u.end(), d->ctrl);  // held for the whole control period
    for (int s = 0; s < substeps; ++s) mj_step(m.get(), d.get());
    r.steps += substeps;
    r.max_tilt_rad = std::max(r.max_tilt_rad, tilt_rad(d->qpos + root + 3));
    r.diverged = unstable(d.get());
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.sim_s = d->time;
  r.rtf = r.sim_s / r.wall_s;
  r.drop_m = z0 - d->qpos[root + 2];
  judge_standing(r, task);
  return r;
}

#else  // no MuJoCo

bool mujoco_available() { return false; }
std::string mujoco_version() { return ""; }

StandingResult run_mujoco_standing(const RobotDescription&, const std::vector<ActuatorParams>*, const StandingTask&) {
  throw std::runtime_error(kMujocoMissing);
}

#endif

}  // namespace dmbd::bench
