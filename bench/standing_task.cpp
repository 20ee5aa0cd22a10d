#include "standing_task.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace dmbd::bench {

using dmbd::model::ActuatorParams;
using dmbd::model::Geometry;
using dmbd::model::RobotDescription;

double standing_root_height_m(const RobotDescription& robot) {
  const auto X_WL = dmbd::model::default_pose_link_frames(robot);
  double lowest = std::numeric_limits<double>::infinity();
  for (std::size_t l = 0; l < robot.links.size(); ++l)
    for (const auto& s : robot.links[l].collisions)
      if (s.geometry.kind == Geometry::Kind::Sphere)
        lowest = std::min(lowest, (X_WL[l] * s.X_LG).translation().z() - s.geometry.radius_m);
  if (!(lowest < std::numeric_limits<double>::infinity()))
    throw std::runtime_error("standing task: robot '" + robot.name + "' has no collision sphere");
  return -lowest;
}

std::vector<double> standing_torques(const std::vector<std::string>& joints, const std::vector<double>& q,
                                     const std::vector<double>& qd, const StandingTask& t) {
  std::vector<double> tau(joints.size());
  for (std::size_t j = 0; j < joints.size(); ++j) {
    const bool ankle = joints[j].find("ankle") != std::string::npos;
    const double kp = ankle ? t.kp_ankle_Nm_per_rad : t.kp_Nm_per_rad;
    const double kd = ankle ? t.kd_ankle_Nms_per_rad : t.kd_Nms_per_rad;
    tau[j] = kp * (0 - q[j]) - kd * qd[j];
  }
  return tau;
}

std::vector<double> standing_currents(const std::vector<ActuatorParams>& actuators, const std::vector<double>& q,
                                      const std::vector<double>& qd, const StandingTask& t) {
  std::vector<double> i(actuators.size());
  for (std::size_t a = 0; a < actuators.size(); ++a) {
    const ActuatorParams& p = actuators[a];
    const double tau = t.kp_actuated_Nm_per_rad * (0 - q[a]) - t.kd_actuated_Nms_per_rad * qd[a];
    const double amps = tau / (p.k_tau_Nm_per_A * p.N_m_rad_per_m * p.linkage.moment_arm_m(q[a]));
    i[a] = std::clamp(amps, -p.current_limit_A, p.current_limit_A);
  }
  return i;
}

void judge_standing(StandingResult& r, const StandingTask& t) {
  r.fell = r.diverged || r.drop_m > t.max_drop_m || r.max_tilt_rad > t.max_tilt_rad;
}

}  // namespace dmbd::bench
