// Options of the balancing pieces whose effect needs a floating-base robot, on DRACO's
// model (control::DynamicsModel over the URDF), standing in double support with one point
// contact at each foot's centre (the set-up of tests/sim/test_wbc_standing.cpp):
// WbcQpParams::w_qdd_base (a negative value is the default weight, bit for bit; a small
// one puts the QP's correction of an inconsistent base acceleration into the base
// rather than the joints) and PointTask relative to a frame (the foot from the torso:
// no base-translation columns, the difference of two point tasks).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "draco_feet.hpp"

#include "dmbd/model/robot_description.hpp"
#include "dmbd/control/dynamics_model.hpp"
#include "dmbd/wholebody/task.hpp"
#include "dmbd/wholebody/wbc_qp.hpp"

namespace dmbd::wholebody::testing {
namespace {

constexpr int kNv = 16;  // 6 base + 10 joints

using sim::test::collision_centre;

// Knees bent (hip −0.3, knee 0.6, ankle −0.3 rad on both legs), base 1 m up, at rest
// unless a base velocity is given.
struct Standing {
  model::RobotDescription robot = model::load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf");
  control::DynamicsModel model{robot, model::DynamicsOptions{}};
  int left = model.add_frame({"l_foot", collision_centre(robot, "l_foot")});
  int right = model.add_frame({"r_foot", collision_centre(robot, "r_foot")});
  int torso = model.add_frame({"torso", Eigen::Vector3d::Zero()});
  ModelData data = model.make_data();
  Eigen::MatrixXd J_c = Eigen::MatrixXd::Zero(6, kNv);
  Eigen::VectorXd Jc_dot_v = Eigen::VectorXd::Zero(6);

  explicit Standing(const Eigen::VectorXd& v = Eigen::VectorXd::Zero(kNv)) {
    Eigen::VectorXd q = model.dynamics().neutral_configuration();
    for (const auto& [j, a] : std::vector<std::pair<const char*, double>>{
             {"l_hip_pitch", -0.3}, {"l_knee", 0.6}, {"l_ankle", -0.3}, {"r_hip_pitch", -0.3}, {"r_knee", 0.6}, {"r_ankle", -0.3}})
      q[model.layout().joints[static_cast<size_t>(model.layout().joint_index(j))].q_index] = a;
    q[6] = 1.0;
    model.update(q, v, data);
    J_c.topRows(3) = data.frames[static_cast<size_t>(left)].J.bottomRows(3);
    J_c.bottomRows(3) = data.frames[static_cast<size_t>(right)].J.bottomRows(3);
    Jc_dot_v.head(3) = data.frames[static_cast<size_t>(left)].Jdot_v.tail(3);
    Jc_dot_v.tail(3) = data.frames[static_cast<size_t>(right)].Jdot_v.tail(3);
  }
};

struct Solution {
  Eigen::VectorXd qdd, forces, tau;
};

Solution solve(const Standing& s, const WbcQpParams& params, const Eigen::VectorXd& qdd_cmd) {
  WbcQp wbc(s.model.layout(), 2, params);
  const ContactSetting stance[2] = {};
  EXPECT_EQ(wbc.solve(s.data, s.J_c, s.Jc_dot_v, qdd_cmd, stance), QpStatus::Optimal);
  return {wbc.qdd(), wbc.forces(), wbc.tau()};
}

// A q̈_cmd the feet cannot follow: the base accelerating forwards at 1 m/s² (v index 3)
// with the joints still, which would drag both planted feet along.
Eigen::VectorXd base_pushed_forwards() { return Eigen::VectorXd::Unit(kNv, 3); }

// w_qdd_base < 0 is "use w_qdd": the same solution, bit for bit, as parameters that never
// mention it (the cost is the same matrix), on a q̈_cmd that makes the QP work.
TEST(WbcQpBaseWeight, NegativeIsTheDefaultWeight) {
  const Standing s;
  WbcQpParams minus_one;
  minus_one.w_qdd_base = -1.0;
  const Solution a = solve(s, minus_one, base_pushed_forwards()), b = solve(s, WbcQpParams{}, base_pushed_forwards());
  EXPECT_EQ(a.qdd, b.qdd);
  EXPECT_EQ(a.forces, b.forces);
  EXPECT_EQ(a.tau, b.tau);
  // ... and w_qdd_base = w_qdd is the same cost as well (1e-12 relative: the same G).
  WbcQpParams equal;
  equal.w_qdd_base = equal.w_qdd;
  const Solution c = solve(s, equal, base_pushed_forwards());
  EXPECT_LT((c.qdd - b.qdd).norm(), 1e-12 * b.qdd.norm());
  EXPECT_LT((c.tau - b.tau).norm(), 1e-12 * b.tau.norm());
  // A weight of its own does change the solution (the option is wired): measured 0.032.
  WbcQpParams other;
  other.w_qdd_base = 1.0;
  EXPECT_GT((solve(s, other, base_pushed_forwards()).qdd - b.qdd).norm(), 1e-3);
}

// q̈_cmd pushes the base forwards at 1 m/s² (v index 3) with the joints still: that
// would drag both planted feet along (slack weight 1000), so the QP must undo it, in the
// base translation or by moving the joints. With w_qdd_base = 1 (100 times below w_qdd)
// the joints' |Δq̈| is smaller than with the default weights, and the push's own share
// of it (the joints' q̈ with the push less without it) nearly vanishes.
// Measured, default → w_qdd_base = 1:
//   joints' |Δq̈|                        0.148 → 0.140 rad/s²
//   the push's share, |q̈_j(push) − q̈_j(0)|   0.0437 → 0.00044 rad/s²
//   base translation Δq̈_x                −0.679 → −0.681 m/s²
// Most of the joints' Δq̈ is there without the push (0.136 rad/s²): with the authors'
// force weights the robot pitches and sinks a little rather than carry all its weight. The push itself is undone mostly in
// the base even with the default weights (keeping it would need ~m · 1 m/s² of friction,
// whose cost w_t F² outweighs w_qdd Δq̈²).
TEST(WbcQpBaseWeight, SmallBaseWeightPutsTheCorrectionIntoTheBase) {
  const Standing s;
  const Eigen::VectorXd push = base_pushed_forwards(), none = Eigen::VectorXd::Zero(kNv);
  WbcQpParams small;
  small.w_qdd_base = 1.0;
  const Solution d = solve(s, WbcQpParams{}, push), b = solve(s, small, push);
  const double joints_default = (d.qdd - push).tail(10).norm(), joints_small = (b.qdd - push).tail(10).norm();
  const double share_default = (d.qdd - solve(s, WbcQpParams{}, none).qdd).tail(10).norm();
  const double share_small = (b.qdd - solve(s, small, none).qdd).tail(10).norm();
  std::printf("joints |dqdd| %.4g -> %.4g, the push's share %.4g -> %.4g rad/s^2, base dqdd_x %.4g -> %.4g m/s^2\n",
              joints_default, joints_small, share_default, share_small, d.qdd[3] - 1.0, b.qdd[3] - 1.0);
  EXPECT_LT(joints_small, joints_default);
  EXPECT_GT(share_default, 0.01);                 // the default weights do move the joints for the push
  EXPECT_LT(share_small, 0.05 * share_default);  // ... the small base weight hardly
  EXPECT_LT(b.qdd[3] - 1.0, -0.5);               // the push undone in the base translation
  // The feet stay planted as without the push: |J_c q̈ + J̇_c v| (the slack) measured
  // 0.048 m/s² by default and 0.051 with w_qdd_base = 1 (0.049 and 0.051 with q̈_cmd = 0).
  EXPECT_LT((s.J_c * b.qdd + s.Jc_dot_v).norm(), 0.1);
  EXPECT_LT((s.J_c * d.qdd + s.Jc_dot_v).norm(), 0.1);
}

// The foot from the torso (PointTask(foot, nv, torso)): x = p_F − p_T and J = J_F − J_T,
// J̇v = J̇_F v − J̇_T v against two plain point tasks (the same subtractions: 1e-15), on
// a moving robot (base and joints); its base-translation columns are zero (a translation
// of the whole robot moves foot and torso alike: 1e-15), so only the joints and the
// base's rotation can meet it.
TEST(PointTaskRelative, FootFromTheTorsoOnDraco) {
  Eigen::VectorXd v(kNv);
  v << 0.2, -0.3, 0.1, 0.5, -0.2, 0.3, 0.4, -0.6, 0.8, 0.3, -0.5, -0.2, 0.7, -0.4, 0.6, 0.1;
  const Standing s(v);
  PointTask relative(s.left, kNv, s.torso), foot(s.left, kNv), torso(s.torso, kNv);
  for (PointTask* t : {&relative, &foot, &torso}) t->update(s.data);
  EXPECT_LT((relative.position() - (foot.position() - torso.position())).norm(), 1e-15);
  EXPECT_LT((relative.jacobian() - (foot.jacobian() - torso.jacobian())).norm(), 1e-15);
  EXPECT_LT((relative.jacobian_dot_v() - (foot.jacobian_dot_v() - torso.jacobian_dot_v())).norm(), 1e-15);
  EXPECT_LT(relative.jacobian().middleCols(3, 3).norm(), 1e-15);
  EXPECT_GT(foot.jacobian().middleCols(3, 3).norm(), 1.0);  // identity for the plain task
  EXPECT_GT(relative.jacobian().leftCols(3).norm(), 0.1);  // a base rotation does move the foot from the torso
  EXPECT_GT(relative.jacobian_dot_v().norm(), 1e-3);  // a J̇v that is not trivially zero
}

}  // namespace
}  // namespace dmbd::wholebody::testing
