// DRACO in Simbody: time to load the URDF (with meshes) and build the plant, and the
// real-time factor (simulated seconds per wall second, counter "rtf") of
//   - the fixed-base robot swinging freely (no contact, no actuators),
//   - the floating robot standing on its feet under a 1 kHz joint PD (ideal torques),
//   - the floating robot standing with its ten actuators driven by currents.
#include "dmbd/model/plant.hpp"

#include <benchmark/benchmark.h>

#include <chrono>
#include <string>

namespace {

using namespace dmbd::model;

const RobotDescription& draco() {
  static const RobotDescription r = load_urdf(DMBD_DRACO_DIR "/draco.urdf");
  return r;
}

void BM_LoadUrdfWithMeshes(benchmark::State& st) {
  for (auto _ : st) benchmark::DoNotOptimize(load_urdf(DMBD_DRACO_DIR "/draco.urdf"));
}
BENCHMARK(BM_LoadUrdfWithMeshes)->Unit(benchmark::kMillisecond);

void BM_BuildPlantWithActuators(benchmark::State& st) {
  PlantOptions o;
  o.actuators = draco_actuators();
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

void BM_FixedBaseFreeSwing(benchmark::State& st) {
  PlantOptions o;
  o.base = BaseMode::Fixed;
  o.contact = false;
  Plant p(draco(), o);
  run(st, p, 1.0, [](Plant&) {});
}
BENCHMARK(BM_FixedBaseFreeSwing)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_StandingJointPD(benchmark::State& st) {
  Plant p(draco(), PlantOptions{});
  const Eigen::VectorXd q0 = Eigen::VectorXd::Zero(p.num_joints());
  Eigen::VectorXd kp = Eigen::VectorXd::Constant(10, 1500), kd = Eigen::VectorXd::Constant(10, 20);
  for (int j = 0; j < 10; ++j)
    if (p.joint_names()[static_cast<std::size_t>(j)].find("ankle") != std::string::npos) kp[j] = 800, kd[j] = 2;
  run(st, p, 1.0, [&](Plant& pl) {
    pl.set_joint_torques(kp.cwiseProduct(q0 - pl.joint_positions()) - kd.cwiseProduct(pl.joint_velocities()));
  });
}
BENCHMARK(BM_StandingJointPD)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_StandingActuators(benchmark::State& st) {
  PlantOptions o;
  o.actuators = draco_actuators();
  Plant p(draco(), o);
  const Eigen::VectorXd q0 = Eigen::VectorXd::Zero(p.num_joints());
  Eigen::VectorXd cur(p.num_actuators());
  run(st, p, 0.2, [&](Plant& pl) {
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
BENCHMARK(BM_StandingActuators)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
