#pragma once
// The centre of mass from the torso IMU and the joint encoders through kinematics
// (issue 15, state estimation): the stance foot's contact point is taken to stay where
// it landed (its world position latched at touch-down), so the base position is where
// that point's kinematics puts it, and the base's linear velocity the one that keeps it
// still; the CoM and its velocity follow from the whole configuration. The paper used
// motion capture for the CoM velocity; a scenario may offer that instead (ground truth
// plus noise). Allocation-free per update.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "dmbd/model/robot_description.hpp"
#include "dmbd/control/dynamics_model.hpp"
#include "dmbd/wholebody/phase_machine.hpp"

namespace dmbd::control {

// One update's estimate, all in the world frame.
struct ComEstimate {
  Eigen::Vector3d base_position_m = Eigen::Vector3d::Zero();    // the base (torso) origin, m
  Eigen::Vector3d base_velocity_m_s = Eigen::Vector3d::Zero();  // its velocity, m/s
  Eigen::Vector3d com_m = Eigen::Vector3d::Zero();              // the whole robot's centre of mass, m
  Eigen::Vector3d com_velocity_m_s = Eigen::Vector3d::Zero();   // its velocity, m/s
};

// The estimator above, over its own floating-base DynamicsModel of the robot. The stance
// foot is the left one, at the world's origin, until set_stance() says otherwise.
class KinematicComEstimator {
 public:
  // left_foot, right_foot: each foot's contact point (link and point in it). InputError
  // for a link the robot does not have.
  KinematicComEstimator(const model::RobotDescription& robot, const wholebody::FrameSpec& left_foot,
                        const wholebody::FrameSpec& right_foot);

  // The stance foot and where its contact point is in the world (latched at touch-down).
  void set_stance(wholebody::Side side, const Eigen::Vector3d& foot_W);

  // R_WB and ω_W from the IMU; joints in the model's joint order (Layout::joints).
  const ComEstimate& update(const Eigen::Quaterniond& R_WB, const Eigen::Vector3d& omega_W,
                            const Eigen::Ref<const Eigen::VectorXd>& joint_q,
                            const Eigen::Ref<const Eigen::VectorXd>& joint_v);

  // The model's coordinates (floating base); its joints give update()'s joint order.
  const wholebody::Layout& layout() const { return model_.layout(); }

 private:
  DynamicsModel model_;
  int foot_frame_[2];
  wholebody::ModelData data_;
  wholebody::Side stance_ = wholebody::Side::Left;
  Eigen::Vector3d stance_foot_W_ = Eigen::Vector3d::Zero();
  Eigen::VectorXd q_, v_;
  ComEstimate estimate_;
};

}  // namespace dmbd::control
