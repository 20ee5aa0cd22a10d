#pragma once
// BalanceController's insides (balance_controller.hpp), shared by its source files:
// balance_controller.cpp (construction, ports, the tick), balance_state.cpp (the state
// estimate), balance_plan.cpp (phase events, TVR, swing), balance_wbc.cpp (IK and QP).
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "dmbd/control/balance_controller.hpp"
#include "dmbd/control/com_estimator.hpp"
#include "dmbd/control/dynamics_model.hpp"
#include "dmbd/wholebody/prioritized_ik.hpp"
#include "dmbd/wholebody/selection_task.hpp"
#include "dmbd/wholebody/task.hpp"

namespace dmbd::control {

using wholebody::Side;

struct BalanceController::Impl {
  BalanceSetup setup;
  DynamicsModel model;
  wholebody::ModelData data;
  KinematicComEstimator estimator;
  std::mt19937_64 rng;
  std::normal_distribution<double> normal{0.0, 1.0};

  // Model frames and joint indices (into Layout::joints).
  int torso_frame = 0;
  std::array<int, 2> foot_frame{}, ankle{}, hip_yaw{};
  int nj = 0;
  std::vector<std::optional<model::ActuatorParams>> actuator;  // per joint: its actuator, if any
  // Per joint with an actuator (0 without): the reflected rotor mass J_m N_m² (kg), the
  // damping along the actuator B_m N_m² + B_l (N s/m) and the drive efficiency.
  std::vector<double> rotor_mass, actuator_damping, efficiency;
  Eigen::VectorXd kp, kd;                                       // per joint (joint feedback)
  Eigen::VectorXd stance_q;                                     // joint move target, per joint

  // Tasks and solvers.
  std::unique_ptr<wholebody::PostureTask> hip_yaws, all_joints;
  std::array<std::unique_ptr<wholebody::PostureTask>, 2> swing_ankle;
  std::array<std::unique_ptr<wholebody::OrientationTask>, 2> foot_orientation;
  std::array<std::unique_ptr<wholebody::SelectionTask>, 2> foot_pitch;  // world y row (swing_foot_level)
  std::array<Eigen::Matrix3d, 2> foot_flat_R{Eigen::Matrix3d::Identity(), Eigen::Matrix3d::Identity()};  // at lift
  std::array<std::unique_ptr<wholebody::PointTask>, 2> swing_foot;
  std::unique_ptr<wholebody::OrientationTask> torso_orientation;
  std::unique_ptr<wholebody::PointTask> torso_position;
  std::unique_ptr<wholebody::SelectionTask> torso;
  std::unique_ptr<wholebody::ComTask> com;
  std::unique_ptr<wholebody::SelectionTask> com_y;
  std::unique_ptr<wholebody::PrioritizedIk> ik_double, ik_shift, ik_single;
  std::unique_ptr<wholebody::WbcQp> qp;
  wholebody::PhaseMachine phases;
  wholebody::TvrPlanner tvr;
  wholebody::SwingTrajectory swing;

  // Per-tick storage.
  Eigen::VectorXd joint_q, joint_v, q, v, qdd_cmd, q_des, qd_des, tau_ff, last_q_des, last_qd_des;
  Eigen::VectorXd qdd_joint;  // the QP's joint accelerations (0 when fallen)
  Eigen::MatrixXd J_double, J_single;
  Eigen::VectorXd Jdv_double, Jdv_single;

  // Plan and start-up state.
  long long tick = 0;
  Eigen::VectorXd move_start_q;        // joints at the joint move's start
  double lift_start_height = 0.0;      // torso height at the body lift's start
  Eigen::Vector2d shift_start = Eigen::Vector2d::Zero(), shift_end = Eigen::Vector2d::Zero();
  Eigen::Vector2d shift_end_velocity = Eigen::Vector2d::Zero();  // the weight shift's CoM path
  Eigen::Vector2d com_desired = Eigen::Vector2d::Zero();
  Eigen::Vector2d com_integral = Eigen::Vector2d::Zero();  // the planner's target less com_desired (tvr.integral_gain)
  bool com_desired_set = false;
  Eigen::Vector2d foothold = Eigen::Vector2d::Zero();
  Eigen::Vector2d landed = Eigen::Vector2d::Zero(), planned = Eigen::Vector2d::Zero();
  bool landing_pending = false;  // touched down, its standing point not yet latched
  long long landings = 0;        // standing points latched
  double swing_ankle_start = 0.0;
  // The heading hold (BalanceSetup::heading_gain): the heading latched at the first lift,
  // and per side the hip yaw's offset from its stance angle, at the swing's start and its
  // target at the swing's end.
  double heading = 0.0;
  bool heading_set = false;
  Eigen::Vector2d hip_yaw_offset_start = Eigen::Vector2d::Zero(), hip_yaw_offset_end = Eigen::Vector2d::Zero();
  Eigen::Vector2d hip_yaw_offset = Eigen::Vector2d::Zero();  // now
  long long qp_failures = 0;
  bool fallen = false;
  double tilt = 0.0;  // the torso's, from the IMU
  std::vector<std::string> in_names, out_names, out_units;

  Impl(const model::RobotDescription& robot, double gravity, const BalanceSetup& s);

  // Construction (balance_controller.cpp).
  void find_frames_and_joints(const model::RobotDescription& robot);
  void make_tasks();
  void bind_actuators(const std::vector<model::ActuatorParams>& actuators);
  void set_gains();
  void name_ports();
  void start_at(const std::vector<std::pair<std::string, double>>& q0);

  // The state estimate (balance_state.cpp): q, v and data from the inputs.
  void read_state(const double* u);
  Eigen::Vector3d foot_point(Side s) const;  // the contact point, world (at data's state)

  // Phase events (balance_plan.cpp).
  void on_events(const wholebody::PhaseInfo& ph);
  void plan_step(const wholebody::PhaseInfo& ph, bool replan);
  void plan_weight_shift(const wholebody::PhaseInfo& ph);
  void plan_heading(Side swing_side);  // the hip yaws' offsets over the coming swing
  void pendulum_state(Side stance, Eigen::Vector2d& position_m, Eigen::Vector2d& velocity_m_s) const;  // TVR's point

  // Tasks, IK and QP (balance_wbc.cpp): q_des, qd_des, tau_ff; false when the QP failed.
  bool whole_body(const wholebody::PhaseInfo& ph);
  void joint_move(const wholebody::PhaseInfo& ph);
  void set_torso_reference(const wholebody::PhaseInfo& ph);
  void set_com_reference(const wholebody::PhaseInfo& ph);
  void solve_ik(const wholebody::PhaseInfo& ph);
  void clamp_to_limits();  // q_des, qd_des and q̈_cmd within the joints' ranges
  bool solve_qp(const wholebody::PhaseInfo& ph);

  void write_outputs(const wholebody::PhaseInfo& ph, double* y) const;
  double actuator_force(int j) const;  // J.force_ff
};

}  // namespace dmbd::control
