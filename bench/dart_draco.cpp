// DRACO in DART on the standing task (see dart_draco.hpp for what the world holds and why).
#include "dart_draco.hpp"

#include <stdexcept>

#if DMBD_HAVE_DART
#include <dart/collision/CollisionDetector.hpp>
#include <dart/collision/fcl/FCLCollisionDetector.hpp>
#include <dart/config.hpp>
#include <dart/constraint/ConstraintSolver.hpp>
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/BoxShape.hpp>
#include <dart/dynamics/FreeJoint.hpp>
#include <dart/dynamics/Joint.hpp>
#include <dart/dynamics/ShapeNode.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/dynamics/SphereShape.hpp>
#include <dart/dynamics/WeldJoint.hpp>
#include <dart/simulation/World.hpp>
#include <dart/utils/urdf/DartLoader.hpp>
#if DMBD_HAVE_DART_ODE
#include <dart/collision/ode/OdeCollisionDetector.hpp>
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#endif

namespace dmbd::bench {

bool dart_supports(bool elastic, Integrator integrator) { return !elastic && integrator == Integrator::Euler; }

#if DMBD_HAVE_DART

namespace {

using dmbd::model::ActuatorParams;
using dmbd::model::Joint;
using dmbd::model::JointType;
using dmbd::model::RobotDescription;
namespace dd = dart::dynamics;

constexpr double kGroundHalfThicknessM = 0.05;  // the ground box: 10 x 10 x 0.1 m, top face at z = 0

bool one_dof(const Joint& j) {
  return j.type == JointType::Revolute || j.type == JointType::Continuous || j.type == JointType::Prismatic;
}

// The skeleton DartLoader reads from `urdf` (meshes: package://<robot>/ is the URDF's
// folder), parsed once per file: every run clones it.
const dd::SkeletonPtr& parsed_skeleton(const RobotDescription& robot) {
  static std::map<std::string, dd::SkeletonPtr> cache;
  if (robot.source.empty()) throw std::runtime_error("DART: robot '" + robot.name + "' was not read from a URDF file");
  dd::SkeletonPtr& skel = cache[robot.source];
  if (skel) return skel;
  dart::utils::DartLoader::Options options;  // no root joint in the URDF: a FreeJoint (floating base)
  options.mDefaultRootJointType = dart::utils::DartLoader::RootJointType::FLOATING;
  dart::utils::DartLoader loader(options);
  loader.addPackageDirectory(robot.name, std::filesystem::path(robot.source).parent_path().string());
  skel = loader.parseSkeleton(dart::common::Uri::createFromPath(robot.source));
  if (!skel) {
    cache.erase(robot.source);
    throw std::runtime_error("DART's URDF loader could not read '" + robot.source + "'");
  }
  if (!dynamic_cast<dd::FreeJoint*>(skel->getRootJoint()))
    throw std::runtime_error("DART: the root of '" + robot.source + "' is not a free joint");
  return skel;
}

// The robot as the task wants it: collision on the foot spheres only, the task's friction
// on them, joint limits enforced, torso upright at the standing height, joints at 0.
dd::SkeletonPtr make_robot(const RobotDescription& robot, const StandingTask& task) {
  dd::SkeletonPtr skel = parsed_skeleton(robot)->cloneSkeleton();
  skel->disableSelfCollisionCheck();
  for (std::size_t b = 0; b < skel->getNumBodyNodes(); ++b) {
    dd::BodyNode* body = skel->getBodyNode(b);
    for (dd::ShapeNode* s : body->getShapeNodesWith<dd::CollisionAspect>()) {
      if (s->getShape()->getType() != dd::SphereShape::getStaticType()) {
        s->removeCollisionAspect();  // as the MuJoCo model: spheres only
        continue;
      }
      s->getDynamicsAspect()->setFrictionCoeff(task.friction);
      s->getDynamicsAspect()->setRestitutionCoeff(0.0);
    }
  }
  for (const Joint& j : robot.joints) {
    if (!one_dof(j)) continue;
    dd::Joint* dj = skel->getJoint(j.name);
    if (!dj || dj->getNumDofs() != 1) throw std::runtime_error("DART skeleton has no 1-dof joint '" + j.name + "'");
    dj->setLimitEnforcement(j.has_limits);
  }
  skel->setPositions(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(skel->getNumDofs())));
  skel->setVelocities(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(skel->getNumDofs())));
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation().z() = standing_root_height_m(robot);
  skel->getRootJoint()->setPositions(dd::FreeJoint::convertToPositions(X));
  return skel;
}

// A welded box, its top face at z = 0, with the task's friction.
dd::SkeletonPtr make_ground(const StandingTask& task) {
  dd::SkeletonPtr ground = dd::Skeleton::create("ground");
  dd::BodyNode* body = ground->createJointAndBodyNodePair<dd::WeldJoint>().second;
  auto box = std::make_shared<dd::BoxShape>(Eigen::Vector3d(10, 10, 2 * kGroundHalfThicknessM));
  dd::ShapeNode* s = body->createShapeNodeWith<dd::CollisionAspect, dd::DynamicsAspect>(box);
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation().z() = -kGroundHalfThicknessM;
  s->setRelativeTransform(X);
  s->getDynamicsAspect()->setFrictionCoeff(task.friction);
  s->getDynamicsAspect()->setRestitutionCoeff(0.0);
  return ground;
}

double tilt_rad(const dd::BodyNode* torso) {
  return std::acos(std::clamp(torso->getTransform().linear()(2, 2), -1.0, 1.0));
}

bool finite_state(const dd::Skeleton& skel) {
  return skel.getPositions().allFinite() && skel.getVelocities().allFinite();
}

StandingResult run(const RobotDescription& robot, const std::vector<ActuatorParams>* acts, const StandingTask& task,
                   const std::shared_ptr<dart::collision::CollisionDetector>& detector) {
  if (!dart_supports(acts != nullptr, task.integrator))
    throw std::invalid_argument("DART runs the ideal-torque, Euler variant only");
  const dd::SkeletonPtr skel = make_robot(robot, task);
  const auto world = dart::simulation::World::create("draco");
  world->setGravity(Eigen::Vector3d(0, 0, -task.gravity_mps2));
  world->setTimeStep(task.timestep_s);
  world->getConstraintSolver()->setCollisionDetector(detector);  // before the skeletons: they join its group
  world->addSkeleton(make_ground(task));
  world->addSkeleton(skel);

  // The joints the controller reads, in the description's order (as MuJoCo's controls).
  std::vector<std::string> names;
  std::vector<dd::Joint*> joints;
  for (const Joint& j : robot.joints)
    if (one_dof(j)) {
      names.push_back(j.name);
      joints.push_back(skel->getJoint(j.name));
    }
  const dd::BodyNode* torso = skel->getRootBodyNode();
  const int substeps = static_cast<int>(std::lround(task.control_period_s / task.timestep_s));
  const long long ticks = std::llround(task.duration_s / task.control_period_s);
  const double z0 = torso->getTransform().translation().z();
  std::vector<double> q(names.size()), qd(names.size());

  StandingResult r;
  const auto t0 = std::chrono::steady_clock::now();
  for (long long k = 0; k < ticks && !r.diverged; ++k) {
    for (std::size_t i = 0; i < joints.size(); ++i) {
      q[i] = joints[i]->getPosition(0);
      qd[i] = joints[i]->getVelocity(0);
    }
    const std::vector<double> tau = standing_torques(names, q, qd, task);
    for (std::size_t i = 0; i < joints.size(); ++i) joints[i]->setForce(0, tau[i]);
    for (int s = 0; s < substeps; ++s) world->step(false);  // false: the forces are held
    r.steps += substeps;
    r.diverged = !finite_state(*skel);
    if (!r.diverged) r.max_tilt_rad = std::max(r.max_tilt_rad, tilt_rad(torso));
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.sim_s = world->getTime();
  r.rtf = r.sim_s / r.wall_s;
  r.drop_m = z0 - torso->getTransform().translation().z();
  if (!std::isfinite(r.drop_m)) r.diverged = true;
  judge_standing(r, task);
  return r;
}

}  // namespace

bool dart_available() { return true; }
#if DMBD_HAVE_DART_ODE
bool dart_ode_available() { return true; }
#else
bool dart_ode_available() { return false; }
#endif
std::string dart_version() { return DART_VERSION; }

StandingResult run_dart_fcl_standing(const RobotDescription& robot, const std::vector<ActuatorParams>* actuators_or_null,
                                     const StandingTask& task) {
  return run(robot, actuators_or_null, task, dart::collision::FCLCollisionDetector::create());
}

StandingResult run_dart_ode_standing(const RobotDescription& robot, const std::vector<ActuatorParams>* actuators_or_null,
                                     const StandingTask& task) {
#if DMBD_HAVE_DART_ODE
  return run(robot, actuators_or_null, task, dart::collision::OdeCollisionDetector::create());
#else
  (void)robot, (void)actuators_or_null, (void)task;
  throw std::runtime_error(kDartOdeMissing);
#endif
}

#else  // no DART

bool dart_available() { return false; }
bool dart_ode_available() { return false; }
std::string dart_version() { return ""; }

StandingResult run_dart_fcl_standing(const dmbd::model::RobotDescription&, const std::vector<dmbd::model::ActuatorParams>*,
                                     const StandingTask&) {
  throw std::runtime_error(kDartMissing);
}

StandingResult run_dart_ode_standing(const dmbd::model::RobotDescription&, const std::vector<dmbd::model::ActuatorParams>*,
                                     const StandingTask&) {
  throw std::runtime_error(kDartMissing);
}

#endif

}  // namespace dmbd::bench
