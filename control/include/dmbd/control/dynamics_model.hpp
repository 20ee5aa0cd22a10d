#pragma once
// The adapter from model::RobotDynamics (the robot's rigid-body dynamics, Simbody behind
// it) to the interface whole-body controllers read (wholebody::RobotModel). It lives in
// sim/, which may use both; wholebody never sees model/ or Simbody.
// Joint limits come from the URDF (position, effort, velocity; an effort or velocity of
// 0 in the URDF means none given: infinite here). A joint's armature (a geared rotor
// reflected onto it, model::Joint::armature, as the plant adds it) is on its diagonal of
// the mass matrix: the controller's model is the plant's.
#include <memory>
#include <utility>
#include <vector>

#include "dmbd/model/dynamics.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/wholebody/robot_model.hpp"

namespace dmbd::control {

// The layout wholebody's controllers (and the Python robot model) see of a robot: its
// coordinates' sizes and, per moving joint of dyn, its indices and the URDF's limits
// (position limits only where the URDF gives them, never for a continuous joint; a
// missing effort or velocity limit is infinite).
wholebody::Layout layout_of(const model::RobotDescription& robot, const model::RobotDynamics& dyn);

// wholebody::RobotModel over model::RobotDynamics: the layout, frames and per-state terms
// (mass matrix, b + g, frame and CoM Jacobians) a whole-body controller reads, in the
// coordinates of model::RobotDynamics (wholebody/robot_model.hpp).
class DynamicsModel : public wholebody::RobotModel {
 public:
  // Copies the description (RobotDynamics keeps a reference to it).
  DynamicsModel(const model::RobotDescription& robot, const model::DynamicsOptions& options);

  // nq, nv, the base's dofs (0 fixed, 6 floating, as options.base) and each joint
  // coordinate of RobotDynamics, in its order, with the URDF's limits (above).
  const wholebody::Layout& layout() const override { return layout_; }
  // Registers a frame at p_L in a link (axes the link's); its index into
  // ModelData::frames. InputError "frame: robot 'NAME' has no link 'LINK'".
  int add_frame(const wholebody::FrameSpec& frame) override;
  int num_frames() const override { return static_cast<int>(frames_.size()); }  // frames added so far
  void update(const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& v,
              wholebody::ModelData& data) override;

  // The rigid-body dynamics behind it (its own copy of the description).
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
  std::vector<std::pair<int, double>> armature_;  // (v index, kg m² or kg) of each joint that has one
};

}  // namespace dmbd::control
