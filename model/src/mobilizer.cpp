// The mobilizer kinds' coordinates, as Simbody defines them (see mobilizer.hpp).
#include "mobilizer.hpp"

#include <cmath>

namespace dmbd::model::detail {

namespace {

Eigen::Matrix3d rot_z(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Eigen::Matrix3d R;
  R << c, -s, 0, s, c, 0, 0, 0, 1;
  return R;
}

}  // namespace

void mobilizer_transform(const Mobilizer& mob, const Eigen::VectorXd& q, Eigen::Matrix3d& R_FM, Eigen::Vector3d& p_FM) {
  const int i = mob.first_q;
  switch (mob.kind) {
    case MobilizerKind::Weld:
      R_FM.setIdentity();
      p_FM.setZero();
      return;
    case MobilizerKind::Pin:
      R_FM = rot_z(q[i]);
      p_FM.setZero();
      return;
    case MobilizerKind::Slider:
      R_FM.setIdentity();
      p_FM = Eigen::Vector3d(q[i], 0, 0);
      return;
    case MobilizerKind::Free:
      R_FM = Eigen::Quaterniond(q[i], q[i + 1], q[i + 2], q[i + 3]).toRotationMatrix();
      p_FM = q.segment<3>(i + 4);
      return;
    case MobilizerKind::Planar:
      R_FM = rot_z(q[i]);
      p_FM = Eigen::Vector3d(q[i + 1], q[i + 2], 0);
      return;
  }
}

Eigen::Matrix<double, 6, 1> mobilizer_column(MobilizerKind kind, int i) {
  Eigen::Matrix<double, 6, 1> h = Eigen::Matrix<double, 6, 1>::Zero();
  switch (kind) {
    case MobilizerKind::Weld:
      break;
    case MobilizerKind::Pin:
      h[2] = 1;  // about z
      break;
    case MobilizerKind::Slider:
      h[3] = 1;  // along x
      break;
    case MobilizerKind::Free:
      h[i] = 1;  // w_FM then v_FM, both in F
      break;
    case MobilizerKind::Planar:
      h[i == 0 ? 2 : 2 + i] = 1;  // about z, along x, along y
      break;
  }
  return h;
}

void mobilizer_qdot(const Mobilizer& mob, const Eigen::VectorXd& q, const Eigen::Ref<const Eigen::VectorXd>& u,
                    Eigen::Ref<Eigen::VectorXd> qdot) {
  if (mob.kind != MobilizerKind::Free) {
    for (int k = 0; k < mob.nu; ++k) qdot[mob.first_q + k] = u[mob.first_u + k];
    return;
  }
  const int iq = mob.first_q, iu = mob.first_u;
  const double e0 = q[iq];
  const Eigen::Vector3d e = q.segment<3>(iq + 1), w = u.segment<3>(iu);
  qdot[iq] = -0.5 * e.dot(w);
  qdot.segment<3>(iq + 1) = 0.5 * (e0 * w + w.cross(e));
  qdot.segment<3>(iq + 4) = u.segment<3>(iu + 3);
}

}  // namespace dmbd::model::detail
