#pragma once
// Internal to model/: the ground, a plane through the world origin with unit normal n
// (PlantOptions::ground_normal; gravity stays along -z world), and its frame
// G = [t1 t2 n]: contact laws are written in G (x, y along the ground, z along n).
// Heights are n . p (m, positive above the ground); the ground's tangent coordinates of a
// point are (t1 . p, t2 . p): t1 is world x projected into the plane (world y when n is
// within 26 degrees of x), t2 = n x t1.
// For n = +z every mapping is the identity and returns its argument unchanged (no
// arithmetic), so the sphere law is bit for bit the one before the ground could tilt.
#include "dmbd/model/error.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <string>

namespace dmbd::model::detail {

class GroundFrame {
 public:
  explicit GroundFrame(const Eigen::Vector3d& normal) {
    const double len = normal.norm();
    if (!(len > 0) || !std::isfinite(len) || !(normal.z() > 0))
      throw ModelError("plant: ground_normal (" + std::to_string(normal.x()) + ", " + std::to_string(normal.y()) + ", " +
                       std::to_string(normal.z()) + ") is not a finite upward direction (expected n.z > 0)");
    n_ = normal / len;
    is_z_ = n_.x() == 0 && n_.y() == 0;
    if (is_z_) n_ = Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d ref = std::abs(n_.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    t1_ = (ref - ref.dot(n_) * n_).normalized();
    t2_ = n_.cross(t1_);
  }

  bool is_z() const { return is_z_; }
  const Eigen::Vector3d& n() const { return n_; }
  double height(const Eigen::Vector3d& p) const { return is_z_ ? p.z() : n_.dot(p); }
  Eigen::Vector2d tangent(const Eigen::Vector3d& p) const {
    return is_z_ ? Eigen::Vector2d(p.head<2>()) : Eigen::Vector2d(t1_.dot(p), t2_.dot(p));
  }
  Eigen::Vector3d to_ground(const Eigen::Vector3d& v) const {
    return is_z_ ? v : Eigen::Vector3d(t1_.dot(v), t2_.dot(v), n_.dot(v));
  }
  // A law's output (force, K, D in G) into world.
  template <class Force>
  void to_world(Force& c) const {
    if (is_z_) return;
    Eigen::Matrix3d R;
    R << t1_, t2_, n_;
    c.force_W = R * c.force_W;
    c.K = R * c.K * R.transpose();
    c.D = R * c.D * R.transpose();
  }

 private:
  Eigen::Vector3d n_, t1_, t2_;
  bool is_z_ = true;
};

}  // namespace dmbd::model::detail
