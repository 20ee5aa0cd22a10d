#pragma once
// The whole-robot speed benchmark's standing task, free of any simulator, so that every
// engine in bench_standing (MuJoCo in mujoco_draco.cpp, the project's own simulator next
// to it) runs exactly the same thing:
//   - DRACO floating, every joint at 0, torso upright, placed so that the lowest foot
//     contact sphere just touches the floor (bottom of the lowest sphere at z = 0);
//   - a 1 kHz joint controller with zero-order hold: the command is computed every
//     control period from the state at that instant and held until the next;
//   - ideal joint torques: tau = Kp (0 - q) - Kd qdot, Kp 1500 N m/rad and Kd 20 N m s/rad
//     for the hips and knees, 800 and 2 for the ankles (joint names containing "ankle");
//   - actuators (elastic): tau_cmd = 3000 (0 - q) - 100 qdot for every joint, sent as the
//     current tau_cmd / (k_tau N_m r(q)) with r(q) the linkage moment arm at the current
//     angle, clamped to the actuator's current limit;
//   - outcome: the largest tilt of the torso z axis from vertical, the torso's height
//     drop (initial minus final z) and "fell" (drop > 0.2 m or tilt > 0.5 rad, or the
//     engine diverged).

#include "dmbd/model/actuator.hpp"
#include "dmbd/model/robot_description.hpp"

#include <string>
#include <vector>

namespace dmbd::bench {

enum class Integrator { Euler, Implicit };

struct StandingTask {
  double duration_s = 2.0;           // simulated time per run
  double control_period_s = 1e-3;    // 1 kHz, zero-order hold
  double timestep_s = 1e-3;          // the engine's step (a divisor of the control period)
  Integrator integrator = Integrator::Euler;
  double gravity_mps2 = 9.81;
  double friction = 0.8;             // foot-floor Coulomb friction
  // Ideal joint torques.
  double kp_Nm_per_rad = 1500, kd_Nms_per_rad = 20;               // hips and knees
  double kp_ankle_Nm_per_rad = 800, kd_ankle_Nms_per_rad = 2;     // "ankle" joints
  // Actuators: the joint PD whose torque is turned into a current.
  double kp_actuated_Nm_per_rad = 3000, kd_actuated_Nms_per_rad = 100;
  // "fell" thresholds.
  double max_drop_m = 0.2, max_tilt_rad = 0.5;
};

struct StandingResult {
  double rtf = 0;                    // simulated s / wall s of the stepping loop only
  double sim_s = 0, wall_s = 0;
  long long steps = 0;               // engine steps taken
  double max_tilt_rad = 0;           // torso z axis from vertical, largest over the run
  double drop_m = 0;                 // torso height: initial minus final
  bool diverged = false;             // the engine reported a numerical instability
  bool fell = false;                 // drop, tilt or divergence past the task's limits
};

// Height of the root link frame (every joint at 0, upright) that puts the bottom of the
// lowest collision sphere at z = 0. Throws std::runtime_error if the robot has no sphere.
double standing_root_height_m(const dmbd::model::RobotDescription& robot);

// Ideal joint torques (N m) for joints named `joints` at positions q and rates qd.
std::vector<double> standing_torques(const std::vector<std::string>& joints, const std::vector<double>& q,
                                     const std::vector<double>& qd, const StandingTask& task);

// Actuator currents (A), one per actuator; q and qd are of the actuator's joint
// (q[a] is the angle of actuators[a].joint).
std::vector<double> standing_currents(const std::vector<dmbd::model::ActuatorParams>& actuators,
                                      const std::vector<double>& q, const std::vector<double>& qd,
                                      const StandingTask& task);

// Fills `fell` from drop_m, max_tilt_rad and diverged.
void judge_standing(StandingResult& r, const StandingTask& task);

}  // namespace dmbd::bench
