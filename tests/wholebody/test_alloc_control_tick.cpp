// No heap allocation in a whole-body control tick after warm-up: the model's update(),
// the tasks' update() and OperationalSpaceControl::compute (with a posture task), and
// the DynamicallyConsistentInverse alone, at full rank and with a dropped row. The C
// allocator is interposed in this executable to count allocations (malloc, calloc,
// realloc: what operator new and Eigen use), as in tests/model/test_alloc_steps.cpp;
// skipped under AddressSanitizer (tests/support/sanitizer.hpp).
#include <gtest/gtest.h>

#include "malloc_counter.hpp"

#include <cmath>
#include <random>
#include <vector>

#include "dmbd/wholebody/osc.hpp"
#include "dmbd/wholebody/phase_machine.hpp"
#include "dmbd/wholebody/projection.hpp"
#include "dmbd/wholebody/qp.hpp"
#include "dmbd/wholebody/swing.hpp"
#include "dmbd/wholebody/task.hpp"
#include "dmbd/wholebody/tvr.hpp"
#include "planar_point_task.hpp"
#include "two_link_arm.hpp"

using dmbd::test::g_allocations;

namespace dmbd::wholebody::testing {
namespace {

TEST(NoAllocation, TheCounterSeesAllocations) {
  DMBD_SKIP_UNDER_ASAN();
  const long before = g_allocations.load();
  std::vector<double> x(100, 1.0);
  EXPECT_GT(g_allocations.load() - before, 0);
  EXPECT_EQ(x.size(), 100u);
}

TEST(NoAllocation, ControlTickOfOperationalSpaceControl) {
  DMBD_SKIP_UNDER_ASAN();
  PlanarArm arm = three_link_arm();
  const int tip = arm.add_frame({"link3", Eigen::Vector3d(link_c().length, 0, 0)});
  const int elbow = arm.add_frame({"link2", Eigen::Vector3d(0.1, 0.0, 0.0)});
  ModelData d = arm.make_data();
  PointTask point(tip, 3);  // its y row is dropped: the rank-deficient path
  PlanarPointTask planar(tip, 3);
  OrientationTask orientation(elbow, 3);
  ComTask com(3);
  PostureTask posture(arm.layout(), {0, 1, 2});
  point.set_reference({0.9, 0.0, -0.4}, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  planar.set_reference({0.9, -0.4}, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero());
  orientation.set_reference(rotation_y(0.5), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  posture.set_reference(Eigen::Vector3d(0.3, 0.9, 0.6), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  for (Task* t : std::vector<Task*>{&point, &planar, &orientation, &com, &posture}) t->set_gains(100, 20);
  OperationalSpaceControl osc3(arm.layout(), 3, 3), osc2(arm.layout(), 2, 3);
  Eigen::VectorXd q(3), v(3), tau(3);
  auto tick = [&](double s) {
    q << 0.3 + s, 0.8 - s, -0.5 + 2 * s;
    v << 1.0 - s, 0.5, -2.0 * s;
    arm.update(q, v, d);
    point.update(d);
    planar.update(d);
    orientation.update(d);
    com.update(d);
    posture.update(d);
    osc3.compute(d, point, &posture, tau);
    double sum = tau.sum();
    osc2.compute(d, planar, &posture, tau);
    sum += tau.sum();
    osc2.compute(d, planar, nullptr, tau);
    return sum + tau.sum() + orientation.command().sum() + com.command().sum();
  };
  double sink = tick(0.0);  // warm-up
  const long before = g_allocations.load();
  for (int k = 1; k <= 100; ++k) sink += tick(0.001 * k);
  EXPECT_EQ(g_allocations.load() - before, 0) << "allocations in 100 control ticks";
  EXPECT_TRUE(std::isfinite(sink));
}

TEST(NoAllocation, DynamicallyConsistentInverseCompute) {
  DMBD_SKIP_UNDER_ASAN();
  Eigen::MatrixXd A(4, 4), J(3, 4);
  A << 4, 1, 0, 0, 1, 3, 1, 0, 0, 1, 2, 0.5, 0, 0, 0.5, 1;
  J << 1, 0, 2, 0, 0, 1, 0, 1, 1, 1, 2, 1;  // row 3 = row 1 + row 2: rank 2
  DynamicallyConsistentInverse dci(3, 4);
  dci.compute(A, J);  // warm-up
  const long before = g_allocations.load();
  for (int k = 0; k < 100; ++k) {
    A(0, 0) = 4.0 + 0.01 * k;
    dci.compute(A, J);
  }
  EXPECT_EQ(g_allocations.load() - before, 0) << "allocations in 100 computes";
  EXPECT_EQ(dci.rank(), 2);
}

// A QP of the whole-body controller's size, its active set changing between solves.
TEST(NoAllocation, QpSolve) {
  DMBD_SKIP_UNDER_ASAN();
  const int n = 28, m_eq = 12, m_in = 32;
  std::mt19937 rng(8);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd G = Eigen::MatrixXd::Identity(n, n), C_eq(m_eq, n), C_in(m_in, n);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < m_eq; ++i) C_eq(i, j) = normal(rng);
    for (int i = 0; i < m_in; ++i) C_in(i, j) = normal(rng);
  }
  Eigen::VectorXd a = Eigen::VectorXd::LinSpaced(n, -1.0, 1.0), b_eq = Eigen::VectorXd::Zero(m_eq);
  Eigen::VectorXd b_in = Eigen::VectorXd::Constant(m_in, -0.5);
  QpSolver qp(n, m_eq, m_in);
  ASSERT_EQ(qp.solve(G, a, C_eq, b_eq, C_in, b_in), QpStatus::Optimal);  // warm-up
  const long before = g_allocations.load();
  int active = 0;
  for (int k = 0; k < 50; ++k) {
    a[k % n] += 3.0;  // moves the unconstrained minimum: other constraints become active
    ASSERT_EQ(qp.solve(G, a, C_eq, b_eq, C_in, b_in), QpStatus::Optimal);
    active += qp.active_inequalities();
  }
  EXPECT_EQ(g_allocations.load() - before, 0) << "allocations in 50 solves";
  EXPECT_GT(active, 0);
}

// The contact-phase state machine over 10,000 ticks at 1 kHz: the start-up and ~16 steps,
// every other swing ended early by its ankle's velocity.
TEST(NoAllocation, PhaseMachineUpdate) {
  DMBD_SKIP_UNDER_ASAN();
  PhaseMachine machine;
  machine.update(0.001, 0.0, 0.0);  // warm-up: the first tick
  int early = 0, nominal = 0;
  const long before = g_allocations.load();
  for (int k = 0; k < 10000; ++k) {
    const PhaseInfo& now = machine.info();
    const bool drop = now.phase == Phase::Swing && now.step % 2 == 0 && now.time_in_phase_s > 0.2;
    const double swing_ankle = drop ? -3.0 : 0.0;
    const PhaseInfo& next = machine.update(0.001, now.swing_side == Side::Left ? swing_ankle : 0.0,
                                           now.swing_side == Side::Right ? swing_ankle : 0.0);
    if (next.events.touch_down) ++(next.events.touch_down_early ? early : nominal);
  }
  EXPECT_EQ(g_allocations.load() - before, 0) << "allocations in 10,000 phase-machine ticks";
  EXPECT_GE(early, 7);
  EXPECT_GE(nominal, 7);
}

// The stepping pieces per tick: the swing trajectory evaluated (with a start and a
// mid-swing replan among the ticks) and a TVR plan, 100 times.
TEST(NoAllocation, SwingTrajectoryAndTvrPlan) {
  DMBD_SKIP_UNDER_ASAN();
  const TvrPlanner planner;
  SwingTrajectory swing;
  TvrInput in;
  in.stance_foot_m = {0.0, -0.14};
  in.com_velocity_m_s = {0.05, 0.3};
  in.time_to_switch_s = 0.33;
  swing.start(Eigen::Vector3d(0.0, 0.14, 0.0), Eigen::Vector3d(0.0, 0.3, 0.0), 0.33);
  double sink = swing.at(0.1).position_m.sum() + planner.plan(in).foothold_m.sum();  // warm-up
  const long before = g_allocations.load();
  for (int k = 0; k < 100; ++k) {
    const double t = 0.33 * (k % 50) / 50.0;
    if (k % 50 == 0) swing.start(Eigen::Vector3d(0.0, 0.14, 0.0), Eigen::Vector3d(0.0, 0.3, 0.0), 0.33);
    in.com_m = {0.001 * k, -0.05 + 0.001 * k};
    in.time_to_switch_s = 0.33 - t;
    const TvrPlan plan = planner.plan(in);
    if (k % 50 == 25) swing.replan(t, Eigen::Vector3d(plan.foothold_m.x(), plan.foothold_m.y(), 0.0));
    const SwingSample s = swing.at(t);
    sink += s.position_m.sum() + s.velocity_m_s.sum() + s.acceleration_m_s2.sum() + plan.foothold_m.sum();
  }
  EXPECT_EQ(g_allocations.load() - before, 0) << "allocations in 100 ticks of swing and TVR";
  EXPECT_EQ(swing.replans(), 1);
  EXPECT_TRUE(std::isfinite(sink));
}

}  // namespace
}  // namespace dmbd::wholebody::testing
