// The tree kernel (model/src/tree_kernel.hpp) against Simbody's own operators at random
// states: body poses and velocities against Simbody's realised State, qdot = N(q) v
// against multiplyByN, the composite-rigid-body mass matrix against calcM, Coriolis +
// gravity against calcResidualForceIgnoringConstraints, the hinge-column point Jacobians
// and their bias terms against calcStationJacobian / calcBiasForStationJacobian, the
// centre-of-mass Jacobian against finite differences of the centre of mass, and the
// energies. On DRACO and on a tree with every joint kind (tests/model/data/urdf/every_joint).
#include "tree_kernel.hpp"

#include "plant_fixtures.hpp"
#include "test_urdf_support.hpp"

#include <gtest/gtest.h>

#include <random>

namespace dmbd::model {
// The base as ctest lists the cases (found by argument-dependent lookup; gtest would print
// the enum's bytes).
static void PrintTo(BaseMode b, std::ostream* os) { *os << (b == BaseMode::Fixed ? "fixed base" : "floating base"); }
}  // namespace dmbd::model

namespace dmbd::model::detail {
namespace {

const RobotDescription& draco() {
  static const RobotDescription r = load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf", UrdfOptions{{}, false, false});
  return r;
}

const RobotDescription& every_joint() {
  static const RobotDescription r = load_urdf(test::urdf_data("every_joint/every_joint.urdf"), UrdfOptions{{}, false, false});
  return r;
}

// A random configuration: unit quaternion, joints in [-1, 1], base within a metre.
void randomize(const TreeKernel& k, std::mt19937& rng, Eigen::VectorXd& q, Eigen::VectorXd& v) {
  std::uniform_real_distribution<double> u(-1, 1);
  q = Eigen::VectorXd::NullaryExpr(k.nq(), [&] { return u(rng); });
  v = Eigen::VectorXd::NullaryExpr(k.nv(), [&] { return 2 * u(rng); });
  k.normalize(q);
}

// Relative error of a against b, against the scale of b (or 1).
double rel(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

class KernelVsSimbody : public ::testing::TestWithParam<BaseMode> {};

// Worst relative differences, kernel against Simbody, over random states.
struct Worst {
  double pose = 0, vel = 0, qdot = 0, m = 0, c = 0, j = 0, b = 0;
};

Worst against_simbody(TreeKernel& k, int trials, unsigned seed) {
  std::mt19937 rng(seed);
  Eigen::VectorXd q, v;
  const int n = k.nv();
  Eigen::MatrixXd M(n, n), Mr(n, n), J(3, n), Jr(3, n);
  Eigen::VectorXd c(n), cr(n), qd(k.nq()), qdr(k.nq());
  Worst w;
  for (int trial = 0; trial < trials; ++trial) {
    randomize(k, rng, q, v);
    k.set_q(q);
    k.set_v(v);
    k.mass_matrix(M);
    k.reference_mass_matrix(Mr);
    k.coriolis_and_gravity(c);
    k.reference_coriolis_and_gravity(cr);
    k.qdot(v, qd);
    k.reference_qdot(v, qdr);
    w.m = std::max(w.m, rel(M, Mr));
    w.c = std::max(w.c, rel(c, cr));
    w.qdot = std::max(w.qdot, rel(qd, qdr));
    for (int b = 1; b < k.num_bodies(); ++b) {
      const Eigen::Isometry3d X = k.pose(b), Xr = k.reference_pose(b);
      w.pose = std::max({w.pose, rel(X.linear(), Xr.linear()), rel(X.translation(), Xr.translation())});
      Vector6d V;
      V << k.angular_velocity(b), k.point_velocity(b, k.origin(b));
      w.vel = std::max(w.vel, rel(V, k.reference_velocity(b)));
      const Eigen::Vector3d p = k.origin(b) + k.rotation(b) * Eigen::Vector3d(0.03, -0.02, -0.1);
      k.point_jacobian(b, p, J);
      k.reference_point_jacobian(b, p, Jr);
      w.j = std::max(w.j, rel(J, Jr));
      w.b = std::max(w.b, rel(k.point_bias_acceleration(b, p), k.reference_point_bias_acceleration(b, p)));
    }
  }
  return w;
}

void expect_rounding_level(const Worst& w, const char* robot) {
  // Both sides are exact up to rounding: entries are O(1-100), 1e-12 relative.
  EXPECT_LT(w.pose, 1e-12) << robot;
  EXPECT_LT(w.vel, 1e-12) << robot;
  EXPECT_LT(w.qdot, 1e-12) << robot;
  EXPECT_LT(w.m, 1e-12) << robot;
  EXPECT_LT(w.c, 1e-12) << robot;
  EXPECT_LT(w.j, 1e-12) << robot;
  EXPECT_LT(w.b, 1e-12) << robot;
  std::printf("kernel vs Simbody, %s: pose %.2g, V %.2g, qdot %.2g, M %.2g, c %.2g, J %.2g, Jdot v %.2g\n", robot, w.pose,
              w.vel, w.qdot, w.m, w.c, w.j, w.b);
}

TEST_P(KernelVsSimbody, KinematicsMassMatrixBiasForcesAndJacobiansAgree) {
  TreeKernel k(draco(), GetParam(), Eigen::Isometry3d::Identity(), 9.81);
  expect_rounding_level(against_simbody(k, 20, 11), "DRACO");
}

// Pin, slider, weld, a second free body and a planar joint, all off-axis, so every
// mobilizer kind's transform, hinge columns, bias acceleration and N(q) is exercised.
TEST_P(KernelVsSimbody, EveryJointKindAgrees) {
  TreeKernel k(every_joint(), GetParam(), Eigen::Isometry3d::Identity(), 9.81);
  ASSERT_EQ(k.nv(), GetParam() == BaseMode::Floating ? 6 + 3 + 6 + 3 : 3 + 6 + 3);
  expect_rounding_level(against_simbody(k, 20, 7), "every joint kind");
}

TEST_P(KernelVsSimbody, ComJacobianMatchesFiniteDifferencesAndEnergyIsQuadratic) {
  TreeKernel k(draco(), GetParam(), Eigen::Isometry3d::Identity(), 9.81);
  std::mt19937 rng(5);
  Eigen::VectorXd q, v;
  randomize(k, rng, q, v);
  k.set_q(q);
  k.set_v(v);
  const int n = k.nv();
  Eigen::MatrixXd Jc(3, n), M(n, n);
  k.com_jacobian(Jc);
  k.mass_matrix(M);
  const Eigen::Vector3d c0 = k.com(), vc = Jc * v, ab = k.com_bias_acceleration();
  const double ke = k.kinetic_energy();
  // Central differences along the motion: c(q(t +- h)) with q(t) from integrate().
  const double h = 1e-6;
  Eigen::VectorXd qp = q, qm = q;
  k.integrate(qp, v, h);
  k.integrate(qm, v, -h);
  k.set_q(qp);
  const Eigen::Vector3d cp = k.com();
  k.set_q(qm);
  const Eigen::Vector3d cm = k.com();
  EXPECT_LT(((cp - cm) / (2 * h) - vc).norm(), 1e-6 * std::max(1.0, vc.norm()));
  EXPECT_NEAR(ke, 0.5 * v.dot(M * v), 1e-12 * std::max(1.0, ke));
  EXPECT_TRUE(ab.allFinite());
  (void)c0;
}

INSTANTIATE_TEST_SUITE_P(Bases, KernelVsSimbody, ::testing::Values(BaseMode::Fixed, BaseMode::Floating));

}  // namespace
}  // namespace dmbd::model::detail
