// The balancing controller's per-tick pieces on DRACO's floating-base model (issue 15:
// wbc_tick_us ≤ 200 µs): the model's terms with three frames, the prioritised IK of the
// double-support phase from the two feet's contact null space (hip yaws → torso
// orientation → torso position), and the whole-body QP (28 variables, 12 equalities,
// 32 inequalities). Anchor in the same run: the model's terms alone. And the whole
// controller tick (control::BalanceController::step: state, phase, events, IK, QP, outputs)
// in double support and in the swing, with the motion-capture and the kinematic
// estimators (the latter updates a second model: the estimator's).
// With DART (DMBD_HAVE_DART, bench only): BM_DartModelTerms, DART's equivalents of
// BM_WbcModelTermsOnly's terms on the same URDF (DartLoader, floating base) at the same
// state, for a second anchor.
#include <benchmark/benchmark.h>

#include "draco_options.hpp"

#include "dmbd/model/robot_description.hpp"
#include "dmbd/model/actuator.hpp"
#include "dmbd/control/balance_controller.hpp"
#include "dmbd/control/dynamics_model.hpp"
#include "dmbd/wholebody/prioritized_ik.hpp"
#include "dmbd/wholebody/task.hpp"
#include "dmbd/wholebody/wbc_qp.hpp"

#if DMBD_HAVE_DART
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/FreeJoint.hpp>
#include <dart/dynamics/Joint.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/utils/urdf/DartLoader.hpp>

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#endif

namespace {

using namespace dmbd;

// The three frames of the model's terms: the feet's contact points and the torso.
const wholebody::FrameSpec kLeftFoot{"l_foot", Eigen::Vector3d(0.015, 0, -0.044)};
const wholebody::FrameSpec kRightFoot{"r_foot", Eigen::Vector3d(0.015, 0, -0.044)};
const wholebody::FrameSpec kTorso{"torso", Eigen::Vector3d::Zero()};

struct DoubleSupport {
  model::RobotDescription robot = model::load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf");
  control::DynamicsModel model{robot, model::DynamicsOptions{}};
  int left = model.add_frame(kLeftFoot);
  int right = model.add_frame(kRightFoot);
  int torso = model.add_frame(kTorso);
  wholebody::ModelData data = model.make_data();
  wholebody::PostureTask yaws{model.layout(), {model.layout().joint_index("l_hip_yaw"), model.layout().joint_index("r_hip_yaw")}};
  wholebody::OrientationTask orientation{torso, 16};
  wholebody::PointTask height{torso, 16};
  wholebody::PrioritizedIk ik{16, 6, {2, 3, 3}};
  wholebody::WbcQp qp{model.layout(), 2};
  Eigen::VectorXd q, v;
  Eigen::MatrixXd J_c = Eigen::MatrixXd::Zero(6, 16);
  Eigen::VectorXd Jc_dot_v = Eigen::VectorXd::Zero(6);
  wholebody::ContactSetting contacts[2];

  DoubleSupport() {
    q = model.dynamics().neutral_configuration();
    q[6] = 1.0;
    for (const char* j : {"l_knee", "r_knee"}) q[model.layout().joints[static_cast<size_t>(model.layout().joint_index(j))].q_index] = 0.6;
    v = Eigen::VectorXd::Constant(16, 0.05);
    orientation.set_gains(100, 20);
    height.set_gains(100, 20);
    yaws.set_gains(100, 20);
    height.set_reference(Eigen::Vector3d(0, 0, 1.0), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  }
  void terms() { model.update(q, v, data); }
  wholebody::QpStatus control() {
    J_c.topRows(3) = data.frames[static_cast<size_t>(left)].J.bottomRows(3);
    J_c.bottomRows(3) = data.frames[static_cast<size_t>(right)].J.bottomRows(3);
    Jc_dot_v.head(3) = data.frames[static_cast<size_t>(left)].Jdot_v.tail(3);
    Jc_dot_v.tail(3) = data.frames[static_cast<size_t>(right)].Jdot_v.tail(3);
    yaws.update(data);
    orientation.update(data);
    height.update(data);
    const wholebody::Task* tasks[] = {&yaws, &orientation, &height};
    ik.solve(data, J_c, Jc_dot_v, tasks);
    return qp.solve(data, J_c, Jc_dot_v, ik.qdd(), contacts);
  }
};

void BM_WbcTermsIkAndQp(benchmark::State& state) {
  DoubleSupport s;
  s.terms();
  if (s.control() != wholebody::QpStatus::Optimal) state.SkipWithError("the QP found no solution");
  for (auto _ : state) {
    s.terms();
    s.control();
    benchmark::DoNotOptimize(s.qp.tau().data());
  }
}
BENCHMARK(BM_WbcTermsIkAndQp);

void BM_WbcModelTermsOnly(benchmark::State& state) {
  DoubleSupport s;
  for (auto _ : state) {
    s.terms();
    benchmark::DoNotOptimize(s.data.A.data());
  }
}
BENCHMARK(BM_WbcModelTermsOnly);

#if DMBD_HAVE_DART
// DART's equivalents of BM_WbcModelTermsOnly (DynamicsModel::update), on DRACO's URDF read
// by DART's loader (floating base: a FreeJoint), at the same state as DoubleSupport's: the
// base pose and twist from q and v (quaternion w x y z and origin in world; angular and
// origin velocity in world), each joint's angle and rate by name. Per iteration: the state
// set (which invalidates DART's caches), the mass matrix, Coriolis + gravity and gravity
// alone, and for each of the three frames (the feet at the same points, the torso) its
// pose, its world Jacobian at the point (6 x all dofs) and J̇·v (the classic derivative,
// in world axes, times the velocities), then the CoM, its linear Jacobian and J̇·v. DART
// skips the work when a coordinate is set to the value it already holds, so the
// iterations alternate between that state and one offset by 1e-9 in every coordinate:
// each one recomputes everything, as the controller's update does at every tick. The
// counter state_gap_m is the largest gap between the two models' CoM, frame origins and
// CoM velocity at that state (the benchmark fails above 1e-9).
struct DartDoubleSupport {
  struct Frame {
    dart::dynamics::BodyNode* body;
    Eigen::Vector3d p_L;
  };
  dart::dynamics::SkeletonPtr skel;
  std::vector<Frame> frames;
  Eigen::VectorXd positions[2], velocities[2];
  double mismatch_m = 0;  // the largest gap between the two models' CoM, frame origins and CoM velocity

  DartDoubleSupport() {
    DoubleSupport s;  // the state and the frames of BM_WbcModelTermsOnly
    s.terms();
    dart::utils::DartLoader loader;
    const std::string urdf = s.robot.source;
    loader.addPackageDirectory(s.robot.name, std::filesystem::path(urdf).parent_path().string());
    skel = loader.parseSkeleton(dart::common::Uri::createFromPath(urdf));
    if (!skel || !dynamic_cast<dart::dynamics::FreeJoint*>(skel->getRootJoint()))
      throw std::runtime_error("DART could not load " + urdf + " with a floating base");
    for (const wholebody::FrameSpec* f : {&kLeftFoot, &kRightFoot, &kTorso}) {
      dart::dynamics::BodyNode* body = skel->getBodyNode(f->link);
      if (!body) throw std::runtime_error("DART skeleton has no body '" + f->link + "'");
      frames.push_back({body, f->p_L});
    }
    const auto n = static_cast<Eigen::Index>(skel->getNumDofs());
    Eigen::VectorXd pos = Eigen::VectorXd::Zero(n), vel = Eigen::VectorXd::Zero(n);
    // The base: q = [w x y z, origin], v = [angular, origin velocity] in world; DART's free
    // joint: [rotation vector, origin] and [angular; linear] in the body's own axes.
    const Eigen::Quaterniond quat(s.q[0], s.q[1], s.q[2], s.q[3]);
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.linear() = quat.normalized().toRotationMatrix();
    X.translation() = s.q.segment<3>(4);
    pos.head<6>() = dart::dynamics::FreeJoint::convertToPositions(X);
    vel.head<3>() = X.linear().transpose() * s.v.segment<3>(0);
    vel.segment<3>(3) = X.linear().transpose() * s.v.segment<3>(3);
    const wholebody::Layout& layout = s.model.layout();
    if (skel->getNumDofs() != static_cast<std::size_t>(layout.nv))
      throw std::runtime_error("DART's skeleton and the controller's model differ in their number of dofs");
    for (const wholebody::Joint& j : layout.joints) {
      dart::dynamics::Joint* dj = skel->getJoint(j.name);
      if (!dj || dj->getNumDofs() != 1) throw std::runtime_error("DART skeleton has no 1-dof joint '" + j.name + "'");
      const auto i = static_cast<Eigen::Index>(dj->getIndexInSkeleton(0));
      pos[i] = s.q[j.q_index];
      vel[i] = s.v[j.v_index];
    }
    positions[0] = pos;
    velocities[0] = vel;
    positions[1] = pos.array() + 1e-9;
    velocities[1] = vel.array() + 1e-9;

    // The same state in both models: the CoM, the frames' origins and the CoM velocity.
    skel->setPositions(pos);
    skel->setVelocities(vel);
    auto gap = [this](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { mismatch_m = std::max(mismatch_m, (a - b).norm()); };
    gap(skel->getCOM(), s.data.com);
    gap(skel->getCOMLinearVelocity(), s.data.J_com * s.v);
    for (std::size_t k = 0; k < frames.size(); ++k)
      gap(frames[k].body->getWorldTransform() * frames[k].p_L, s.data.frames[k].X_WF.translation());
  }

  void terms(int which) {
    skel->setPositions(positions[which]);
    skel->setVelocities(velocities[which]);
    const Eigen::VectorXd& dq = velocities[which];
    benchmark::DoNotOptimize(skel->getMassMatrix().data());
    benchmark::DoNotOptimize(skel->getCoriolisAndGravityForces().data());
    benchmark::DoNotOptimize(skel->getGravityForces().data());
    for (const Frame& f : frames) {
      const Eigen::Isometry3d X = f.body->getWorldTransform();
      const Eigen::Vector3d p = X * f.p_L;
      // The skeleton's versions: 6 x (all dofs), as the controller's (a body's own are
      // 6 x the dofs it depends on).
      const dart::math::Jacobian J = skel->getWorldJacobian(f.body, f.p_L);
      const Eigen::Vector6d Jdot_v = skel->getJacobianClassicDeriv(f.body, f.p_L) * dq;
      benchmark::DoNotOptimize(p.data());
      benchmark::DoNotOptimize(J.data());
      benchmark::DoNotOptimize(Jdot_v.data());
    }
    const Eigen::Vector3d com = skel->getCOM();
    const dart::math::LinearJacobian J_com = skel->getCOMLinearJacobian();
    const Eigen::Vector3d com_Jdot_v = skel->getCOMLinearJacobianDeriv() * dq;
    benchmark::DoNotOptimize(com.data());
    benchmark::DoNotOptimize(J_com.data());
    benchmark::DoNotOptimize(com_Jdot_v.data());
  }
};

void BM_DartModelTerms(benchmark::State& state) {
  DartDoubleSupport s;
  if (s.mismatch_m > 1e-9) state.SkipWithError("DART's state differs from the controller model's");
  state.counters["state_gap_m"] = s.mismatch_m;
  int which = 0;
  for (auto _ : state) {
    s.terms(which);
    which ^= 1;
  }
}
BENCHMARK(BM_DartModelTerms);
#endif

// The controller fed a still robot in its stance posture, advanced to the phase asked
// for (range 0: double support, at the first step's start; 1: mid-swing; range 1: the
// kinematic estimator; range 2: balance.yaml's options instead of the authors'), then ticked
// there (each tick advances the phase machine; the range keeps it in that phase by
// starting over when it leaves).
void BM_BalanceTick(benchmark::State& state) {
  const model::RobotDescription robot = model::load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf");
  control::BalanceSetup setup = dmbd::test::draco_balance_names();  // robots/draco/robot.yaml's
  setup.estimator = state.range(1) ? control::BalanceEstimator::Kinematic : control::BalanceEstimator::MotionCapture;
  setup.phases.joint_move_s = setup.phases.body_lift_s = 0.05;
  setup.phases.body_lift_start_force_N = 300;
  if (state.range(2)) {  // the options balance.yaml sets (its weight shift aside)
    setup.tvr_point = control::TvrPoint::Torso;
    setup.ik_base_weight = 1000;
    setup.swing_relative_to_torso = setup.swing_foot_level = setup.actuator_feedforward = true;
    setup.task_gains.torso = {200, 28};
    setup.task_gains.swing_foot = {300, 35};
    setup.task_gains.joints = {200, 28};
    setup.qp.w_qdd = 1000;
    setup.qp.w_qdd_base = 10;
  }
  const bool swing = state.range(0) == 1;
  if (!swing) setup.phases.double_support_s = 1e6;  // stays in double support
  const std::vector<std::pair<std::string, double>> q0 = {
      {"l_hip_pitch", -0.9}, {"l_knee", 1.7}, {"l_ankle", -0.8}, {"r_hip_pitch", -0.9}, {"r_knee", 1.7}, {"r_ankle", -0.8}};
  auto make = [&] {
    auto c = std::make_unique<control::BalanceController>(robot, 9.81, dmbd::model::load_actuators(DMBD_ROBOTS_DIR "/draco/actuators.yaml"), q0, setup, 1);
    return c;
  };
  std::unique_ptr<control::BalanceController> c = make();
  std::vector<double> u(static_cast<size_t>(c->num_inputs()), 0.0), y(static_cast<size_t>(c->num_outputs()), 0.0);
  for (int k = 0; k < c->num_inputs(); ++k)
    for (const auto& [joint, angle] : q0)
      if (c->input_name(k) == joint + ".q") u[static_cast<size_t>(k)] = angle;
  // Ticks to the phase: 100 of start-up, then 10 DS, 30 lift, 165 into the swing.
  const int warm_up = swing ? 100 + 10 + 30 + 100 : 120;
  for (int k = 0; k < warm_up; ++k) c->step(u.data(), y.data());
  int ticks = 0;
  for (auto _ : state) {
    c->step(u.data(), y.data());
    benchmark::DoNotOptimize(y.data());
    if (swing && ++ticks == 200) {  // before the swing ends: back to its start
      state.PauseTiming();
      c = make();
      for (int k = 0; k < warm_up; ++k) c->step(u.data(), y.data());
      ticks = 0;
      state.ResumeTiming();
    }
  }
}
BENCHMARK(BM_BalanceTick)
    ->ArgNames({"swing", "kinematic", "shipped"})
    ->Args({0, 0, 0})
    ->Args({1, 0, 0})
    ->Args({0, 1, 0})
    ->Args({1, 1, 0})
    ->Args({0, 0, 1})
    ->Args({1, 0, 1});

}  // namespace

BENCHMARK_MAIN();
