// The whole-body QP solved in reduced variables (wholebody/wbc_qp.hpp: the base's Δq̈ and
// the contact slacks substituted from the equalities) against the problem as the header
// states it, z = [Δq̈, F, s] with its 6 + 3 n_c equalities, built here and solved by the
// same QpSolver. Same minimiser, so the same forces, accelerations and torques (1e-7
// relative), on DRACO's model in double support, in a swing (one foot F_max = 0, a small
// slack weight), with torque limits and friction cones active, over random commands.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "draco_feet.hpp"

#include "dmbd/control/dynamics_model.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/wholebody/qp.hpp"
#include "dmbd/wholebody/wbc_qp.hpp"

namespace dmbd::control {
namespace {

using wholebody::ContactSetting;
using wholebody::QpSolver;
using wholebody::QpStatus;

struct Robot {
  model::RobotDescription robot = model::load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf");
  DynamicsModel model{robot, model::DynamicsOptions{}};
  int feet[2] = {model.add_frame({"l_foot", sim::test::collision_centre(robot, "l_foot")}),
                 model.add_frame({"r_foot", sim::test::collision_centre(robot, "r_foot")})};
  wholebody::ModelData data = model.make_data();
  Eigen::MatrixXd J_c = Eigen::MatrixXd::Zero(6, 16);
  Eigen::VectorXd Jc_dot_v = Eigen::VectorXd::Zero(6);

  void update(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
    model.update(q, v, data);
    for (int c = 0; c < 2; ++c) {
      const auto& f = data.frames[static_cast<size_t>(feet[c])];
      J_c.middleRows(3 * c, 3) = f.J.bottomRows(3);
      Jc_dot_v.segment(3 * c, 3) = f.Jdot_v.tail(3);
    }
  }
};

struct FullSolution {
  QpStatus status;
  Eigen::VectorXd qdd, forces, tau;
};

// The problem of wbc_qp.hpp's header, z = [Δq̈ (16), F (6), s (6)], as written there.
FullSolution solve_full(const Robot& r, const wholebody::WbcQpParams& p, const Eigen::VectorXd& qdd_cmd,
                        const ContactSetting* c) {
  const int nv = 16, nj = 10, n = nv + 12;
  const Eigen::MatrixXd& A = r.data.A;
  const Eigen::VectorXd rhs = A * qdd_cmd + r.data.bg;
  Eigen::MatrixXd AJ(nv, nv + 6);
  AJ << A, -r.J_c.transpose();
  Eigen::VectorXd g = Eigen::VectorXd::Constant(n, 2.0 * p.w_qdd);
  if (p.w_qdd_base >= 0) g.segment(3, 3).setConstant(2.0 * p.w_qdd_base);
  for (int k = 0; k < 2; ++k) {
    g.segment(nv + 3 * k, 3) << 2.0 * c[k].w_tangential, 2.0 * c[k].w_tangential, 2.0 * c[k].w_normal;
    g.segment(nv + 6 + 3 * k, 3).setConstant(2.0 * c[k].w_slack);
  }
  Eigen::MatrixXd C_eq = Eigen::MatrixXd::Zero(12, n);
  Eigen::VectorXd b_eq(12);
  C_eq.topLeftCorner(6, nv + 6) = AJ.topRows(6);
  b_eq.head(6) = -rhs.head(6);
  C_eq.block(6, 0, 6, nv) = r.J_c;
  C_eq.block(6, nv + 6, 6, 6) = -Eigen::MatrixXd::Identity(6, 6);
  b_eq.tail(6) = -r.Jc_dot_v - r.J_c * qdd_cmd;
  Eigen::MatrixXd C_in = Eigen::MatrixXd::Zero(12 + 2 * nj, n);
  Eigen::VectorXd b_in = Eigen::VectorXd::Zero(12 + 2 * nj);
  for (int k = 0; k < 2; ++k) {
    const int f = nv + 3 * k, row = 6 * k;
    C_in(row, f + 2) = 1;
    C_in(row + 1, f + 2) = -1;
    b_in[row + 1] = -c[k].f_max_N;
    for (int d = 0; d < 2; ++d) {
      C_in(row + 2 + 2 * d, f + 2) = p.mu;
      C_in(row + 2 + 2 * d, f + d) = -1;
      C_in(row + 3 + 2 * d, f + 2) = p.mu;
      C_in(row + 3 + 2 * d, f + d) = 1;
    }
  }
  C_in.block(12, 0, nj, nv + 6) = AJ.bottomRows(nj);
  C_in.block(12 + nj, 0, nj, nv + 6) = -AJ.bottomRows(nj);
  Eigen::VectorXd limit(nj);
  for (int j = 0; j < nj; ++j)
    limit[j] = std::min(p.torque_limit_Nm, r.model.layout().joints[static_cast<size_t>(j)].limits.effort_Nm);
  b_in.segment(12, nj) = -rhs.tail(nj) - limit;
  b_in.segment(12 + nj, nj) = rhs.tail(nj) - limit;
  QpSolver qp(n, 12, 12 + 2 * nj);
  FullSolution out{qp.solve(g.asDiagonal().toDenseMatrix(), Eigen::VectorXd::Zero(n), C_eq, b_eq, C_in, b_in), {}, {}, {}};
  if (out.status != QpStatus::Optimal) return out;
  out.qdd = qdd_cmd + qp.x().head(nv);
  out.forces = qp.x().segment(nv, 6);
  out.tau = (AJ * qp.x().head(nv + 6) + rhs).tail(nj);
  return out;
}

void expect_same(const Eigen::VectorXd& reduced, const Eigen::VectorXd& full, const char* what, int trial) {
  const double scale = std::max(1.0, full.cwiseAbs().maxCoeff());
  EXPECT_LE((reduced - full).cwiseAbs().maxCoeff(), 1e-7 * scale)
      << what << " (trial " << trial << ")\nreduced " << reduced.transpose() << "\nfull    " << full.transpose();
}

TEST(WbcQpReducedForm, SameSolutionAsTheProblemWithItsEqualities) {
  Robot r;
  std::mt19937 rng(27);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int torque_bound = 0, cone_or_normal_bound = 0;
  for (int trial = 0; trial < 40; ++trial) {
    Eigen::VectorXd q = r.model.dynamics().neutral_configuration();
    for (int i = 7; i < q.size(); ++i) q[i] = 0.4 * u(rng);
    q[6] = 1.0;
    Eigen::VectorXd v(16);
    for (int i = 0; i < 16; ++i) v[i] = u(rng);
    r.update(q, v);
    Eigen::VectorXd qdd_cmd(16);
    for (int i = 0; i < 16; ++i) qdd_cmd[i] = 20.0 * u(rng);
    wholebody::WbcQpParams p;
    p.w_qdd = trial % 2 ? 1000.0 : 100.0;
    p.w_qdd_base = trial % 3 == 0 ? 10.0 : -1.0;
    p.torque_limit_Nm = trial % 4 == 0 ? 20.0 : 100.0;  // some trials with torques at their bounds
    ContactSetting c[2];
    if (trial % 5 == 1) c[1] = {0.0, 1.0, 0.01, 0.001};  // the right foot in the air
    wholebody::WbcQp wbc(r.model.layout(), 2, p);
    const QpStatus reduced = wbc.solve(r.data, r.J_c, r.Jc_dot_v, qdd_cmd, c);
    const FullSolution full = solve_full(r, p, qdd_cmd, c);
    ASSERT_EQ(reduced, full.status) << "trial " << trial;
    if (full.status != QpStatus::Optimal) continue;
    expect_same(wbc.forces(), full.forces, "forces", trial);
    expect_same(wbc.qdd(), full.qdd, "q̈", trial);
    expect_same(wbc.tau(), full.tau, "τ", trial);
    torque_bound += (full.tau.cwiseAbs().array() > std::min(p.torque_limit_Nm, 100.0) - 1e-6).any();
    for (int k = 0; k < 2; ++k) {
      const Eigen::Vector3d f = full.forces.segment<3>(3 * k);
      cone_or_normal_bound += f.z() > c[k].f_max_N - 1e-6 || f.head<2>().cwiseAbs().maxCoeff() > p.mu * f.z() - 1e-6;
    }
  }
  std::printf("trials with a torque at its bound: %d; contacts on a cone face or at F_max: %d\n", torque_bound, cone_or_normal_bound);
  EXPECT_GE(torque_bound, 3);          // the comparison covers active torque rows
  EXPECT_GE(cone_or_normal_bound, 3);  // and active force rows
}

}  // namespace
}  // namespace dmbd::control
