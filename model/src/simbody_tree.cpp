#include "simbody_tree.hpp"

#include "dmbd/model/error.hpp"

#include <cmath>

namespace dmbd::model::detail {

SimTK::Transform to_simtk(const Eigen::Isometry3d& X) {
  const Eigen::Matrix3d& R = X.linear();
  SimTK::Mat33 m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = R(i, j);
  // Re-orthonormalises (the Eigen rotation may carry rounding from products).
  return SimTK::Transform(SimTK::Rotation(m), to_simtk(Eigen::Vector3d(X.translation())));
}

Eigen::Isometry3d to_eigen(const SimTK::Transform& X) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out.linear()(i, j) = X.R().asMat33()(i, j);
  out.translation() = to_eigen(X.p());
  return out;
}

namespace {

bool has_dofs(JointType t) { return t != JointType::Fixed; }

SimTK::Body::Rigid make_body(const Link& l, double taken) {
  const double m = l.mass_kg;
  if (m <= 0) return SimTK::Body::Rigid(SimTK::MassProperties(0, SimTK::Vec3(0), SimTK::Inertia(0)));
  const double keep = m - taken;
  const double f = keep / m;
  const Eigen::Matrix3d Ic = l.inertia_kgm2 * f;
  const Eigen::Vector3d c = l.com_m;
  // Inertia about the body origin (Simbody's MassProperties convention): parallel axes.
  const Eigen::Matrix3d Io = Ic + keep * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  const SimTK::Inertia I(SimTK::Vec3(Io(0, 0), Io(1, 1), Io(2, 2)), SimTK::Vec3(Io(0, 1), Io(0, 2), Io(1, 2)));
  return SimTK::Body::Rigid(SimTK::MassProperties(keep, to_simtk(c), I));
}

// A rotation whose `which` axis is along `axis`.
SimTK::Rotation align(const Eigen::Vector3d& axis, SimTK::CoordinateAxis which) {
  return SimTK::Rotation(SimTK::UnitVec3(to_simtk(axis.normalized())), which);
}

}  // namespace

Tree build_tree(const RobotDescription& robot, SimTK::SimbodyMatterSubsystem& matter, BaseMode base,
                const Eigen::Isometry3d& X_WB, const std::vector<double>& mass_taken) {
  Tree t;
  const std::size_t nl = robot.links.size();
  if (nl == 0) throw ModelError(robot.source + ": the robot has no links");
  t.link_body.assign(nl, SimTK::MobilizedBodyIndex());
  t.link_mass.assign(nl, 0.0);
  auto taken = [&](std::size_t l) { return l < mass_taken.size() ? mass_taken[l] : 0.0; };
  for (std::size_t l = 0; l < nl; ++l) t.link_mass[l] = robot.links[l].mass_kg - taken(l);
  const std::vector<double> sub = subtree_masses(robot);

  SimTK::MobilizedBody& ground = matter.updGround();
  if (base == BaseMode::Floating) {
    SimTK::MobilizedBody::Free root(ground, SimTK::Transform(), make_body(robot.links[0], taken(0)), SimTK::Transform());
    root.setDefaultTransform(to_simtk(X_WB));
    t.root = root.getMobilizedBodyIndex();
    t.base_dofs = 6;
  } else {
    SimTK::MobilizedBody::Weld root(ground, to_simtk(X_WB), make_body(robot.links[0], taken(0)), SimTK::Transform());
    t.root = root.getMobilizedBodyIndex();
  }
  t.link_body[0] = t.root;

  for (std::size_t j = 0; j < robot.joints.size(); ++j) {
    const Joint& jt = robot.joints[j];
    const int p = robot.link_index(jt.parent), c = robot.link_index(jt.child);
    if (p < 0 || c < 0 || !t.link_body[static_cast<std::size_t>(p)].isValid())
      throw ModelError(robot.source + ": joint '" + jt.name + "': links not in tree order");
    SimTK::MobilizedBody& parent = matter.updMobilizedBody(t.link_body[static_cast<std::size_t>(p)]);
    const SimTK::Transform X_PJ = to_simtk(jt.X_PJ);
    const SimTK::Body::Rigid body = make_body(robot.links[static_cast<std::size_t>(c)], taken(static_cast<std::size_t>(c)));
    JointType type = jt.type;
    // A 1-dof joint whose subtree has no mass would make the mass matrix singular.
    if (has_dofs(type) && type != JointType::Floating && sub[static_cast<std::size_t>(c)] <= 0) {
      t.welded.push_back(jt.name);
      type = JointType::Fixed;
    }
    SimTK::MobilizedBodyIndex idx;
    switch (type) {
      case JointType::Fixed:
        idx = SimTK::MobilizedBody::Weld(parent, X_PJ, body, SimTK::Transform()).getMobilizedBodyIndex();
        break;
      case JointType::Revolute:
      case JointType::Continuous: {
        const SimTK::Transform A(align(jt.axis, SimTK::ZAxis), SimTK::Vec3(0));
        idx = SimTK::MobilizedBody::Pin(parent, X_PJ * A, body, A).getMobilizedBodyIndex();
        break;
      }
      case JointType::Prismatic: {
        const SimTK::Transform A(align(jt.axis, SimTK::XAxis), SimTK::Vec3(0));
        idx = SimTK::MobilizedBody::Slider(parent, X_PJ * A, body, A).getMobilizedBodyIndex();
        break;
      }
      case JointType::Floating:
        idx = SimTK::MobilizedBody::Free(parent, X_PJ, body, SimTK::Transform()).getMobilizedBodyIndex();
        break;
      case JointType::Planar: {
        // Simbody's Planar: rotation about z, translation in x-y; the URDF axis is the normal.
        const SimTK::Transform A(align(jt.axis, SimTK::ZAxis), SimTK::Vec3(0));
        idx = SimTK::MobilizedBody::Planar(parent, X_PJ * A, body, A).getMobilizedBodyIndex();
        break;
      }
    }
    t.link_body[static_cast<std::size_t>(c)] = idx;
    if (type == JointType::Revolute || type == JointType::Continuous || type == JointType::Prismatic) {
      t.coord_joint.push_back(static_cast<int>(j));
      t.coord_body.push_back(idx);
      t.joint_names.push_back(jt.name);
    }
  }
  return t;
}

Eigen::VectorXd gather_q(const Tree& t, const SimTK::SimbodyMatterSubsystem& m, const SimTK::State& s) {
  const int nb = t.base_dofs ? 7 : 0;
  Eigen::VectorXd q(nb + static_cast<int>(t.coord_body.size()));
  if (nb) {
    const SimTK::Vector& qr = m.getMobilizedBody(t.root).getQAsVector(s);
    for (int i = 0; i < 7; ++i) q[i] = qr[i];
  }
  for (std::size_t k = 0; k < t.coord_body.size(); ++k)
    q[nb + static_cast<int>(k)] = m.getMobilizedBody(t.coord_body[k]).getOneQ(s, 0);
  return q;
}

Eigen::VectorXd gather_u(const Tree& t, const SimTK::SimbodyMatterSubsystem& m, const SimTK::State& s) {
  const int nb = t.base_dofs;
  Eigen::VectorXd u(nb + static_cast<int>(t.coord_body.size()));
  if (nb) {
    const SimTK::Vector& ur = m.getMobilizedBody(t.root).getUAsVector(s);
    for (int i = 0; i < 6; ++i) u[i] = ur[i];
  }
  for (std::size_t k = 0; k < t.coord_body.size(); ++k)
    u[nb + static_cast<int>(k)] = m.getMobilizedBody(t.coord_body[k]).getOneU(s, 0);
  return u;
}

void scatter_q(const Tree& t, const SimTK::SimbodyMatterSubsystem& m, SimTK::State& s, const Eigen::VectorXd& q) {
  const int nb = t.base_dofs ? 7 : 0;
  if (q.size() != nb + static_cast<int>(t.coord_body.size()))
    throw ModelError("configuration has " + std::to_string(q.size()) + " entries, expected " +
                     std::to_string(nb + t.coord_body.size()));
  if (nb) {
    SimTK::Vector qr(7);
    for (int i = 0; i < 7; ++i) qr[i] = q[i];
    m.getMobilizedBody(t.root).setQFromVector(s, qr);
  }
  for (std::size_t k = 0; k < t.coord_body.size(); ++k)
    m.getMobilizedBody(t.coord_body[k]).setOneQ(s, 0, q[nb + static_cast<int>(k)]);
}

void scatter_u(const Tree& t, const SimTK::SimbodyMatterSubsystem& m, SimTK::State& s, const Eigen::VectorXd& u) {
  const int nb = t.base_dofs;
  if (u.size() != nb + static_cast<int>(t.coord_body.size()))
    throw ModelError("velocity has " + std::to_string(u.size()) + " entries, expected " +
                     std::to_string(nb + t.coord_body.size()));
  if (nb) {
    SimTK::Vector ur(6);
    for (int i = 0; i < 6; ++i) ur[i] = u[i];
    m.getMobilizedBody(t.root).setUFromVector(s, ur);
  }
  for (std::size_t k = 0; k < t.coord_body.size(); ++k)
    m.getMobilizedBody(t.coord_body[k]).setOneU(s, 0, u[nb + static_cast<int>(k)]);
}

}  // namespace dmbd::model::detail
