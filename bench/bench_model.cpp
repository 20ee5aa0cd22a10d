// DRACO's model: time to load the URDF (with meshes) and build the plant; one controller
// update of RobotDynamics (BM_ControllerUpdate: set the state, A, b + g, both feet's frame
// Jacobians and Jdot v, the CoM Jacobian; issue 12's goal <= 30 us); and the real-time
// factor (simulated seconds per wall second, counter "rtf") of
//   - the fixed-base robot swinging freely (no contact, no actuators),
//   - the floating robot standing on its feet under a 1 kHz joint PD (ideal torques),
//   - the floating robot standing with its ten actuators driven by currents,
// each with the accurate (error-controlled) integrator and the fixed 0.5 ms step.
// The side-by-side comparison with MuJoCo is bench_standing.
#include "dmbd/model/dynamics.hpp"
#include "dmbd/model/plant.hpp"

#include <benchmark/benchmark.h>

#include <chrono>
#include <string>

namespace {

using namespace dmbd::model;

const RobotDescription& draco() {
  static const RobotDescription r = load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf");
  return r;
}

void BM_LoadUrdfWithMeshes(benchmark::State& st) {
  for (auto _ : st) benchmark::DoNotOptimize(load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf"));
}
BENCHMARK(BM_LoadUrdfWithMeshes)->Unit(benchmark::kMillisecond);

void BM_BuildPlantWithActuators(benchmark::State& st) {
  PlantOptions o;
  o.actuators = load_actuators(DMBD_ROBOTS_DIR "/draco/actuators.yaml");
  for (auto _ : st) {
    Plant p(draco(), o);
    benchmark::DoNotOptimize(p.total_mass_kg());
  }
}
BENCHMARK(BM_BuildPlantWithActuators)->Unit(benchmark::kMillisecond);

// Runs `sim_s` seconds at a 1 kHz control rate; reports the real-time factor.
template <class Control>
void run(benchmark::State& st, Plant& p, double sim_s, Control control) {
  double wall = 0, sim = 0;
  long long steps = 0;
  for (auto _ : st) {
    p.reset();
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 1; k <= static_cast<int>(sim_s * 1000); ++k) {
      control(p);
      p.advance_to(k * 1e-3);
    }
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    sim += sim_s;
    steps += p.integrator_steps();  // counted from reset()
  }
  st.counters["rtf"] = sim / wall;
  st.counters["steps_per_sim_s"] = static_cast<double>(steps) / sim;
}

void BM_ControllerUpdate(benchmark::State& st) {
  RobotDynamics d(draco());
  const int nv = d.nv();
  Eigen::VectorXd q = d.neutral_configuration(), v = Eigen::VectorXd::Constant(nv, 0.1), bg(nv);
  q[6] = 1.1;
  Eigen::MatrixXd A(nv, nv), Jl(6, nv), Jr(6, nv), Jc(3, nv);
  const int lf = d.link_index("l_foot"), rf = d.link_index("r_foot");
  double k = 0;
  for (auto _ : st) {
    q[8] = 1e-3 * (k += 1);  // a new state every update
    d.set_state(q, v);
    d.mass_matrix(A);
    d.coriolis_and_gravity(bg);
    d.frame_jacobian(lf, Eigen::Vector3d::Zero(), Jl);
    d.frame_jacobian(rf, Eigen::Vector3d::Zero(), Jr);
    benchmark::DoNotOptimize(d.frame_jacobian_dot_v(lf, Eigen::Vector3d::Zero()));
    benchmark::DoNotOptimize(d.frame_jacobian_dot_v(rf, Eigen::Vector3d::Zero()));
    d.com_jacobian(Jc);
    benchmark::DoNotOptimize(A.data());
    benchmark::DoNotOptimize(Jc.data());
  }
}
BENCHMARK(BM_ControllerUpdate)->Unit(benchmark::kMicrosecond);

PlantOptions with_mode(PlantOptions o, int fixed) {
  o.integration = fixed ? Integration::Fixed : Integration::Accurate;
  o.step_s = 5e-4;
  return o;
}

void BM_FixedBaseFreeSwing(benchmark::State& st) {
  PlantOptions o;
  o.base = BaseMode::Fixed;
  o.contact = false;
  Plant p(draco(), with_mode(o, static_cast<int>(st.range(0))));
  run(st, p, 1.0, [](Plant&) {});
}
BENCHMARK(BM_FixedBaseFreeSwing)->Arg(0)->Arg(1)->ArgName("fixed")->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_StandingJointPD(benchmark::State& st) {
  Plant p(draco(), with_mode(PlantOptions{}, static_cast<int>(st.range(0))));
  const Eigen::VectorXd q0 = Eigen::VectorXd::Zero(p.num_joints());
  Eigen::VectorXd kp = Eigen::VectorXd::Constant(10, 1500), kd = Eigen::VectorXd::Constant(10, 20);
  for (int j = 0; j < 10; ++j) {
    const std::string& n = p.joint_names()[static_cast<std::size_t>(j)];
    if (n.find("ankle") != std::string::npos) kp[j] = 800, kd[j] = 2;
    if (n.find("yaw") != std::string::npos) kd[j] = 5;  // as tests/model/test_plant_draco.cpp
  }
  run(st, p, 1.0, [&](Plant& pl) {
    pl.set_joint_torques(kp.cwiseProduct(q0 - pl.joint_positions()) - kd.cwiseProduct(pl.joint_velocities()));
  });
}
BENCHMARK(BM_StandingJointPD)->Arg(0)->Arg(1)->ArgName("fixed")->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_StandingActuators(benchmark::State& st) {
  PlantOptions o;
  o.actuators = load_actuators(DMBD_ROBOTS_DIR "/draco/actuators.yaml");
  Plant p(draco(), with_mode(o, static_cast<int>(st.range(0))));
  const Eigen::VectorXd q0 = Eigen::VectorXd::Zero(p.num_joints());
  Eigen::VectorXd cur(p.num_actuators());
  run(st, p, st.range(0) ? 2.0 : 0.2, [&](Plant& pl) {
    // Joint PD turned into currents through the linkage and the motor constant.
    const Eigen::VectorXd q = pl.joint_positions(), v = pl.joint_velocities();
    for (int a = 0; a < pl.num_actuators(); ++a) {
      const ActuatorParams& ap = pl.actuator(a);
      const int j = pl.joint_index(ap.joint);
      const double tau = 3000 * (q0[j] - q[j]) - 100 * v[j];
      cur[a] = tau / (ap.linkage.moment_arm_m(q[j]) * ap.force_per_amp_N_per_A());
    }
    pl.set_currents(cur);
  });
}
BENCHMARK(BM_StandingActuators)->Arg(0)->Arg(1)->ArgName("fixed")->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
