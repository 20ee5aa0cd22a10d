// control::DynamicsModel, wholebody's robot model over model::RobotDynamics: every quantity
// against RobotDynamics' own value forms (two paths through the same kernel must agree
// exactly), and the kinematic ones against finite differences (an independent check of
// the Jacobians and J̇v that the OSC reads).
#include <gtest/gtest.h>

#include <random>

#include "dmbd/base/error.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/control/dynamics_model.hpp"
#include "dmbd/wholebody/momentum.hpp"

namespace dmbd::control {

namespace {

const model::RobotDescription& draco() {
  static const model::RobotDescription r = model::load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf");
  return r;
}

model::DynamicsOptions table(double z) {
  model::DynamicsOptions o;
  o.base = model::BaseMode::Fixed;
  o.X_WB.translation() = Eigen::Vector3d(0, 0, z);
  return o;
}

// A random state inside the joint limits, rates of up to 2 rad/s.
void random_state(const wholebody::Layout& l, std::mt19937& rng, Eigen::VectorXd& q, Eigen::VectorXd& v) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  q.setZero(l.nq);
  v.setZero(l.nv);
  for (const auto& j : l.joints) {
    const double lo = std::isfinite(j.limits.lower_rad) ? j.limits.lower_rad : -1.0;
    const double hi = std::isfinite(j.limits.upper_rad) ? j.limits.upper_rad : 1.0;
    q[j.q_index] = lo + (hi - lo) * (0.1 + 0.8 * u(rng));
    v[j.v_index] = 4.0 * u(rng) - 2.0;
  }
}

TEST(DynamicsModel, LayoutIsTheTenJointsWithTheirUrdfLimits) {
  DynamicsModel m(draco(), table(1.3));
  const auto& l = m.layout();
  EXPECT_EQ(l.nq, 10);
  EXPECT_EQ(l.nv, 10);
  EXPECT_EQ(l.base_dofs, 0);
  ASSERT_EQ(l.joints.size(), 10u);
  const int knee = l.joint_index("l_knee");
  ASSERT_GE(knee, 0);
  const model::Joint& urdf = draco().joints[static_cast<size_t>(draco().joint_index("l_knee"))];
  EXPECT_EQ(l.joints[static_cast<size_t>(knee)].limits.lower_rad, urdf.lower);
  EXPECT_EQ(l.joints[static_cast<size_t>(knee)].limits.upper_rad, urdf.upper);
  EXPECT_THROW(m.add_frame({"no_such_link", Eigen::Vector3d::Zero()}), InputError);
}

TEST(DynamicsModel, EveryQuantityIsRobotDynamicsOwn) {
  DynamicsModel m(draco(), table(1.3));
  const Eigen::Vector3d p_L(0.05, -0.01, -0.04);
  m.add_frame({"l_foot", p_L});
  m.add_frame({"r_shank", Eigen::Vector3d::Zero()});
  wholebody::ModelData d = m.make_data();
  model::RobotDynamics ref(draco(), table(1.3));
  std::mt19937 rng(3);
  Eigen::VectorXd q, v;
  for (int trial = 0; trial < 5; ++trial) {
    random_state(m.layout(), rng, q, v);
    m.update(q, v, d);
    ref.set_state(q, v);
    EXPECT_EQ((d.A - ref.mass_matrix()).norm(), 0.0);
    EXPECT_EQ((d.bg - ref.coriolis_and_gravity()).norm(), 0.0);
    EXPECT_EQ((d.g - ref.gravity()).norm(), 0.0);
    const int foot = ref.link_index("l_foot");
    EXPECT_EQ((d.frames[0].X_WF.translation() - ref.point_position(foot, p_L)).norm(), 0.0);
    EXPECT_EQ((d.frames[0].X_WF.rotation() - ref.link_pose(foot).rotation()).norm(), 0.0);
    EXPECT_EQ((d.frames[0].J - ref.frame_jacobian(foot, p_L)).norm(), 0.0);
    EXPECT_EQ((d.frames[0].Jdot_v - ref.frame_jacobian_dot_v(foot, p_L)).norm(), 0.0);
    EXPECT_EQ((d.com - ref.com_position()).norm(), 0.0);
    EXPECT_EQ((d.J_com - ref.com_jacobian()).norm(), 0.0);
  }
}

// Central differences along v: x(q + v h) − x(q − v h) = 2h J v + O(h³), and
// J(q + v h) v − J(q − v h) v = 2h J̇ v + O(h²·|v|³). With h = 1e-6 the truncation is
// ~1e-12 and rounding ~1e-10 m/s: tolerances 1e-7 (absolute, m/s and m/s²).
TEST(DynamicsModel, JacobiansAndBiasAgreeWithFiniteDifferences) {
  DynamicsModel m(draco(), table(1.3));
  m.add_frame({"l_foot", Eigen::Vector3d(0.08, 0.005, -0.044)});
  wholebody::ModelData d = m.make_data(), dp = m.make_data(), dm = m.make_data();
  std::mt19937 rng(11);
  Eigen::VectorXd q, v;
  const double h = 1e-6;
  for (int trial = 0; trial < 5; ++trial) {
    random_state(m.layout(), rng, q, v);
    m.update(q, v, d);
    m.update(q + h * v, v, dp);
    m.update(q - h * v, v, dm);
    const Eigen::Vector3d p_rate = (dp.frames[0].X_WF.translation() - dm.frames[0].X_WF.translation()) / (2 * h);
    EXPECT_LT((p_rate - d.frames[0].J.bottomRows<3>() * v).norm(), 1e-7);
    // Angular velocity from R(q ± hv): log(R₊ R₋ᵀ) / 2h.
    const Eigen::AngleAxisd dR(Eigen::Matrix3d(dp.frames[0].X_WF.rotation() * dm.frames[0].X_WF.rotation().transpose()));
    EXPECT_LT((dR.axis() * dR.angle() / (2 * h) - d.frames[0].J.topRows<3>() * v).norm(), 1e-7);
    const Eigen::Matrix<double, 6, 1> jdv = (dp.frames[0].J * v - dm.frames[0].J * v) / (2 * h);
    EXPECT_LT((jdv - d.frames[0].Jdot_v).norm(), 1e-6 * std::max(1.0, jdv.norm()));
    EXPECT_LT(((dp.com - dm.com) / (2 * h) - d.J_com * v).norm(), 1e-7);
    const Eigen::Vector3d cdv = (dp.J_com * v - dm.J_com * v) / (2 * h);
    EXPECT_LT((cdv - d.com_Jdot_v).norm(), 1e-6 * std::max(1.0, cdv.norm()));
  }
}

// The angular momentum from the mass matrix's base rows (wholebody/momentum.hpp) against
// its definition, summed link by link through the frame Jacobians at each link's centre
// of mass: L_p = Σ R I Rᵀ ω + m (c − p) × ċ. Two paths through the kernel (A's composite
// inertias against the Jacobians); they agree to rounding: 1e-10 relative.
TEST(DynamicsModel, AngularMomentumFromTheBaseRowsIsTheSumOverTheLinks) {
  model::DynamicsOptions o;
  o.base = model::BaseMode::Floating;
  DynamicsModel m(draco(), o);
  std::vector<int> links;
  for (size_t i = 0; i < draco().links.size(); ++i)
    if (draco().links[i].mass_kg > 0) {
      m.add_frame({draco().links[i].name, draco().links[i].com_m});
      links.push_back(static_cast<int>(i));
    }
  wholebody::ModelData d = m.make_data();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd q, v;
  for (int trial = 0; trial < 5; ++trial) {
    random_state(m.layout(), rng, q, v);
    q.head<4>() = Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized();  // any unit quaternion (w x y z)
    q.segment<3>(4) = Eigen::Vector3d(u(rng), u(rng), 1.0 + u(rng));
    for (int k = 0; k < 6; ++k) v[k] = u(rng);
    m.update(q, v, d);
    const Eigen::Vector3d p(u(rng), u(rng), 0.0);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double mass = 0;
    for (size_t f = 0; f < links.size(); ++f) {
      const model::Link& link = draco().links[static_cast<size_t>(links[f])];
      const Eigen::Matrix3d R = d.frames[f].X_WF.rotation();
      const Eigen::Vector3d w = d.frames[f].J.topRows<3>() * v, c_dot = d.frames[f].J.bottomRows<3>() * v;
      sum += R * link.inertia_kgm2 * R.transpose() * w + link.mass_kg * (d.frames[f].X_WF.translation() - p).cross(c_dot);
      mass += link.mass_kg;
    }
    const Eigen::Vector3d L = wholebody::angular_momentum_about(d, p);
    EXPECT_LT((L - sum).norm(), 1e-10 * std::max(1.0, sum.norm())) << L.transpose() << " vs " << sum.transpose();
    const Eigen::Vector2d pendulum = wholebody::contact_pendulum_velocity(d, p, 0.8);
    EXPECT_NEAR(pendulum.x(), sum.y() / (mass * 0.8), 1e-10 * std::max(1.0, sum.norm()));
    EXPECT_NEAR(pendulum.y(), -sum.x() / (mass * 0.8), 1e-10 * std::max(1.0, sum.norm()));
  }
}

// A joint's armature (model::Joint::armature, the plant adds it to the same diagonal) is
// on its diagonal of the controller's mass matrix: A with 0.55 kg m² on the left ankle
// and 0.3 on the right knee less A without is exactly those two entries (to 1e-12, the
// rounding of one addition); the bias and the kinematics are unchanged.
TEST(DynamicsModel, TheArmatureIsOnItsJointsDiagonal) {
  model::RobotDescription geared = draco();
  geared.joints[static_cast<size_t>(geared.joint_index("l_ankle"))].armature = 0.55;
  geared.joints[static_cast<size_t>(geared.joint_index("r_knee"))].armature = 0.3;
  DynamicsModel plain(draco(), table(1.3)), with(geared, table(1.3));
  wholebody::ModelData a = plain.make_data(), b = with.make_data();
  std::mt19937 rng(5);
  Eigen::VectorXd q, v;
  random_state(plain.layout(), rng, q, v);
  plain.update(q, v, a);
  with.update(q, v, b);
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(10, 10);
  const auto& l = plain.layout();
  expected(l.joints[static_cast<size_t>(l.joint_index("l_ankle"))].v_index, l.joints[static_cast<size_t>(l.joint_index("l_ankle"))].v_index) = 0.55;
  expected(l.joints[static_cast<size_t>(l.joint_index("r_knee"))].v_index, l.joints[static_cast<size_t>(l.joint_index("r_knee"))].v_index) = 0.3;
  EXPECT_LT((b.A - a.A - expected).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(b.bg, a.bg);
  EXPECT_EQ(b.com, a.com);
}

}  // namespace
}  // namespace dmbd::control
