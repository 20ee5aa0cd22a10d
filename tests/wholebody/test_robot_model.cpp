// The hand-derived test arms (two_link_arm.hpp) checked against themselves before they
// judge the controllers: the tip against the textbook's forward kinematics, Jacobians
// and J̇v against finite differences of the pose, the textbook A, b, g against the Kane
// sums of the n-link arm, b against the Christoffel form, g against the potential's
// gradient, and energy conservation of the passive arm. Also RobotModel's shared parts
// (make_data's sizes, Layout::joint_index, frame registration).
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "arm_fixtures.hpp"
#include "two_link_arm.hpp"

namespace dmbd::wholebody::testing {
namespace {

// Central differences with step kStep: truncation h²/6 |f'''| ≈ 2e-11 |f'''| and rounding
// ε |f| / h ≈ 2e-11 for the O(1) quantities here (metres, radians, kg m²); |f'''| along
// the test velocities (|v| ≤ 2 rad/s) is at most ~10, so 1e-7 leaves a margin of > 100.
constexpr double kStep = 1e-5;
constexpr double kFiniteDifferenceTol = 1e-7;

// The arms with frames: the tip of the last link (frame 0), the end of link 1 (frame 1),
// an off-axis point of the last link (frame 2: y and z offsets exercise the rotation).
std::unique_ptr<PlanarArm> with_frames(std::unique_ptr<PlanarArm> arm) {
  const int n = arm->size();
  const std::string last = "link" + std::to_string(n);
  arm->add_frame({last, Eigen::Vector3d(arm->link(n - 1).length, 0, 0)});
  arm->add_frame({"link1", Eigen::Vector3d(arm->link(0).length, 0, 0)});
  arm->add_frame({last, Eigen::Vector3d(0.1, 0.05, -0.07)});
  return arm;
}

std::vector<std::unique_ptr<PlanarArm>> arms() {
  std::vector<std::unique_ptr<PlanarArm>> a;
  a.push_back(with_frames(std::make_unique<TwoLinkArm>(two_link_arm())));
  a.push_back(with_frames(std::make_unique<PlanarArm>(three_link_arm())));
  return a;
}

// Random states of an n-link arm: angles in [-π, π], rates in [-2, 2] rad/s.
std::vector<std::pair<Eigen::VectorXd, Eigen::VectorXd>> states(int n) {
  std::mt19937 rng(7);
  std::vector<std::pair<Eigen::VectorXd, Eigen::VectorXd>> s;
  for (int k = 0; k < 6; ++k) s.emplace_back(uniform(rng, n, M_PI), uniform(rng, n, 2.0));
  return s;
}

Eigen::Vector3d rotation_vector(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

TEST(TwoLinkArm, TipMatchesTheTextbookForwardKinematics) {
  auto arm = with_frames(std::make_unique<TwoLinkArm>(two_link_arm()));
  const double l1 = arm->link(0).length, l2 = arm->link(1).length;
  for (const auto& [q, v] : states(2)) {
    const ModelData d = evaluate(*arm, q, v);
    const double s1 = std::sin(q[0]), c1 = std::cos(q[0]), s12 = std::sin(q[0] + q[1]), c12 = std::cos(q[0] + q[1]);
    const double w1 = v[0], w12 = v[0] + v[1];
    const FrameData& tip = d.frames[0];
    // (x, w = -z) = l1 (c1, s1) + l2 (c12, s12); its Jacobian and J̇v = ∂/∂t of J v.
    EXPECT_LT((tip.X_WF.translation() - Eigen::Vector3d(l1 * c1 + l2 * c12, 0, -(l1 * s1 + l2 * s12))).norm(), 1e-15);
    Eigen::Matrix<double, 6, 2> J;
    J << 0, 0, 1, 1, 0, 0, -(l1 * s1 + l2 * s12), -l2 * s12, 0, 0, -(l1 * c1 + l2 * c12), -l2 * c12;
    EXPECT_LT((tip.J - J).norm(), 1e-15) << tip.J;
    Eigen::Matrix<double, 6, 1> Jdot_v;
    Jdot_v << 0, 0, 0, -(l1 * c1 * w1 * w1 + l2 * c12 * w12 * w12), 0, l1 * s1 * w1 * w1 + l2 * s12 * w12 * w12;
    EXPECT_LT((tip.Jdot_v - Jdot_v).norm(), 1e-14) << tip.Jdot_v.transpose();
    EXPECT_LT((tip.X_WF.linear() - rotation_y(q[0] + q[1])).norm(), 1e-15);
  }
}

TEST(PlanarArms, FrameJacobianIsTheDerivativeOfThePose) {
  for (auto& arm : arms()) {
    const int n = arm->size();
    for (const auto& [q, v] : states(n)) {
      const ModelData d = evaluate(*arm, q, v);
      for (int j = 0; j < n; ++j) {
        const Eigen::VectorXd dq = kStep * Eigen::VectorXd::Unit(n, j);
        const ModelData p = evaluate(*arm, q + dq, v), m = evaluate(*arm, q - dq, v);
        for (size_t f = 0; f < d.frames.size(); ++f) {
          const Eigen::Vector3d lin = (p.frames[f].X_WF.translation() - m.frames[f].X_WF.translation()) / (2 * kStep);
          const Eigen::Vector3d ang =
              rotation_vector(p.frames[f].X_WF.linear() * m.frames[f].X_WF.linear().transpose()) / (2 * kStep);
          EXPECT_LT((d.frames[f].J.col(j).tail<3>() - lin).norm(), kFiniteDifferenceTol) << "frame " << f << " q" << j;
          EXPECT_LT((d.frames[f].J.col(j).head<3>() - ang).norm(), kFiniteDifferenceTol) << "frame " << f << " q" << j;
        }
      }
    }
  }
}

TEST(PlanarArms, JdotVIsTheDerivativeOfTheJacobianAlongV) {
  for (auto& arm : arms()) {
    for (const auto& [q, v] : states(arm->size())) {
      const ModelData d = evaluate(*arm, q, v);
      const ModelData p = evaluate(*arm, q + kStep * v, v), m = evaluate(*arm, q - kStep * v, v);
      for (size_t f = 0; f < d.frames.size(); ++f) {
        const Eigen::Matrix<double, 6, 1> fd = (p.frames[f].J - m.frames[f].J) * v / (2 * kStep);
        EXPECT_LT((d.frames[f].Jdot_v - fd).norm(), kFiniteDifferenceTol) << "frame " << f;
      }
      const Eigen::Vector3d fd_com = (p.J_com - m.J_com) * v / (2 * kStep);
      EXPECT_LT((d.com_Jdot_v - fd_com).norm(), kFiniteDifferenceTol);
      EXPECT_GT(d.com_Jdot_v.norm(), 1e-2);  // not vacuous
    }
  }
}

TEST(PlanarArms, ComJacobianIsTheDerivativeOfTheCom) {
  for (auto& arm : arms()) {
    const int n = arm->size();
    for (const auto& [q, v] : states(n)) {
      const ModelData d = evaluate(*arm, q, v);
      for (int j = 0; j < n; ++j) {
        const Eigen::VectorXd dq = kStep * Eigen::VectorXd::Unit(n, j);
        const Eigen::Vector3d fd = (evaluate(*arm, q + dq, v).com - evaluate(*arm, q - dq, v).com) / (2 * kStep);
        EXPECT_LT((d.J_com.col(j) - fd).norm(), kFiniteDifferenceTol) << "q" << j;
      }
    }
  }
  // Hand value: stretched along +x, the CoM is at Σ m_k x_k / M.
  auto arm = with_frames(std::make_unique<TwoLinkArm>(two_link_arm()));
  const ModelData d = evaluate(*arm, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero());
  const double x = (2.0 * 0.3 + 1.5 * (0.5 + 0.25)) / 3.5;
  EXPECT_LT((d.com - Eigen::Vector3d(x, 0, 0)).norm(), 1e-15);
}

TEST(PlanarArms, MassMatrixIsSymmetricPositiveDefinite) {
  for (auto& arm : arms()) {
    for (const auto& [q, v] : states(arm->size())) {
      const ModelData d = evaluate(*arm, q, v);
      EXPECT_LT((d.A - d.A.transpose()).norm(), 1e-15 * d.A.norm());
      const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(d.A).eigenvalues();
      // Positive definite: every eigenvalue positive (they are ~1e-2 to 1 kg m² here,
      // far above the ~1e-16 rounding of the decomposition) and Cholesky succeeds.
      EXPECT_GT(eig.minCoeff(), 1e-6) << eig.transpose();
      EXPECT_EQ(d.A.llt().info(), Eigen::Success);
    }
  }
}

TEST(TwoLinkArm, TextbookDynamicsMatchTheKaneSums) {
  // Two derivations of the same arm: TwoLinkArm's closed forms and PlanarArm's sums over
  // the links' CoM Jacobians. Both are exact: agreement to rounding.
  TwoLinkArm textbook = two_link_arm();
  PlanarArm kane({link_a(), link_b()});
  for (const auto& [q, v] : states(2)) {
    const ModelData a = evaluate(textbook, q, v), b = evaluate(kane, q, v);
    EXPECT_LT((a.A - b.A).norm(), 1e-14 * a.A.norm()) << a.A << "\n" << b.A;
    EXPECT_LT((a.g - b.g).norm(), 1e-14 * a.g.norm() + 1e-14);
    EXPECT_LT((a.bg - b.bg).norm(), 1e-13 * (a.bg.norm() + a.g.norm()));
  }
}

TEST(PlanarArms, CoriolisIsTheChristoffelForm) {
  // Lagrange: d/dt(A v) − ∂T/∂q = A v̇ + Ȧ v − ½ ∂(vᵀ A v)/∂q, so b = Ȧ v − ½ ∂(vᵀAv)/∂q.
  for (auto& arm : arms()) {
    const int n = arm->size();
    for (const auto& [q, v] : states(n)) {
      const ModelData d = evaluate(*arm, q, v);
      const Eigen::VectorXd b = d.bg - d.g;
      const Eigen::MatrixXd A_dot =
          (evaluate(*arm, q + kStep * v, v).A - evaluate(*arm, q - kStep * v, v).A) / (2 * kStep);
      Eigen::VectorXd dT(n);
      for (int i = 0; i < n; ++i) {
        const Eigen::VectorXd dq = kStep * Eigen::VectorXd::Unit(n, i);
        dT[i] = v.dot((evaluate(*arm, q + dq, v).A - evaluate(*arm, q - dq, v).A) * v) / (2 * kStep);
      }
      const Eigen::VectorXd christoffel = A_dot * v - 0.5 * dT;
      EXPECT_LT((b - christoffel).norm(), kFiniteDifferenceTol) << b.transpose() << " vs " << christoffel.transpose();
      EXPECT_GT(b.norm(), 1e-2);  // not vacuous
      // The energy identity: vᵀ b = ½ vᵀ Ȧ v (Ȧ − 2C skew), so d/dt(T + V) = vᵀ τ.
      EXPECT_NEAR(v.dot(b), 0.5 * v.dot(A_dot * v), kFiniteDifferenceTol);
    }
  }
}

TEST(PlanarArms, GravityIsTheGradientOfThePotential) {
  // V = M G z_com.
  for (auto& arm : arms()) {
    const int n = arm->size();
    const double MG = arm->total_mass() * kGravity;
    for (const auto& [q, v] : states(n)) {
      const ModelData d = evaluate(*arm, q, v);
      for (int i = 0; i < n; ++i) {
        const Eigen::VectorXd dq = kStep * Eigen::VectorXd::Unit(n, i);
        const double dV = MG * (evaluate(*arm, q + dq, v).com.z() - evaluate(*arm, q - dq, v).com.z()) / (2 * kStep);
        // V is O(10 J): rounding εV/h ≈ 2e-10; 1e-6 leaves a margin of > 100.
        EXPECT_NEAR(d.g[i], dV, 1e-6) << "q" << i;
      }
    }
  }
}

TEST(PlanarArms, PassiveArmConservesEnergy) {
  // τ = 0: E = ½ vᵀ A v + M G z_com is constant. RK4 at 1 ms on a motion of ~5 rad/s:
  // (ω dt)⁴ ≈ 1e-9 relative per unit time; a wrong sign or factor in b or g gives O(1).
  auto arm = with_frames(std::make_unique<PlanarArm>(three_link_arm()));
  auto energy = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
    const ModelData d = evaluate(*arm, q, v);
    return 0.5 * v.dot(d.A * v) + arm->total_mass() * kGravity * d.com.z();
  };
  Eigen::VectorXd q = Eigen::Vector3d(0.3, -0.5, 0.8), v = Eigen::Vector3d(1.0, -1.0, 2.0);
  const double E0 = energy(q, v);
  const TorqueLaw passive = [](double, const ModelData& d) { return Eigen::VectorXd::Zero(d.v.size()); };
  double drift = 0.0, travel = 0.0;
  for (int k = 0; k < 1000; ++k) {
    const Eigen::VectorXd q_prev = q;
    rk4_step(*arm, passive, 1e-3 * k, 1e-3, q, v);
    travel += (q - q_prev).norm();
    drift = std::max(drift, std::abs(energy(q, v) - E0));
  }
  EXPECT_LT(drift, 1e-7 * std::abs(E0) + 1e-7) << "E0 " << E0;
  EXPECT_GT(travel, 1.0);  // the arm did move
}

TEST(RobotModel, MakeDataSizesEveryQuantity) {
  auto arm = with_frames(std::make_unique<PlanarArm>(three_link_arm()));
  const ModelData d = arm->make_data();
  EXPECT_EQ(d.q.size(), 3);
  EXPECT_EQ(d.v.size(), 3);
  EXPECT_EQ(d.A.rows(), 3);
  EXPECT_EQ(d.A.cols(), 3);
  EXPECT_EQ(d.bg.size(), 3);
  EXPECT_EQ(d.g.size(), 3);
  ASSERT_EQ(d.frames.size(), 3u);
  EXPECT_EQ(d.frames[2].J.cols(), 3);
  EXPECT_EQ(d.J_com.cols(), 3);
}

TEST(RobotModel, FramesAndJointsByName) {
  PlanarArm arm = three_link_arm();
  EXPECT_EQ(arm.add_frame({"link2", Eigen::Vector3d::Zero()}), 0);
  EXPECT_EQ(arm.add_frame({"link3", Eigen::Vector3d::Zero()}), 1);
  EXPECT_THROW(arm.add_frame({"link4", Eigen::Vector3d::Zero()}), InputError);
  EXPECT_EQ(arm.num_frames(), 2);
  EXPECT_EQ(arm.layout().joint_index("joint1"), 0);
  EXPECT_EQ(arm.layout().joint_index("joint3"), 2);
  EXPECT_EQ(arm.layout().joint_index("elbow"), -1);
}

}  // namespace
}  // namespace dmbd::wholebody::testing
