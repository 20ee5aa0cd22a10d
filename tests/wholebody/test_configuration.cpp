// Configuration-space arithmetic (robot_model.hpp: integrate, difference) for a floating
// base (q = [w x y z, base origin, joints], v = [world angular velocity, base origin
// velocity, joint rates]) and a fixed base: difference inverts integrate, the angular
// velocity is in world axes, the quaternion's sign does not matter, the shorter way round.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>

#include "arm_fixtures.hpp"
#include "dmbd/wholebody/robot_model.hpp"

namespace dmbd::wholebody {
namespace {

constexpr int kJoints = 3;

Layout floating_layout() {
  Layout l;
  l.base_dofs = 6;
  l.nq = 7 + kJoints;
  l.nv = 6 + kJoints;
  for (int k = 0; k < kJoints; ++k) l.joints.push_back({"j" + std::to_string(k), 7 + k, 6 + k, {}});
  return l;
}

Eigen::Quaterniond quaternion_of(const Eigen::VectorXd& q) { return {q[0], q[1], q[2], q[3]}; }

Eigen::VectorXd configuration(const Eigen::Quaterniond& Q, const Eigen::Vector3d& p, const Eigen::VectorXd& joints) {
  Eigen::VectorXd q(7 + joints.size());
  q << Q.w(), Q.x(), Q.y(), Q.z(), p, joints;
  return q;
}

Eigen::VectorXd random_configuration(std::mt19937& rng) {
  const Eigen::Quaterniond Q(Eigen::Vector4d(testing::uniform(rng, 4, 1.0)).normalized());
  return configuration(Q, testing::uniform(rng, 3, 2.0), testing::uniform(rng, kJoints, M_PI));
}

// v with a random axis and |ω| uniform in [0, 0.99 π] (difference returns the rotation
// vector of angle ≤ π, so integrate is invertible there).
Eigen::VectorXd random_velocity(std::mt19937& rng) {
  Eigen::VectorXd v = testing::uniform(rng, 6 + kJoints, 3.0);
  const double angle = 0.99 * M_PI * std::uniform_real_distribution<double>(0.0, 1.0)(rng);
  v.head<3>() = angle * v.head<3>().normalized();
  return v;
}

Eigen::VectorXd integrated(const Layout& l, const Eigen::VectorXd& q, const Eigen::VectorXd& v, double dt) {
  Eigen::VectorXd out(l.nq);
  integrate(l, q, v, dt, out);
  return out;
}

Eigen::VectorXd differenced(const Layout& l, const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) {
  Eigen::VectorXd out(l.nv);
  difference(l, q0, q1, out);
  return out;
}

TEST(Configuration, DifferenceInvertsIntegrate) {
  // Exact in exact arithmetic; in doubles the quaternion product, normalisation and the
  // atan2 of AngleAxis round at ~1e-16 relative per operation on O(1) angles.
  const Layout l = floating_layout();
  std::mt19937 rng(11);
  for (int k = 0; k < 200; ++k) {
    const Eigen::VectorXd q0 = random_configuration(rng), v = random_velocity(rng);
    const Eigen::VectorXd q1 = integrated(l, q0, v, 1.0);
    EXPECT_NEAR(quaternion_of(q1).norm(), 1.0, 1e-15);
    EXPECT_LT((differenced(l, q0, q1) - v).norm(), 1e-12) << "v " << v.transpose();
    // dt scales v.
    EXPECT_LT((integrated(l, q0, v, 0.25) - integrated(l, q0, 0.25 * v, 1.0)).norm(), 1e-15);
  }
}

TEST(Configuration, TinyRotationsRoundTrip) {
  const Layout l = floating_layout();
  std::mt19937 rng(12);
  for (const double angle : {0.0, 1e-14, 1e-9, 1e-6}) {
    const Eigen::VectorXd q0 = random_configuration(rng);
    Eigen::VectorXd v = random_velocity(rng);
    v.head<3>() = angle * Eigen::Vector3d(1, -2, 2) / 3.0;
    EXPECT_LT((differenced(l, q0, integrated(l, q0, v, 1.0)) - v).norm(), 1e-12) << "angle " << angle;
  }
}

TEST(Configuration, AngularVelocityIsInWorldAxes) {
  // R(t + dt) = R_z(ω dt) R(t) for ω = ω ẑ in world axes. R0 is not about z, so the
  // body-axes reading R0 R_z(ω dt) differs (checked below: the test can tell them apart).
  const Layout l = floating_layout();
  const Eigen::Quaterniond Q0(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 1, 0).normalized()));
  const Eigen::VectorXd q0 = configuration(Q0, Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(0.1, 0.2, 0.3));
  Eigen::VectorXd v = Eigen::VectorXd::Zero(l.nv);
  v[2] = 0.4;
  const Eigen::VectorXd q1 = integrated(l, q0, v, 0.5);
  const Eigen::Matrix3d R_z = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d R1 = quaternion_of(q1).toRotationMatrix();
  EXPECT_LT((R1 - R_z * Q0.toRotationMatrix()).norm(), 1e-15) << R1;
  EXPECT_GT((R1 - Q0.toRotationMatrix() * R_z).norm(), 0.05);
  EXPECT_LT((q1.tail(3 + kJoints) - q0.tail(3 + kJoints)).norm(), 1e-15);  // nothing else moved
}

TEST(Configuration, TranslationAndJointsAreIntegratedLinearly) {
  const Layout l = floating_layout();
  const Eigen::VectorXd q0 = configuration(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 2, 3),
                                           Eigen::Vector3d(0.1, 0.2, 0.3));
  Eigen::VectorXd v(l.nv);
  v << 0, 0, 0, 0.5, -1.0, 2.0, 1.0, -2.0, 4.0;
  Eigen::VectorXd expected = q0;
  expected.segment<3>(4) += 0.1 * Eigen::Vector3d(0.5, -1.0, 2.0);
  expected.tail<3>() += 0.1 * Eigen::Vector3d(1.0, -2.0, 4.0);
  EXPECT_LT((integrated(l, q0, v, 0.1) - expected).norm(), 1e-15);
}

TEST(Configuration, DifferenceIgnoresTheQuaternionSignAndTakesTheShorterWay) {
  const Layout l = floating_layout();
  const Eigen::Quaterniond Q0(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()));
  const Eigen::VectorXd q0 = configuration(Q0, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  // 1.5 π about x, the same rotation as −0.5 π about x.
  const Eigen::Quaterniond Q1 = Eigen::Quaterniond(Eigen::AngleAxisd(1.5 * M_PI, Eigen::Vector3d::UnitX())) * Q0;
  const Eigen::VectorXd q1 = configuration(Q1, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  const Eigen::VectorXd q1_flipped =
      configuration(Eigen::Quaterniond(-Q1.coeffs()), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  const Eigen::VectorXd d = differenced(l, q0, q1);
  EXPECT_LT((d.head<3>() - Eigen::Vector3d(-0.5 * M_PI, 0, 0)).norm(), 1e-12) << d.head<3>().transpose();
  EXPECT_LT((differenced(l, q0, q1_flipped) - d).norm(), 1e-12);
  EXPECT_LT(differenced(l, q0, q0).norm(), 1e-15);
}

TEST(Configuration, FixedBaseIsPlainArithmetic) {
  Layout l;
  l.nq = l.nv = 2;
  l.joints = {{"a", 0, 0, {}}, {"b", 1, 1, {}}};
  const Eigen::Vector2d q(0.5, -1.0), v(2.0, 3.0);
  Eigen::VectorXd out(2);
  integrate(l, q, v, 0.5, out);
  EXPECT_EQ(out, Eigen::VectorXd(Eigen::Vector2d(1.5, 0.5)));
  difference(l, q, Eigen::Vector2d(1.5, 0.5), out);
  EXPECT_EQ(out, Eigen::VectorXd(Eigen::Vector2d(1.0, 1.5)));
}

}  // namespace
}  // namespace dmbd::wholebody
