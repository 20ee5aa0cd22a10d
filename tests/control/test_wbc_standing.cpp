// The whole-body controller's QP (wholebody/wbc_qp.hpp) on DRACO's model (floating base,
// control::DynamicsModel), standing still in double support with one point contact at each
// foot's centre: the forces respect the pyramid and the normal bounds; the base's
// equations of motion hold exactly (the contact forces equal m (a_com + g) by Newton);
// with a stiff Δq̈ weight the forces carry the weight; with no force allowed the robot
// falls at g; torques within their limits; no allocation in a solve.
#include <gtest/gtest.h>

#include "malloc_counter.hpp"

#include "draco_feet.hpp"

#include "dmbd/model/robot_description.hpp"
#include "dmbd/control/dynamics_model.hpp"
#include "dmbd/wholebody/wbc_qp.hpp"

namespace dmbd::control {
using namespace dmbd::sim;  // NOLINT: the engine's names in these tests
namespace {

using wholebody::ContactSetting;
using wholebody::QpStatus;

using dmbd::sim::test::collision_centre;

struct Standing {
  model::RobotDescription robot = model::load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf");
  DynamicsModel model{robot, model::DynamicsOptions{}};
  int left = model.add_frame({"l_foot", collision_centre(robot, "l_foot")});
  int right = model.add_frame({"r_foot", collision_centre(robot, "r_foot")});
  wholebody::ModelData data = model.make_data();
  Eigen::MatrixXd J_c = Eigen::MatrixXd::Zero(6, 16);
  Eigen::VectorXd Jc_dot_v = Eigen::VectorXd::Zero(6);
  double mass = 0;

  Standing() {
    Eigen::VectorXd q = model.dynamics().neutral_configuration();
    for (const auto& [j, a] : std::vector<std::pair<const char*, double>>{
             {"l_hip_pitch", -0.3}, {"l_knee", 0.6}, {"l_ankle", -0.3}, {"r_hip_pitch", -0.3}, {"r_knee", 0.6}, {"r_ankle", -0.3}})
      q[model.layout().joints[static_cast<size_t>(model.layout().joint_index(j))].q_index] = a;
    q[6] = 1.0;  // base height (the QP does not depend on it)
    model.update(q, Eigen::VectorXd::Zero(16), data);
    J_c.topRows(3) = data.frames[static_cast<size_t>(left)].J.bottomRows(3);
    J_c.bottomRows(3) = data.frames[static_cast<size_t>(right)].J.bottomRows(3);
    mass = model.dynamics().total_mass_kg();
  }
};

// Newton for the whole robot: Σ F = m (a_com + g ẑ), a_com = J_com q̈ + J̇_com v (1e-9
// relative: the base rows of the QP's equality constraints are this law).
void expect_newton(const Standing& s, const wholebody::WbcQp& wbc) {
  const Eigen::Vector3d a_com = s.data.J_com * wbc.qdd() + s.data.com_Jdot_v;
  const Eigen::Vector3d total = wbc.forces().head<3>() + wbc.forces().tail<3>();
  const Eigen::Vector3d expected = s.mass * (a_com + Eigen::Vector3d(0, 0, 9.81));
  EXPECT_LT((total - expected).norm(), 1e-9 * s.mass * 9.81) << total.transpose() << " vs " << expected.transpose();
}

void expect_pyramid(const wholebody::WbcQp& wbc, double mu, double f_max) {
  for (int c = 0; c < 2; ++c) {
    const Eigen::Vector3d f = wbc.forces().segment<3>(3 * c);
    EXPECT_GE(f.z(), -1e-9);
    EXPECT_LE(f.z(), f_max + 1e-9);
    EXPECT_LE(std::abs(f.x()), mu * f.z() + 1e-9);
    EXPECT_LE(std::abs(f.y()), mu * f.z() + 1e-9);
  }
}

TEST(WbcQp, StiffAccelerationWeightMakesTheFeetCarryTheWeight) {
  Standing s;
  wholebody::WbcQpParams p;
  p.w_qdd = 1e6;
  wholebody::WbcQp wbc(s.model.layout(), 2, p);
  const ContactSetting stance[2] = {};
  ASSERT_EQ(wbc.solve(s.data, s.J_c, s.Jc_dot_v, Eigen::VectorXd::Zero(16), stance), QpStatus::Optimal);
  const double fz = wbc.forces()[2] + wbc.forces()[5];
  std::printf("weight %.2f N, feet carry %.2f N (left %.2f, right %.2f)\n", s.mass * 9.81, fz, wbc.forces()[2], wbc.forces()[5]);
  EXPECT_NEAR(fz, s.mass * 9.81, 1e-3 * s.mass * 9.81);
  EXPECT_NEAR(wbc.forces()[2], wbc.forces()[5], 0.05 * fz);  // a symmetric stance: about half each
  expect_newton(s, wbc);
  expect_pyramid(wbc, p.mu, 550.0);
  EXPECT_LE(wbc.tau().cwiseAbs().maxCoeff(), p.torque_limit_Nm + 1e-9);
}

TEST(WbcQp, TheAuthorsWeightsKeepNewtonAndThePyramid) {
  Standing s;
  wholebody::WbcQp wbc(s.model.layout(), 2);
  const ContactSetting stance[2] = {};
  ASSERT_EQ(wbc.solve(s.data, s.J_c, s.Jc_dot_v, Eigen::VectorXd::Zero(16), stance), QpStatus::Optimal);
  std::printf("authors' weights: feet carry %.1f %% of the weight\n", 100.0 * (wbc.forces()[2] + wbc.forces()[5]) / (s.mass * 9.81));
  expect_newton(s, wbc);
  expect_pyramid(wbc, 0.3, 550.0);
  EXPECT_GT(wbc.forces()[2] + wbc.forces()[5], 0.5 * s.mass * 9.81);
}

TEST(WbcQp, WithNoForceAllowedTheRobotFallsAtG) {
  Standing s;
  wholebody::WbcQp wbc(s.model.layout(), 2);
  ContactSetting air[2];
  air[0].f_max_N = air[1].f_max_N = 0.0;
  air[0].w_slack = air[1].w_slack = 0.001;
  ASSERT_EQ(wbc.solve(s.data, s.J_c, s.Jc_dot_v, Eigen::VectorXd::Zero(16), air), QpStatus::Optimal);
  EXPECT_LT(wbc.forces().norm(), 1e-9);
  const Eigen::Vector3d a_com = s.data.J_com * wbc.qdd() + s.data.com_Jdot_v;
  EXPECT_LT((a_com - Eigen::Vector3d(0, 0, -9.81)).norm(), 1e-9);
}

// One contact (3 force components, fewer than the base's 6 rows): the reduced form needs
// no more rows of the contact Jacobian than it has, and the base's equations hold.
TEST(WbcQp, OneContactKeepsTheBaseEquations) {
  Standing s;
  wholebody::WbcQp wbc(s.model.layout(), 1);
  const ContactSetting stance[1] = {};
  const Eigen::MatrixXd J_left = s.J_c.topRows(3);
  const Eigen::VectorXd Jdv_left = s.Jc_dot_v.head(3);
  ASSERT_EQ(wbc.solve(s.data, J_left, Jdv_left, Eigen::VectorXd::Zero(16), stance), QpStatus::Optimal);
  const Eigen::VectorXd base = (s.data.A * wbc.qdd() + s.data.bg - J_left.transpose() * wbc.forces()).head(6);
  EXPECT_LT(base.norm(), 1e-9 * s.mass * 9.81) << base.transpose();
  EXPECT_GE(wbc.forces()[2], 0.0);
}

TEST(WbcQp, NoAllocationInASolve) {
  DMBD_SKIP_UNDER_ASAN();
  Standing s;
  wholebody::WbcQp wbc(s.model.layout(), 2);
  ContactSetting c[2];
  const Eigen::VectorXd qdd_cmd = Eigen::VectorXd::Zero(16);
  ASSERT_EQ(wbc.solve(s.data, s.J_c, s.Jc_dot_v, qdd_cmd, c), QpStatus::Optimal);  // warm-up
  const long before = dmbd::test::allocations();
  for (int k = 0; k < 50; ++k) {
    c[1].f_max_N = 550.0 - 10.0 * k;  // the right foot lifting
    c[1].w_slack = 1000.0 / (1 + k);
    ASSERT_EQ(wbc.solve(s.data, s.J_c, s.Jc_dot_v, qdd_cmd, c), QpStatus::Optimal);
  }
  EXPECT_EQ(dmbd::test::allocations() - before, 0);
}

}  // namespace
}  // namespace dmbd::control
