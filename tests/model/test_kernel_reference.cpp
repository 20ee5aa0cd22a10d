// RobotDynamics (the tree kernel) and the equations of motion solved either way
// (equations_of_motion.hpp) against SimbodyReference (Simbody's calcM, residual-force
// and articulated-body operators, calcFrameJacobian, the system mass centre on its own
// Simbody system) at random states, on DRACO and on a tree with every joint kind, fixed
// and floating: what the Python robot model's engine="simbody" returns (python/tests/
// test_model.py compares the same quantities there, in the Python API's conventions).
#include "dmbd/model/equations_of_motion.hpp"
#include "dmbd/model/simbody_reference.hpp"

#include "test_urdf_support.hpp"

#include <gtest/gtest.h>

#include <random>

namespace dmbd::model {
namespace {

double rel(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

struct Worst {
  double m = 0, bg = 0, g = 0, rnea = 0, aba = 0, pose = 0, jac = 0, com = 0, jcom = 0, round_trip = 0;
};

Worst against_reference(const RobotDescription& robot, BaseMode base, int states, unsigned seed) {
  DynamicsOptions o;
  o.base = base;
  RobotDynamics d(robot, o);
  SimbodyReference s(robot, o);
  EXPECT_EQ(d.nq(), s.nq());
  EXPECT_EQ(d.nv(), s.nv());
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  const auto random = [&](int n, double scale) { return Eigen::VectorXd(Eigen::VectorXd::NullaryExpr(n, [&] { return scale * u(rng); })); };
  Worst w;
  for (int k = 0; k < states; ++k) {
    const Eigen::VectorXd q = random(d.nq(), 1.0), v = random(d.nv(), 2.0), a = random(d.nv(), 3.0),
                          tau = random(d.nv(), 50.0);
    d.set_state(q, v);  // both normalise the quaternions
    s.set_state(q, v);
    w.m = std::max(w.m, rel(d.mass_matrix(), s.mass_matrix()));
    w.bg = std::max(w.bg, rel(d.coriolis_and_gravity(), s.coriolis_and_gravity()));
    w.g = std::max(w.g, rel(d.gravity(), s.gravity()));
    w.rnea = std::max(w.rnea, rel(inverse_dynamics(d, a), s.inverse_dynamics(a)));
    w.aba = std::max(w.aba, rel(forward_dynamics(d, tau), s.forward_dynamics(tau)));
    w.round_trip = std::max({w.round_trip, rel(forward_dynamics(d, inverse_dynamics(d, a)), a),
                             rel(s.forward_dynamics(s.inverse_dynamics(a)), a)});
    w.com = std::max(w.com, rel(d.com_position(), s.com_position()));
    w.jcom = std::max(w.jcom, rel(d.com_jacobian(), s.com_jacobian()));
    const Eigen::Vector3d p_L(0.03, -0.02, -0.1);
    for (int l = 0; l < static_cast<int>(robot.links.size()); ++l) {
      w.pose = std::max(w.pose, rel(d.link_pose(l).matrix(), s.link_pose(l).matrix()));
      w.jac = std::max(w.jac, rel(d.frame_jacobian(l, p_L), s.frame_jacobian(l, p_L)));
    }
  }
  return w;
}

void expect_rounding_level(const Worst& w, const char* what) {
  // Entries are O(1-1000); both sides are exact up to rounding. The articulated-body
  // solve and the Cholesky solve of M differ by M's condition number times rounding.
  EXPECT_LT(w.m, 1e-12) << what;
  EXPECT_LT(w.bg, 1e-12) << what;
  EXPECT_LT(w.g, 1e-12) << what;
  EXPECT_LT(w.rnea, 1e-12) << what;
  EXPECT_LT(w.aba, 1e-10) << what;
  EXPECT_LT(w.round_trip, 1e-10) << what;
  EXPECT_LT(w.pose, 1e-12) << what;
  EXPECT_LT(w.jac, 1e-12) << what;
  EXPECT_LT(w.com, 1e-12) << what;
  EXPECT_LT(w.jcom, 1e-12) << what;
  std::printf("RobotDynamics vs SimbodyReference, %s: M %.1e, b+g %.1e, g %.1e, rnea %.1e, aba %.1e, aba(rnea) %.1e, "
              "pose %.1e, J %.1e, com %.1e, J_com %.1e\n",
              what, w.m, w.bg, w.g, w.rnea, w.aba, w.round_trip, w.pose, w.jac, w.com, w.jcom);
}

TEST(SimbodyReference, AgreesWithRobotDynamicsOnDraco) {
  const RobotDescription r = load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf", UrdfOptions{{}, false, false});
  expect_rounding_level(against_reference(r, BaseMode::Floating, 5, 1), "DRACO floating");
  expect_rounding_level(against_reference(r, BaseMode::Fixed, 5, 2), "DRACO fixed");
}

// Pin, slider, weld, a second free body and a planar joint: Simbody's operators and the
// kernel on every mobilizer kind.
TEST(SimbodyReference, AgreesWithRobotDynamicsOnEveryJointKind) {
  const RobotDescription r = load_urdf(test::urdf_data("every_joint/every_joint.urdf"), UrdfOptions{{}, false, false});
  expect_rounding_level(against_reference(r, BaseMode::Floating, 5, 3), "every joint kind, floating");
  expect_rounding_level(against_reference(r, BaseMode::Fixed, 5, 4), "every joint kind, fixed");
}

TEST(SimbodyReference, WrongSizesAreModelErrors) {
  const RobotDescription r = load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf", UrdfOptions{{}, false, false});
  SimbodyReference s(r);
  RobotDynamics d(r);
  EXPECT_THROW(s.set_state(Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(s.nv())), ModelError);
  s.set_state(d.neutral_configuration(), Eigen::VectorXd::Zero(s.nv()));
  EXPECT_THROW(s.forward_dynamics(Eigen::VectorXd::Zero(2)), ModelError);
  EXPECT_THROW(forward_dynamics(d, Eigen::VectorXd::Zero(2)), ModelError);
  EXPECT_THROW(inverse_dynamics(d, Eigen::VectorXd::Zero(2)), ModelError);
  EXPECT_THROW(s.link_pose(999), ModelError);
}

}  // namespace
}  // namespace dmbd::model
