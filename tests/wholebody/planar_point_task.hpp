#pragma once
// A 2-D point task for the planar test arms (two_link_arm.hpp): the in-plane coordinates
// (x, z) of a registered frame's origin, i.e. rows 3 and 5 of the frame's Jacobian
// [angular; linear]. PointTask's three rows include y, which an arm in the x-z plane
// cannot move; this task is the full-row-rank version of it.
#include <Eigen/Core>

#include "dmbd/wholebody/task.hpp"

namespace dmbd::wholebody::testing {

class PlanarPointTask : public Task {
 public:
  PlanarPointTask(int frame, int nv) : Task(2, nv), frame_(frame) {}

  void set_reference(const Eigen::Vector2d& p, const Eigen::Vector2d& v, const Eigen::Vector2d& a) {
    p_d_ = p;
    v_d_ = v;
    a_d_ = a;
  }

  void update(const ModelData& data) override {
    const FrameData& f = data.frames[static_cast<size_t>(frame_)];
    J_.row(0) = f.J.row(3);
    J_.row(1) = f.J.row(5);
    Jdot_v_[0] = f.Jdot_v[3];
    Jdot_v_[1] = f.Jdot_v[5];
    e_[0] = p_d_.x() - f.X_WF.translation().x();
    e_[1] = p_d_.y() - f.X_WF.translation().z();
    edot_.noalias() = -J_ * data.v;
    edot_ += v_d_;
    finish(a_d_);
  }

 private:
  int frame_;
  Eigen::Vector2d p_d_ = Eigen::Vector2d::Zero(), v_d_ = Eigen::Vector2d::Zero(), a_d_ = Eigen::Vector2d::Zero();
};

// (x, z) of a 3-D point.
inline Eigen::Vector2d in_plane(const Eigen::Vector3d& p) { return {p.x(), p.z()}; }

}  // namespace dmbd::wholebody::testing
