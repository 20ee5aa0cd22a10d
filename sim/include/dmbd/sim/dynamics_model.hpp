#pragma once
// The adapter from model::RobotDynamics (the robot's rigid-body dynamics, Simbody behind
// it) to the interface whole-body controllers read (wholebody::RobotModel). It lives in
// sim/, which may use both; wholebody never sees model/ or Simbody.
// Joint limits come from the URDF (position, effort, velocity; an effort or velocity of
// 0 in the URDF means none given: infinite here).
#include <memory>
#include <vector>

#include "dmbd/model/dynamics.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/wholebody/robot_model.hpp"

namespace dmbd::sim {

class DynamicsModel : public wholebody::RobotModel {
 public:
  // Copies the description (RobotDynamics keeps a reference to it).
  DynamicsModel(const model::RobotDescription& robot, const model::DynamicsOptions& options);

  const wholebody::Layout& layout() const override { return layout_; }
  int add_frame(const wholebody::FrameSpec& frame) override;
  int num_frames() const override { return static_cast<int>(frames_.size()); }
  void update(const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& v,
              wholebody::ModelData& data) override;

  const model::RobotDynamics& dynamics() const { return *dynamics_; }

 private:
  struct Frame {
    int link;
    Eigen::Vector3d p_L;
  };
  std::unique_ptr<model::RobotDescription> robot_;
  std::unique_ptr<model::RobotDynamics> dynamics_;
  wholebody::Layout layout_;
  std::vector<Frame> frames_;
};

}  // namespace dmbd::sim
