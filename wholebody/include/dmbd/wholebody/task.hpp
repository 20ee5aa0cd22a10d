#pragma once
// Tasks: what a whole-body controller asks of the robot, each a small object (TSID's
// tasks). A task of dimension m reads ModelData and gives its Jacobian J (m x nv), J̇v
// (m), its error e = x_d − x and rate error ė = ẋ_d − J v, and the commanded task
// acceleration ẍ_cmd = ẍ_d + Kp e + Kd ė (diagonal gains, one per task row).
// Allocation-free: storage is sized in the constructor.
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "dmbd/wholebody/robot_model.hpp"

namespace dmbd::wholebody {

class Task {
 public:
  Task(int dim, int nv);
  virtual ~Task() = default;
  int dim() const { return static_cast<int>(e_.size()); }

  // Recomputes J, J̇v, e, ė and ẍ_cmd at data's state.
  virtual void update(const ModelData& data) = 0;

  const Eigen::MatrixXd& jacobian() const { return J_; }
  const Eigen::VectorXd& jacobian_dot_v() const { return Jdot_v_; }
  const Eigen::VectorXd& error() const { return e_; }
  const Eigen::VectorXd& error_rate() const { return edot_; }
  const Eigen::VectorXd& command() const { return xdd_cmd_; }

  // Diagonal gains (1/s², 1/s), per task row.
  void set_gains(const Eigen::Ref<const Eigen::VectorXd>& kp, const Eigen::Ref<const Eigen::VectorXd>& kd);
  void set_gains(double kp, double kd);
  const Eigen::VectorXd& kp() const { return kp_; }
  const Eigen::VectorXd& kd() const { return kd_; }

 protected:
  // ẍ_cmd = ẍ_d + Kp e + Kd ė from e_, edot_ and the reference acceleration.
  void finish(const Eigen::Ref<const Eigen::VectorXd>& xdd_d);

  Eigen::MatrixXd J_;
  Eigen::VectorXd Jdot_v_, e_, edot_, xdd_cmd_, kp_, kd_;
};

// The origin of a registered frame: x = p_WF (3); or, given a second frame B, its
// position from B's origin in world axes, x = p_WF − p_WB (J = J_F − J_B, linear rows):
// a foot's target relative to the torso is met by the joints whatever the base does.
class PointTask : public Task {
 public:
  PointTask(int frame, int nv, int relative_to_frame = -1);
  void set_reference(const Eigen::Vector3d& p, const Eigen::Vector3d& v, const Eigen::Vector3d& a);
  void update(const ModelData& data) override;
  const Eigen::Vector3d& position() const { return p_; }  // at the last update
  const Eigen::Vector3d& reference() const { return p_d_; }

 private:
  int frame_, relative_to_;
  Eigen::Vector3d p_ = Eigen::Vector3d::Zero(), p_d_ = Eigen::Vector3d::Zero(), v_d_ = Eigen::Vector3d::Zero(),
                  a_d_ = Eigen::Vector3d::Zero();
};

// The orientation of a registered frame (3): e = log(R_d Rᵀ) as a rotation vector in
// world axes, ė = ω_d − ω, reference angular velocity and acceleration in world axes.
class OrientationTask : public Task {
 public:
  OrientationTask(int frame, int nv);
  void set_reference(const Eigen::Matrix3d& R_d, const Eigen::Vector3d& w_d, const Eigen::Vector3d& dw_d);
  void update(const ModelData& data) override;

 private:
  int frame_;
  Eigen::Matrix3d R_d_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d w_d_ = Eigen::Vector3d::Zero(), dw_d_ = Eigen::Vector3d::Zero();
};

// The centre of mass (3), world.
class ComTask : public Task {
 public:
  explicit ComTask(int nv);
  void set_reference(const Eigen::Vector3d& p, const Eigen::Vector3d& v, const Eigen::Vector3d& a);
  void update(const ModelData& data) override;

 private:
  Eigen::Vector3d p_d_ = Eigen::Vector3d::Zero(), v_d_ = Eigen::Vector3d::Zero(), a_d_ = Eigen::Vector3d::Zero();
};

// Joint angles of some joints (Layout::joints indices), one row each.
class PostureTask : public Task {
 public:
  PostureTask(const Layout& layout, std::vector<int> joints);
  // Targets per task row (the joints in the order given).
  void set_reference(const Eigen::Ref<const Eigen::VectorXd>& q_d, const Eigen::Ref<const Eigen::VectorXd>& qd_d,
                     const Eigen::Ref<const Eigen::VectorXd>& qdd_d);
  void update(const ModelData& data) override;

 private:
  std::vector<int> q_index_, v_index_;
  Eigen::VectorXd q_d_, qd_d_, qdd_d_;
};

}  // namespace dmbd::wholebody
