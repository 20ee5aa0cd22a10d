#pragma once
// Hand-derived test models for dmbd_wholebody: planar serial arms on a fixed base that
// implement wholebody::RobotModel from closed forms (no recursion library, no numerical
// differentiation), so the controllers can be checked against exact dynamics.
//
// Convention (every model here):
//   the arm moves in the world's vertical x-z plane; every joint rotates about the world
//   +y axis (right-handed); gravity is 9.81 m/s² along -z. Link k's absolute angle is
//   θ_k = q_1 + ... + q_k and its direction u(θ) = R_y(θ) x̂ = (cos θ, 0, -sin θ): q = 0 is
//   the arm stretched horizontally along +x, a positive angle swings it down. Link k's
//   frame has its origin at its joint o_k (o_1 = 0, o_{k+1} = o_k + l_k u(θ_k)) and axes
//   R_y(θ_k) (x along the link). Link k: length l, mass m, CoM at lc along the link,
//   inertia I about its CoM (about y).
//   In the coordinates (x, w = -z) the link direction is (cos θ, sin θ): the textbook
//   planar arm (Spong, Hutchinson & Vidyasagar, Sec. 7.3), with gravity along +w.
//
// PlanarArm (n links), Kane's form:
//   a point p on link k moves with ṗ = Σ_{j≤k} v_j ŷ × (p − o_j), so its Jacobian column j
//   (j ≤ k, zero beyond) is [ŷ; ŷ × (p − o_j)] and J̇v = [0; Σ_{j≤k} v_j ŷ × (ṗ − ȯ_j)].
//   With Jc_k the Jacobian of link k's CoM and Jω_k = [1 ... 1 0 ... 0] (its y rate), and
//   ω ∥ ŷ (so ω × Iω = 0, Jω constant):
//     A = Σ m_k Jc_kᵀ Jc_k + I_k Jω_kᵀ Jω_k,  b = Σ m_k Jc_kᵀ (J̇c_k v),  g = −Σ m_k Jc_kᵀ g⃗.
// TwoLinkArm: the same kinematics; A, b and g from the textbook's closed forms
// (c2 = cos q2, c1 = cos q1, c12 = cos(q1 + q2), G = 9.81):
//   A11 = m1 lc1² + I1 + m2 (l1² + lc2² + 2 l1 lc2 c2) + I2
//   A12 = m2 (lc2² + l1 lc2 c2) + I2,  A22 = m2 lc2² + I2
//   h = −m2 l1 lc2 sin q2,  b = (h (2 v1 v2 + v2²), −h v1²)
//   V = −G (m1 lc1 sin q1 + m2 (l1 sin q1 + lc2 sin(q1+q2)))  (z = −w),  g = ∂V/∂q:
//   g = (−G ((m1 lc1 + m2 l1) c1 + m2 lc2 c12), −G m2 lc2 c12)
// Links are named "link1", "link2", ...; joints "joint1", .... update() allocates nothing.
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "dmbd/base/error.hpp"
#include "dmbd/wholebody/robot_model.hpp"

namespace dmbd::wholebody::testing {

constexpr double kGravity = 9.81;

struct PlanarLink {
  double length = 1.0;   // l, m
  double mass = 1.0;     // m, kg
  double com = 0.5;      // lc, m along the link
  double inertia = 0.1;  // I about the CoM, kg m²
};

// ŷ × r, the velocity a unit rate about the joints' axis gives the arm r.
inline Eigen::Vector3d y_cross(const Eigen::Vector3d& r) { return {r.z(), 0.0, -r.x()}; }
inline Eigen::Vector3d link_direction(double theta) { return {std::cos(theta), 0.0, -std::sin(theta)}; }
inline Eigen::Matrix3d rotation_y(double theta) {
  return Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()).toRotationMatrix();
}

class PlanarArm : public RobotModel {
 public:
  explicit PlanarArm(std::vector<PlanarLink> links) : links_(std::move(links)) {
    const int n = size();
    layout_.nq = layout_.nv = n;
    for (int k = 0; k < n; ++k) layout_.joints.push_back({"joint" + std::to_string(k + 1), k, k, {}});
    theta_.assign(links_.size(), 0.0);
    omega_.assign(links_.size(), 0.0);
    o_.assign(links_.size(), Eigen::Vector3d::Zero());
    o_dot_.assign(links_.size(), Eigen::Vector3d::Zero());
    Jp_ = Eigen::Matrix<double, 3, Eigen::Dynamic>::Zero(3, n);
  }

  const Layout& layout() const override { return layout_; }
  int add_frame(const FrameSpec& frame) override {
    const int k = link_index(frame.link);
    if (k < 0) throw InputError("planar arm: no link '" + frame.link + "'");
    frames_.push_back({k, frame.p_L});
    return num_frames() - 1;
  }
  int num_frames() const override { return static_cast<int>(frames_.size()); }

  void update(const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& v,
              ModelData& data) override {
    data.q = q;
    data.v = v;
    chain(q, v);
    for (size_t f = 0; f < frames_.size(); ++f) write_frame(frames_[f], v, data.frames[f]);
    write_com(data);
    dynamics(data);
  }

  int size() const { return static_cast<int>(links_.size()); }
  const PlanarLink& link(int k) const { return links_[static_cast<size_t>(k)]; }
  double total_mass() const {
    double m = 0.0;
    for (const PlanarLink& l : links_) m += l.mass;
    return m;
  }
  int link_index(const std::string& name) const {
    for (int k = 0; k < size(); ++k)
      if (name == "link" + std::to_string(k + 1)) return k;
    return -1;
  }

 protected:
  // A, b + g and g at data.q, data.v (the chain and the CoM already computed).
  virtual void dynamics(ModelData& data) {
    data.A.setZero();
    data.bg.setZero();
    data.g.setZero();
    const Eigen::Vector3d gravity(0.0, 0.0, -kGravity);
    for (int k = 0; k < size(); ++k) {
      const PlanarLink& l = link(k);
      Eigen::Vector3d c, cdot, c_Jdot_v;
      point(k, Eigen::Vector3d(l.com, 0, 0), data.v, c, cdot, c_Jdot_v);
      data.A.noalias() += l.mass * Jp_.transpose() * Jp_;
      data.A.topLeftCorner(k + 1, k + 1).array() += l.inertia;
      data.bg.noalias() += l.mass * Jp_.transpose() * c_Jdot_v;
      data.g.noalias() -= l.mass * Jp_.transpose() * gravity;
    }
    data.bg += data.g;
  }

  // Link angles θ_k and rates, joint origins o_k and their velocities at (q, v).
  void chain(const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& v) {
    double theta = 0.0, omega = 0.0;
    Eigen::Vector3d o = Eigen::Vector3d::Zero(), o_dot = Eigen::Vector3d::Zero();
    for (size_t k = 0; k < links_.size(); ++k) {
      theta += q[static_cast<Eigen::Index>(k)];
      omega += v[static_cast<Eigen::Index>(k)];
      theta_[k] = theta;
      omega_[k] = omega;
      o_[k] = o;
      o_dot_[k] = o_dot;
      o += links_[k].length * link_direction(theta);
      o_dot += omega * y_cross(links_[k].length * link_direction(theta));
    }
  }

  // The point p_L (link k's frame) at the last chain(): position p, velocity, its linear
  // Jacobian (into Jp_) and J̇v.
  void point(int k, const Eigen::Vector3d& p_L, const Eigen::Ref<const Eigen::VectorXd>& v, Eigen::Vector3d& p,
             Eigen::Vector3d& p_dot, Eigen::Vector3d& Jdot_v) {
    const auto kk = static_cast<size_t>(k);
    p = o_[kk] + rotation_y(theta_[kk]) * p_L;
    p_dot = o_dot_[kk] + omega_[kk] * y_cross(p - o_[kk]);
    Jp_.setZero();
    Jdot_v.setZero();
    for (int j = 0; j <= k; ++j) {
      Jp_.col(j) = y_cross(p - o_[static_cast<size_t>(j)]);
      Jdot_v += v[j] * y_cross(p_dot - o_dot_[static_cast<size_t>(j)]);
    }
  }

 private:
  struct Frame {
    int link;
    Eigen::Vector3d p_L;
  };

  void write_frame(const Frame& f, const Eigen::Ref<const Eigen::VectorXd>& v, FrameData& out) {
    Eigen::Vector3d p, p_dot, Jdot_v;
    point(f.link, f.p_L, v, p, p_dot, Jdot_v);
    out.X_WF.setIdentity();
    out.X_WF.linear() = rotation_y(theta_[static_cast<size_t>(f.link)]);
    out.X_WF.translation() = p;
    out.J.setZero();
    out.J.block(1, 0, 1, f.link + 1).setOnes();  // angular: ŷ for every joint up to the link
    out.J.bottomRows<3>() = Jp_;
    out.Jdot_v.head<3>().setZero();
    out.Jdot_v.tail<3>() = Jdot_v;
  }

  void write_com(ModelData& data) {
    data.com.setZero();
    data.J_com.setZero();
    data.com_Jdot_v.setZero();
    const double M = total_mass();
    for (int k = 0; k < size(); ++k) {
      const PlanarLink& l = link(k);
      Eigen::Vector3d c, cdot, c_Jdot_v;
      point(k, Eigen::Vector3d(l.com, 0, 0), data.v, c, cdot, c_Jdot_v);
      data.com += (l.mass / M) * c;
      data.J_com += (l.mass / M) * Jp_;
      data.com_Jdot_v += (l.mass / M) * c_Jdot_v;
    }
  }

  std::vector<PlanarLink> links_;
  Layout layout_;
  std::vector<Frame> frames_;
  std::vector<double> theta_, omega_;
  std::vector<Eigen::Vector3d> o_, o_dot_;
  Eigen::Matrix<double, 3, Eigen::Dynamic> Jp_;
};

// The two-link arm with the textbook's closed forms for A, b and g (see the top).
class TwoLinkArm : public PlanarArm {
 public:
  TwoLinkArm(const PlanarLink& link1, const PlanarLink& link2) : PlanarArm({link1, link2}) {}

 protected:
  void dynamics(ModelData& data) override {
    const PlanarLink &L1 = link(0), &L2 = link(1);
    const double m1 = L1.mass, m2 = L2.mass, l1 = L1.length, lc1 = L1.com, lc2 = L2.com;
    const double q1 = data.q[0], q2 = data.q[1], v1 = data.v[0], v2 = data.v[1];
    const double c1 = std::cos(q1), c2 = std::cos(q2), c12 = std::cos(q1 + q2);
    data.A(0, 0) = m1 * lc1 * lc1 + L1.inertia + m2 * (l1 * l1 + lc2 * lc2 + 2 * l1 * lc2 * c2) + L2.inertia;
    data.A(0, 1) = data.A(1, 0) = m2 * (lc2 * lc2 + l1 * lc2 * c2) + L2.inertia;
    data.A(1, 1) = m2 * lc2 * lc2 + L2.inertia;
    const double h = -m2 * l1 * lc2 * std::sin(q2);
    data.g[0] = -kGravity * ((m1 * lc1 + m2 * l1) * c1 + m2 * lc2 * c12);
    data.g[1] = -kGravity * m2 * lc2 * c12;
    data.bg[0] = h * (2 * v1 * v2 + v2 * v2) + data.g[0];
    data.bg[1] = -h * v1 * v1 + data.g[1];
  }
};

// The arms the tests use (parameters of a small robot arm, distinct enough that a swapped
// index shows).
inline PlanarLink link_a() { return {0.5, 2.0, 0.3, 0.04}; }
inline PlanarLink link_b() { return {0.4, 1.5, 0.25, 0.02}; }
inline PlanarLink link_c() { return {0.3, 0.8, 0.12, 0.01}; }
inline TwoLinkArm two_link_arm() { return TwoLinkArm(link_a(), link_b()); }
inline PlanarArm three_link_arm() { return PlanarArm({link_a(), link_b(), link_c()}); }

}  // namespace dmbd::wholebody::testing
