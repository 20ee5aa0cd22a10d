// RobotDynamics (Simbody behind an Eigen interface) against closed forms and finite
// differences: a double pendulum's mass matrix, Coriolis and gravity terms; Jacobians
// and their bias terms; a floating base's momentum structure.
#include "dmbd/model/dynamics.hpp"

#include "plant_fixtures.hpp"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <array>
#include <cmath>

namespace dmbd::model {
namespace {

using testing::DoublePendulum;

TEST(Dynamics, DoublePendulumMatchesClosedForms) {
  const DoublePendulum dp;
  const RobotDescription r = dp.robot();
  RobotDynamics d(r, {BaseMode::Fixed, Eigen::Isometry3d::Identity(), 9.81});
  ASSERT_EQ(d.nq(), 2);
  ASSERT_EQ(d.nv(), 2);
  for (const auto& [q1, q2, v1, v2] : std::vector<std::array<double, 4>>{
           {0.3, -0.7, 1.1, -2.0}, {-1.2, 2.1, 0.0, 3.0}, {2.5, 0.4, -1.5, 0.5}}) {
    d.set_state(Eigen::Vector2d(q1, q2), Eigen::Vector2d(v1, v2));
    // Simbody computes these in O(n) recursions; the closed forms are exact: agreement to
    // rounding (1e-12 relative to the largest entry).
    EXPECT_LT((d.mass_matrix() - dp.mass_matrix(q2)).norm(), 1e-12 * dp.mass_matrix(q2).norm());
    const Eigen::Vector2d g = dp.gravity(q1, q2, 9.81);
    EXPECT_LT((d.gravity() - g).norm(), 1e-12 * (1 + g.norm()));
    const Eigen::Vector2d c = dp.coriolis(q2, v1, v2);
    EXPECT_LT((d.coriolis() - c).norm(), 1e-12 * (1 + c.norm()));
    EXPECT_LT((d.coriolis_and_gravity() - c - g).norm(), 1e-11 * (1 + c.norm() + g.norm()));
    // Independent gravity from the description's own forward kinematics.
    EXPECT_LT((d.gravity() - testing::gravity_torques(r, Eigen::Vector2d(q1, q2), 9.81)).norm(), 1e-12 * (1 + g.norm()));
    // Energies: kinetic 1/2 v'Mv, potential m g z of the centres of mass.
    const Eigen::Vector2d v(v1, v2);
    EXPECT_NEAR(d.kinetic_energy(), 0.5 * v.dot(dp.mass_matrix(q2) * v), 1e-12 * (1 + d.kinetic_energy()));
  }
}

// Central differences with h = 1e-6: truncation O(h^2 |f'''|) ~ 1e-12, rounding
// O(eps |f| / h) ~ 1e-10; tolerance 1e-7.
TEST(Dynamics, JacobiansMatchFiniteDifferences) {
  const DoublePendulum dp;
  RobotDescription r = dp.robot();
  // A third joint about x makes the chain spatial.
  r.links.push_back(testing::point_link("hand", 0.5, {0.05, 0.02, -0.1}, 0.003));
  r.joints.push_back(testing::revolute("wrist", "lower", "hand", {0.0, 0.0, -0.4}, {1, 0.3, 0}));
  for (BaseMode base : {BaseMode::Fixed, BaseMode::Floating}) {
    RobotDynamics d(r, {base, Eigen::Isometry3d::Identity(), 9.81});
    Eigen::VectorXd q = d.neutral_configuration();
    const int nb = base == BaseMode::Floating ? 7 : 0;
    q.tail(3) << 0.4, -0.9, 0.7;
    if (nb) {
      const Eigen::Quaterniond qt(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
      q.head(7) << qt.w(), qt.x(), qt.y(), qt.z(), 0.1, -0.2, 1.0;
    }
    Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(d.nv(), -1.0, 1.3);
    const int hand = d.link_index("hand");
    const Eigen::Vector3d p(0.02, -0.03, 0.05);
    d.set_state(q, v);
    const Eigen::MatrixXd J = d.point_jacobian(hand, p);
    const Eigen::MatrixXd JF = d.frame_jacobian(hand, p);
    const Eigen::MatrixXd Jc = d.com_jacobian();
    EXPECT_LT((JF.bottomRows(3) - J).norm(), 1e-12);
    // Velocity of the point and the CoM along v by differencing positions along the motion:
    // integrate q by +-h v (for the quaternion: rotate by the angular velocity in world).
    auto moved = [&](double h) {
      Eigen::VectorXd qh = q;
      if (nb) {
        const Eigen::Vector3d w = v.head(3);
        const Eigen::Quaterniond q0(q[0], q[1], q[2], q[3]);
        const Eigen::Quaterniond dq(Eigen::AngleAxisd(w.norm() * h, w.normalized()));
        const Eigen::Quaterniond q1 = dq * q0;
        qh.head(4) << q1.w(), q1.x(), q1.y(), q1.z();
        qh.segment(4, 3) += h * v.segment(3, 3);
      }
      qh.tail(3) += h * v.tail(3);
      return qh;
    };
    const double h = 1e-6;
    d.set_state(moved(h), v);
    const Eigen::Vector3d pp = d.point_position(hand, p), cp = d.com_position();
    const Eigen::MatrixXd Jp = d.point_jacobian(hand, p), Jcp = d.com_jacobian();
    d.set_state(moved(-h), v);
    const Eigen::Vector3d pm = d.point_position(hand, p), cm = d.com_position();
    const Eigen::MatrixXd Jm = d.point_jacobian(hand, p), Jcm = d.com_jacobian();
    d.set_state(q, v);
    EXPECT_LT(((pp - pm) / (2 * h) - J * v).norm(), 1e-7) << "base mode " << static_cast<int>(base);
    EXPECT_LT(((cp - cm) / (2 * h) - Jc * v).norm(), 1e-7);
    // J̇v: the derivative of J along the motion, times v.
    EXPECT_LT(((Jp - Jm) / (2 * h) * v - d.point_jacobian_dot_v(hand, p)).norm(), 1e-6);
    EXPECT_LT(((Jcp - Jcm) / (2 * h) * v - d.com_jacobian_dot_v()).norm(), 1e-6);
    EXPECT_LT((d.frame_jacobian_dot_v(hand, p).tail(3) - d.point_jacobian_dot_v(hand, p)).norm(), 1e-12);
    if (nb) {
      // The base's translational block of A is the total mass (v = [omega_W, v_W, ...] and
      // the torso origin's velocity moves every body alike).
      const Eigen::MatrixXd A = d.mass_matrix();
      EXPECT_LT((A.block(3, 3, 3, 3) - d.total_mass_kg() * Eigen::Matrix3d::Identity()).norm(), 1e-12);
      EXPECT_NEAR(d.total_mass_kg(), 1.0 + dp.m1 + dp.m2 + 0.5, 1e-12);
      // Gravity on a floating robot: the base force is m g upward-opposed (g_z = m g).
      EXPECT_NEAR(d.gravity()[5], d.total_mass_kg() * 9.81, 1e-9);
      // A is symmetric positive definite.
      EXPECT_LT((A - A.transpose()).norm(), 1e-12);
      EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A).eigenvalues().minCoeff(), 0.0);
    }
  }
}

TEST(Dynamics, MasslessLeafJointIsWelded) {
  RobotDescription r = DoublePendulum().robot();
  r.links.push_back(testing::point_link("camera_frame", 0.0, Eigen::Vector3d::Zero()));
  r.joints.push_back(testing::revolute("camera_tilt", "lower", "camera_frame", {0, 0, -0.3}, {0, 1, 0}));
  RobotDynamics d(r, {BaseMode::Fixed, Eigen::Isometry3d::Identity(), 9.81});
  EXPECT_EQ(d.nv(), 2);
  ASSERT_EQ(d.welded_joints().size(), 1u);
  EXPECT_EQ(d.welded_joints()[0], "camera_tilt");
}

}  // namespace
}  // namespace dmbd::model
