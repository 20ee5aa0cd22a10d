#include "dmbd_standing.hpp"

#include "dmbd/model/error.hpp"
#include "dmbd/model/plant.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace dmbd::bench {

namespace {

using dmbd::model::Plant;

double tilt_rad(const Plant& p) { return std::acos(std::clamp(p.base_pose().linear()(2, 2), -1.0, 1.0)); }

// One control period: read the joints, compute the task's command, hold it.
void control(Plant& p, const std::vector<dmbd::model::ActuatorParams>* acts, const StandingTask& t,
             std::vector<double>& q, std::vector<double>& qd, Eigen::VectorXd& u) {
  const Eigen::VectorXd qa = p.joint_positions(), va = p.joint_velocities();
  if (!acts) {
    q.assign(qa.data(), qa.data() + qa.size());
    qd.assign(va.data(), va.data() + va.size());
    const std::vector<double> tau = standing_torques(p.joint_names(), q, qd, t);
    u = Eigen::Map<const Eigen::VectorXd>(tau.data(), static_cast<Eigen::Index>(tau.size()));
    p.set_joint_torques(u);
    return;
  }
  for (int a = 0; a < p.num_actuators(); ++a) {
    const int j = p.joint_index(p.actuator(a).joint);
    q[static_cast<std::size_t>(a)] = qa[j];
    qd[static_cast<std::size_t>(a)] = va[j];
  }
  const std::vector<double> i = standing_currents(*acts, q, qd, t);
  u = Eigen::Map<const Eigen::VectorXd>(i.data(), static_cast<Eigen::Index>(i.size()));
  p.set_currents(u);
}

StandingResult run(const dmbd::model::RobotDescription& robot, const std::vector<dmbd::model::ActuatorParams>* acts,
                   const StandingTask& t, double step_s) {
  dmbd::model::PlantOptions o;
  o.integration = dmbd::model::Integration::Fixed;
  o.step_s = step_s;
  o.gravity_m_s2 = t.gravity_mps2;
  o.contact_params.friction = t.friction;
  if (acts) o.actuators = *acts;
  Plant p(robot, o);
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation().z() = standing_root_height_m(robot);
  p.set_base_pose(X);
  const double z0 = X.translation().z();
  std::vector<double> q(static_cast<std::size_t>(acts ? p.num_actuators() : p.num_joints())), qd = q;
  Eigen::VectorXd u;
  StandingResult r;
  const long periods = std::lround(t.duration_s / t.control_period_s);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    for (long k = 1; k <= periods; ++k) {
      control(p, acts, t, q, qd, u);
      p.advance_to(static_cast<double>(k) * t.control_period_s);
      r.max_tilt_rad = std::max(r.max_tilt_rad, tilt_rad(p));
    }
  } catch (const dmbd::model::ModelError&) {
    r.diverged = true;
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.sim_s = p.time();
  r.rtf = r.sim_s / r.wall_s;
  r.steps = p.integrator_steps();
  r.drop_m = z0 - p.base_pose().translation().z();
  judge_standing(r, t);
  return r;
}

}  // namespace

StandingResult run_dmbd_standing_1ms(const dmbd::model::RobotDescription& robot,
                                     const std::vector<dmbd::model::ActuatorParams>* actuators, const StandingTask& task) {
  return run(robot, actuators, task, 1e-3);
}

StandingResult run_dmbd_standing_05ms(const dmbd::model::RobotDescription& robot,
                                      const std::vector<dmbd::model::ActuatorParams>* actuators, const StandingTask& task) {
  return run(robot, actuators, task, 5e-4);
}

}  // namespace dmbd::bench
