// PlantDynamics' ground contact (plant_dynamics.hpp): every collision shape's elements
// (contact_elements.hpp) under their laws (contact.hpp for spheres and points,
// rim_contact.hpp for cylinder rims), in the ground's frame (ground_frame.hpp); the
// friction anchors' return map; the readings; and the static loads that place a robot
// on the ground. docs/model.md, "Contact", states the rules.
#include "plant_dynamics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dmbd::model::detail {

namespace {

// The return map of a sphere's or a point's anchor after a step, the contact point at
// tangent coordinates p_t: set where it first touches, dragged so that |p - a| <= delta_s.
// Geometry only (slide_anchor needs no force): the contact law is not evaluated here.
void seat_anchor(const ContactParams& cp, bool touching, const Eigen::Vector2d& p_t, SphereAnchor& an) {
  if (!touching) {
    an.active = false;
  } else if (!an.active) {
    an.active = true;
    an.anchor = p_t;
  } else {
    an.anchor = p_t - slide_anchor(cp, p_t - an.anchor);
  }
}

}  // namespace

Eigen::Vector3d PlantDynamics::point_columns(int body, const Eigen::Vector3d& p_W) {
  const std::vector<int>& mob = kernel_.body_mobilities(body);
  const int m = static_cast<int>(mob.size());
  kernel_.point_jacobian_columns(body, p_W, G_.leftCols(m));
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (int c = 0; c < m; ++c) v += G_.col(c) * V_[mob[static_cast<std::size_t>(c)]];
  return v;
}

// v_p = v_c + omega' x (p - c) with omega' = (I - a a^T) omega: G = J_c - [p - c]x (I - a a^T) J_omega.
Eigen::Vector3d PlantDynamics::rim_columns(int body, const Eigen::Vector3d& c, const Eigen::Vector3d& a, const Eigen::Vector3d& p_W) {
  const std::vector<int>& mob = kernel_.body_mobilities(body);
  const int m = static_cast<int>(mob.size());
  kernel_.frame_jacobian_columns(body, c, J6_.leftCols(m));
  const Eigen::Vector3d r = p_W - c;
  Eigen::Matrix3d rx;
  rx << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
  const Eigen::Matrix3d B = rx * (Eigen::Matrix3d::Identity() - a * a.transpose());
  G_.leftCols(m) = J6_.bottomRows<3>().leftCols(m);
  G_.leftCols(m).noalias() -= B * J6_.topRows<3>().leftCols(m);
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (int k = 0; k < m; ++k) v += G_.col(k) * V_[mob[static_cast<std::size_t>(k)]];
  return v;
}

void PlantDynamics::add_contacts(double h) {
  add_sphere_contacts(h);
  add_point_contacts(h);
  add_rim_contacts(h);
}

// Consecutive elements of one body (a foot's four spheres, a box's corners) are gathered
// at its origin and projected through its frame Jacobian once (add_body_terms) instead
// of one 3 x m point Jacobian each. Starts t on `body`, projecting what t held before.
void PlantDynamics::gather_on(BodyTerms& t, int body) {
  if (body == t.body) return;
  add_body_terms(t);
  t = BodyTerms();
  t.body = body;
  t.o = kernel_.origin(body);
}

void PlantDynamics::add_sphere_contacts(double h) {
  BodyTerms t;
  for (std::size_t i = 0; i < contact_.spheres.size(); ++i) {
    const ContactSphere& sp = contact_.spheres[i];
    gather_on(t, sp.body);
    const Eigen::Vector3d center = world_point(sp.body, sp.center_B);
    const double pen = sp.radius_m - ground_.height(center);
    if (!(pen > 0)) continue;
    const Eigen::Vector3d p = center - sp.radius_m * ground_.n();
    const Eigen::Vector3d v = kernel_.point_velocity(sp.body, p);
    const Eigen::Vector2d offset =
        anchors[i].active ? Eigen::Vector2d(ground_.tangent(p) - anchors[i].anchor) : Eigen::Vector2d::Zero();
    SphereContact sc = sphere_contact_hertz(opt_.contact_params, sphere_hertz_[i], pen, ground_.to_ground(v), offset);
    ground_.to_world(sc);
    t.add(p, sc.force_W, h * sc.D + h * h * sc.K, sc.K * v);
  }
  add_body_terms(t);
}

void PlantDynamics::add_point_contacts(double h) {
  BodyTerms t;
  for (std::size_t i = 0; i < contact_.points.size(); ++i) {
    const ContactPoint& pt = contact_.points[i];
    gather_on(t, pt.body);
    const Eigen::Vector3d p = world_point(pt.body, pt.p_B);
    const double pen = -ground_.height(p);
    if (!(pen > 0)) continue;
    const Eigen::Vector3d v = kernel_.point_velocity(pt.body, p);
    const SphereAnchor& an = point_anchors[i];
    const Eigen::Vector2d offset = an.active ? Eigen::Vector2d(ground_.tangent(p) - an.anchor) : Eigen::Vector2d::Zero();
    ContactForce c = point_contact(opt_.contact_params, pen, ground_.to_ground(v), offset);
    ground_.to_world(c);
    t.add(p, c.force_W, h * c.D + h * h * c.K, c.K * v);
  }
  add_body_terms(t);
}

// Each penetrated sub-arc: its share of the ring's force along n at its own centre of
// pressure, stiffness kappa R (its angle) along n, damping d kappa R (its load) along n,
// both through the rim's motion without its spin (rim_columns); then the friction at the
// material point.
void PlantDynamics::add_rim_contacts(double h) {
  const ContactParams& cp = opt_.contact_params;
  const Eigen::Vector3d& n = ground_.n();
  const Eigen::Matrix3d nn = n * n.transpose();
  for (std::size_t i = 0; i < contact_.rims.size(); ++i) {
    const RimContact rc = rim_contact_now(static_cast<int>(i));
    if (!rc.ring.touching || !(rc.factor > 0)) continue;
    const ContactRim& rim = contact_.rims[i];
    const std::vector<int>& mob = kernel_.body_mobilities(rim.body);
    const int m = static_cast<int>(mob.size());
    const double kR = cp.rim_stiffness_N_per_m2 * rim.radius_m;
    const Eigen::Vector3d c = world_point(rim.body, rim.center_B), a = kernel_.rotation(rim.body) * rim.axis_B;
    for (const RimArc& arc : rc.ring.arcs) {
      const Eigen::Vector3d v = rim_columns(rim.body, c, a, arc.p_W);
      const Eigen::Matrix3d K = (kR * arc.width_rad * rc.factor) * nn;
      const Eigen::Matrix3d D = (cp.point_dissipation_s_per_m * kR * arc.load_m) * nn;
      add_point_term(mob, m, (kR * arc.load_m * rc.factor) * n, h * D + h * h * K, &K, &v);
    }
    const Eigen::Vector3d v = point_columns(rim.body, rc.material_W);
    const ContactForce& f = rc.friction;
    add_point_term(mob, m, f.force_W, h * f.D + h * h * f.K, &f.K, &v);
  }
}

SphereContact PlantDynamics::sphere_contact_now(int sphere, Eigen::Vector3d* p_W) const {
  const ContactSphere& sp = contact_.spheres[static_cast<std::size_t>(sphere)];
  const Eigen::Vector3d center = world_point(sp.body, sp.center_B);
  const Eigen::Vector3d p = center - sp.radius_m * ground_.n();
  if (p_W) *p_W = p;
  const SphereAnchor& an = anchors[static_cast<std::size_t>(sphere)];
  const Eigen::Vector2d offset = an.active ? Eigen::Vector2d(ground_.tangent(p) - an.anchor) : Eigen::Vector2d::Zero();
  const double pen = sp.radius_m - ground_.height(center);
  SphereContact sc = sphere_contact_hertz(opt_.contact_params, sphere_hertz_[static_cast<std::size_t>(sphere)], pen,
                                          ground_.to_ground(kernel_.point_velocity(sp.body, p)), offset);
  ground_.to_world(sc);
  return sc;
}

ContactForce PlantDynamics::point_contact_now(int point, Eigen::Vector3d* p_W) const {
  const ContactPoint& pt = contact_.points[static_cast<std::size_t>(point)];
  const Eigen::Vector3d p = world_point(pt.body, pt.p_B);
  if (p_W) *p_W = p;
  const SphereAnchor& an = point_anchors[static_cast<std::size_t>(point)];
  const Eigen::Vector2d offset = an.active ? Eigen::Vector2d(ground_.tangent(p) - an.anchor) : Eigen::Vector2d::Zero();
  ContactForce c = point_contact(opt_.contact_params, -ground_.height(p), ground_.to_ground(kernel_.point_velocity(pt.body, p)),
                                 offset);
  ground_.to_world(c);
  return c;
}

// The ring's force F = kappa R (load) (1 + d xdot_cop), xdot_cop the centre of
// pressure's penetration rate; friction at the material point with that F.
RimContact PlantDynamics::rim_contact_now(int index) const {
  const ContactRim& rim = contact_.rims[static_cast<std::size_t>(index)];
  const ContactParams& cp = opt_.contact_params;
  RimContact rc;
  const Eigen::Vector3d c = world_point(rim.body, rim.center_B);
  rc.ring = rim_penetration(c, kernel_.rotation(rim.body) * rim.axis_B, rim.radius_m, ground_.n(), ground_.height(c));
  if (!rc.ring.touching) return rc;
  const double kR = cp.rim_stiffness_N_per_m2 * rim.radius_m;
  const double xdot = -ground_.n().dot(kernel_.point_velocity(rim.body, rc.ring.cop_W));
  rc.factor = std::max(0.0, 1.0 + cp.point_dissipation_s_per_m * xdot);
  rc.normal_force_N = kR * rc.ring.load_m * rc.factor;
  const RimFriction& fr = rim_friction[static_cast<std::size_t>(index)];
  rc.material_W = fr.active ? world_point(rim.body, fr.material_B) : rc.ring.cop_W;
  const Eigen::Vector2d offset =
      fr.active ? Eigen::Vector2d(ground_.tangent(rc.material_W) - fr.anchor) : Eigen::Vector2d::Zero();
  const Eigen::Vector3d v = ground_.to_ground(kernel_.point_velocity(rim.body, rc.material_W));
  rc.friction.touching = true;
  rc.friction.normal_force_N = rc.normal_force_N;
  anchor_friction(cp, offset, v.head<2>(), rc.friction);
  ground_.to_world(rc.friction);
  rc.potential_J = kR * rc.ring.energy_m2 + rc.friction.potential_J;
  return rc;
}

void PlantDynamics::update_anchors() {
  const ContactParams& cp = opt_.contact_params;
  for (std::size_t i = 0; i < contact_.spheres.size(); ++i) {  // touching: as sphere_contact decides
    const ContactSphere& sp = contact_.spheres[i];
    const Eigen::Vector3d center = world_point(sp.body, sp.center_B);
    const double pen = sp.radius_m - ground_.height(center);
    seat_anchor(cp, pen > 0, ground_.tangent(center - sp.radius_m * ground_.n()), anchors[i]);
  }
  for (std::size_t i = 0; i < contact_.points.size(); ++i) {  // as point_contact decides
    const ContactPoint& pt = contact_.points[i];
    const Eigen::Vector3d p = world_point(pt.body, pt.p_B);
    seat_anchor(cp, -ground_.height(p) > 0, ground_.tangent(p), point_anchors[i]);
  }
  // A rim's deflection is carried over to the new centre of pressure: the material point
  // moved by its slip since the last step, so rolling adds nothing to it.
  for (std::size_t i = 0; i < contact_.rims.size(); ++i) {
    const RimContact rc = rim_contact_now(static_cast<int>(i));
    RimFriction& fr = rim_friction[i];
    if (!rc.ring.touching) {
      fr.active = false;
      continue;
    }
    const Eigen::Vector2d deflection =
        fr.active ? slide_anchor(cp, ground_.tangent(rc.material_W) - fr.anchor) : Eigen::Vector2d::Zero();
    const int body = contact_.rims[i].body;
    fr.active = true;
    fr.anchor = ground_.tangent(rc.ring.cop_W) - deflection;
    fr.material_B = kernel_.rotation(body).transpose() * (rc.ring.cop_W - kernel_.origin(body));
  }
}

void PlantDynamics::reset_anchors() {
  std::fill(anchors.begin(), anchors.end(), SphereAnchor{});
  std::fill(point_anchors.begin(), point_anchors.end(), SphereAnchor{});
  std::fill(rim_friction.begin(), rim_friction.end(), RimFriction{});
}

void PlantDynamics::add_contact_potential(double& e) const {
  for (std::size_t i = 0; i < contact_.spheres.size(); ++i) e += sphere_contact_now(static_cast<int>(i)).potential_J;
  for (std::size_t i = 0; i < contact_.points.size(); ++i) e += point_contact_now(static_cast<int>(i)).potential_J;
  for (std::size_t i = 0; i < contact_.rims.size(); ++i) e += rim_contact_now(static_cast<int>(i)).potential_J;
}

ContactReading PlantDynamics::contact_reading(int shape) const {
  const ContactShape& rec = contact_.shapes[static_cast<std::size_t>(shape)];
  ContactReading out;
  out.link = rec.link;
  out.shape = rec.shape;
  out.kind = rec.kind;
  if (rec.kind == Geometry::Kind::Sphere) {
    const SphereContact sc = sphere_contact_now(rec.first, &out.p_W);
    out.force_W = sc.force_W;
    out.penetration_m = sc.penetration_m;
    return out;
  }
  // The normal forces' centre of pressure; the lowest point while nothing touches.
  double fn = 0, lowest = std::numeric_limits<double>::infinity();
  Eigen::Vector3d moment = Eigen::Vector3d::Zero(), low = Eigen::Vector3d::Zero();
  auto add = [&](const Eigen::Vector3d& f, double normal, const Eigen::Vector3d& at, double pen, const Eigen::Vector3d& p_low) {
    out.force_W += f;
    fn += normal;
    moment += normal * at;
    out.penetration_m = std::max(out.penetration_m, pen);
    if (ground_.height(p_low) < lowest) {
      lowest = ground_.height(p_low);
      low = p_low;
    }
  };
  for (int k = rec.first; k < rec.first + rec.count; ++k) {
    if (rec.kind == Geometry::Kind::Cylinder) {
      const RimContact rc = rim_contact_now(k);
      const ContactRim& rim = contact_.rims[static_cast<std::size_t>(k)];
      const Eigen::Vector3d c = world_point(rim.body, rim.center_B);
      const Eigen::Vector3d p_low = rim_lowest_point(c, kernel_.rotation(rim.body) * rim.axis_B, rim.radius_m, ground_.n());
      add(rc.normal_force_N * ground_.n() + rc.friction.force_W, rc.normal_force_N, rc.ring.cop_W, rc.ring.deepest_m, p_low);
    } else {
      Eigen::Vector3d p;
      const ContactForce c = point_contact_now(k, &p);
      add(c.force_W, c.normal_force_N, p, c.penetration_m, p);
    }
  }
  out.p_W = fn > 0 ? Eigen::Vector3d(moment / fn) : low;
  return out;
}

double PlantDynamics::lowest_contact_height() const {
  double lowest = std::numeric_limits<double>::infinity();
  for (const ContactSphere& sp : contact_.spheres)
    lowest = std::min(lowest, ground_.height(world_point(sp.body, sp.center_B)) - sp.radius_m);
  for (const ContactPoint& pt : contact_.points) lowest = std::min(lowest, ground_.height(world_point(pt.body, pt.p_B)));
  for (const ContactRim& rim : contact_.rims) {
    const Eigen::Vector3d a = kernel_.rotation(rim.body) * rim.axis_B;
    lowest = std::min(lowest, ground_.height(world_point(rim.body, rim.center_B)) - rim.radius_m * rim_tilt_sine(a, ground_.n()));
  }
  return lowest;
}

double PlantDynamics::static_contact_load(double lift) const {
  const ContactParams& cp = opt_.contact_params;
  double load = 0;
  for (const ContactSphere& sp : contact_.spheres) {
    const double x = sp.radius_m - ground_.height(world_point(sp.body, sp.center_B)) - lift;
    if (x > 0) load += hertz_constant(sp.radius_m, cp.stiffness_Pa) * x * std::sqrt(x);
  }
  for (const ContactPoint& pt : contact_.points)
    load += cp.point_stiffness_N_per_m * std::max(0.0, -ground_.height(world_point(pt.body, pt.p_B)) - lift);
  for (const ContactRim& rim : contact_.rims) {
    const Eigen::Vector3d a = kernel_.rotation(rim.body) * rim.axis_B;
    const double h = ground_.height(world_point(rim.body, rim.center_B)) + lift;
    load += cp.rim_stiffness_N_per_m2 * rim.radius_m * rim_load(rim.radius_m, rim_tilt_sine(a, ground_.n()), h);
  }
  return load;
}

}  // namespace dmbd::model::detail
