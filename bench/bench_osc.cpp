// One evaluation of operational space control on DRACO fixed to the table (issue 14's
// osc_tick_us): the model's terms at the state (control::DynamicsModel over
// model::RobotDynamics), the point and posture tasks, and the law with its null-space
// posture (wholebody::OperationalSpaceControl), allocation-free.
// Anchors in the same run: the dynamics terms alone (the floor under any OSC), and the
// law written the textbook way with Eigen value expressions and dense inverses
// (τ = A J̄ (ẍ − J̇v) + b + g + Nᵀ A q̈₀, J̄ = A⁻¹Jᵀ(JA⁻¹Jᵀ)⁻¹), which allocates.
#include <benchmark/benchmark.h>

#include <Eigen/Dense>

#include "dmbd/model/robot_description.hpp"
#include "dmbd/control/dynamics_model.hpp"
#include "dmbd/wholebody/osc.hpp"
#include "dmbd/wholebody/task.hpp"

namespace {

using namespace dmbd;

struct Table {
  control::DynamicsModel model;
  wholebody::ModelData data;
  wholebody::PointTask task;
  wholebody::PostureTask posture;
  wholebody::OperationalSpaceControl osc;
  Eigen::VectorXd q, v, tau;

  static model::DynamicsOptions options() {
    model::DynamicsOptions o;
    o.base = model::BaseMode::Fixed;
    o.X_WB.translation().z() = 1.3;
    return o;
  }
  static std::vector<int> all(int n) {
    std::vector<int> j(static_cast<size_t>(n));
    for (int k = 0; k < n; ++k) j[static_cast<size_t>(k)] = k;
    return j;
  }
  Table()
      : model(model::load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf"), options()),
        task(model.add_frame({"l_foot", Eigen::Vector3d::Zero()}), model.layout().nv),
        posture(model.layout(), all(model.layout().nv)),
        osc(model.layout(), 3, model.layout().nv) {
    data = model.make_data();
    q = Eigen::VectorXd::Zero(model.layout().nq);
    v = Eigen::VectorXd::Constant(model.layout().nv, 0.3);
    tau = Eigen::VectorXd::Zero(model.layout().nv);
    for (const char* j : {"l_knee", "r_knee"}) q[model.layout().joints[static_cast<size_t>(model.layout().joint_index(j))].q_index] = 1.2;
    task.set_gains(1421.0, 75.4);
    posture.set_gains(158.0, 25.1);
    const Eigen::VectorXd z = Eigen::VectorXd::Zero(model.layout().nv);
    posture.set_reference(q, z, z);
    task.set_reference(Eigen::Vector3d(0.1, 0.17, 0.4), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  }
};

void BM_OscTick(benchmark::State& state) {
  Table t;
  for (auto _ : state) {
    t.model.update(t.q, t.v, t.data);
    t.task.update(t.data);
    t.posture.update(t.data);
    t.osc.compute(t.data, t.task, &t.posture, t.tau);
    benchmark::DoNotOptimize(t.tau.data());
  }
}
BENCHMARK(BM_OscTick);

void BM_DynamicsTermsOnly(benchmark::State& state) {
  Table t;
  for (auto _ : state) {
    t.model.update(t.q, t.v, t.data);
    benchmark::DoNotOptimize(t.data.A.data());
  }
}
BENCHMARK(BM_DynamicsTermsOnly);

void BM_OscTextbookEigen(benchmark::State& state) {
  Table t;
  for (auto _ : state) {
    t.model.update(t.q, t.v, t.data);
    t.task.update(t.data);
    t.posture.update(t.data);
    const Eigen::MatrixXd& A = t.data.A;
    const Eigen::MatrixXd& J = t.task.jacobian();
    const Eigen::MatrixXd Ainv = A.inverse();
    const Eigen::MatrixXd Lambda = (J * Ainv * J.transpose()).inverse();
    const Eigen::MatrixXd Jbar = Ainv * J.transpose() * Lambda;
    const Eigen::MatrixXd N = Eigen::MatrixXd::Identity(A.rows(), A.cols()) - Jbar * J;
    const Eigen::VectorXd tau = A * Jbar * (t.task.command() - t.task.jacobian_dot_v()) + t.data.bg +
                                N.transpose() * (A * t.posture.command());
    benchmark::DoNotOptimize(tau.data());
  }
}
BENCHMARK(BM_OscTextbookEigen);

// The dynamically consistent inverse alone, for the 3-row point task and the 10-row
// posture (the two the OSC forms per tick).
void BM_InverseOf(benchmark::State& state, bool posture) {
  Table t;
  t.model.update(t.q, t.v, t.data);
  t.task.update(t.data);
  const Eigen::MatrixXd& J = posture ? t.posture.jacobian() : t.task.jacobian();
  wholebody::DynamicallyConsistentInverse inv(static_cast<int>(J.rows()), t.model.layout().nv);
  for (auto _ : state) {
    inv.compute(t.data.A, J);
    benchmark::DoNotOptimize(inv.N().data());
  }
}
BENCHMARK_CAPTURE(BM_InverseOf, point_task, false);
BENCHMARK_CAPTURE(BM_InverseOf, posture, true);

}  // namespace

BENCHMARK_MAIN();
