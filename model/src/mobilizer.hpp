#pragma once
// Internal to model/: the joint kinds the tree is built from (model/src/simbody_tree.cpp),
// each as Simbody defines its coordinates, so the tree kernel can realise poses and
// velocities without a Simbody State (realize(Position) and realize(Velocity) were 60 %
// of a DRACO controller update's model terms: pointer-heavy code over every body's cache
// entries, most of which the kernel never reads).
//
// A mobilizer connects frame F, fixed on the parent body P, to frame M, fixed on the
// body B: X_PB = X_PF X_FM(q) X_MB. In Simbody's conventions:
//   Weld    no q, no u; X_FM = identity.
//   Pin     q = angle about the shared z axis; u = qdot.
//   Slider  q = translation along F's x axis; u = qdot.
//   Free    q = [quaternion w x y z of R_FM, p_FM in F]; u = [w_FM in F, v_FM in F]
//           (the quaternion's rate is qdot = 1/2 [-e.w; e0 w + w x e], e = [e1 e2 e3]).
//   Planar  q = [angle about z, translation along F's x, along F's y]; u = qdot.
// tests/model/test_kernel_tree.cpp checks poses, velocities, bias accelerations and qdot
// against Simbody on a tree with every kind.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace dmbd::model::detail {

enum class MobilizerKind { Weld, Pin, Slider, Free, Planar };

struct Mobilizer {
  MobilizerKind kind = MobilizerKind::Weld;
  int first_q = 0, first_u = 0, nq = 0, nu = 0;
  Eigen::Matrix3d R_PF = Eigen::Matrix3d::Identity(), R_MB = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_PF = Eigen::Vector3d::Zero(), p_MB = Eigen::Vector3d::Zero();
};

// X_FM at the system's coordinates q (quaternions already unit).
void mobilizer_transform(const Mobilizer& mob, const Eigen::VectorXd& q, Eigen::Matrix3d& R_FM, Eigen::Vector3d& p_FM);

// Mobility i's hinge column in F: [angular velocity of M in F; velocity of M's origin in F]
// per unit u_i (constant for every kind above).
Eigen::Matrix<double, 6, 1> mobilizer_column(MobilizerKind kind, int i);

// The mobilizer's share of qdot = N(q) u.
void mobilizer_qdot(const Mobilizer& mob, const Eigen::VectorXd& q, const Eigen::Ref<const Eigen::VectorXd>& u,
                    Eigen::Ref<Eigen::VectorXd> qdot);

}  // namespace dmbd::model::detail
