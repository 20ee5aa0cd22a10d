// Contact of boxes, meshes and cylinders with the ground (docs/model.md, "Contact"),
// against closed forms of the stated rules, in the fixed and the accurate integrator:
// resting heights (a box and a box mesh sink by m g / (4 k), a cylinder on its face by
// m g / (2 pi kappa R), on its side by the ring integral's root), a box sliding to a stop
// at mu g, a cylinder rolling down a slope at (2/3) g sin(theta) and sliding down a steeper
// one at g (sin - mu cos), a box at rest on a slope, the energy of undamped drops, a mesh
// decimated to 64 hull points with one warning, a missing collision mesh skipped.
#include "dmbd/model/error.hpp"
#include "dmbd/model/plant.hpp"

#include "contact_fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace dmbd::model {
namespace {

constexpr double kG = 9.81, kPi = 3.14159265358979323846;

PlantOptions with(Integration mode) {
  PlantOptions o;
  o.integration = mode;
  o.step_s = 5e-4;
  return o;
}

const char* name(Integration mode) { return mode == Integration::Fixed ? "fixed" : "accurate"; }

Eigen::Isometry3d rotated(const Eigen::Vector3d& axis, double angle) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  return X;
}

// Lifts the base by dz, lets it fall and settle for t seconds; returns the base height.
double drop_and_settle(Plant& p, double dz, double t) {
  Eigen::Isometry3d X = p.base_pose();
  X.translation().z() += dz;
  p.set_base_pose(X);
  for (int k = 1; k <= static_cast<int>(t * 100); ++k) p.advance_to(k * 0.01);
  return p.base_pose().translation().z();
}

// The resting height z_pred after reset() (the placement's bisection) and after a 2 mm
// drop and 2 s of settling, relative to the sinkage x: |z - z_pred| / x.
void expect_rests_at(const RobotDescription& r, PlantOptions o, double z_pred, double x, const char* what) {
  for (Integration mode : {Integration::Fixed, Integration::Accurate}) {
    o.integration = mode;
    Plant p(r, o);
    const double placed = std::abs(p.base_pose().translation().z() - z_pred) / x;
    const double settled = std::abs(drop_and_settle(p, 2e-3, 2.0) - z_pred) / x;
    std::printf("%s, %s: sinkage %.4f mm; placed %.2g, settled after a 2 mm drop %.2g of it off the closed form\n", what,
                name(mode), x * 1e3, placed, settled);
    EXPECT_LT(placed, 1e-9) << what;    // bisection to adjacent doubles of the lift
    EXPECT_LT(settled, 1e-6) << what;   // the oscillation decays (d = 2 s/m) to this in 2 s
  }
}

TEST(PlantShapes, BoxRestsAtHalfItsHeightMinusWeightOverFourK) {
  const Eigen::Vector3d s(0.2, 0.15, 0.05);
  const double m = 10;
  const PlantOptions o;
  const double x = m * kG / (4 * o.contact_params.point_stiffness_N_per_m);
  expect_rests_at(testing::single_body(testing::box_xml(s), m, testing::box_inertia(m, s)), o, s.z() / 2 - x, x, "box");
}

TEST(PlantShapes, BoxMeshRestsLikeTheBox) {
  const testing::TempDir tmp("box_mesh");
  const std::string& dir = tmp.path;
  const Eigen::Vector3d s(0.2, 0.15, 0.05);
  testing::write_box_obj(dir + "/box.obj", s);
  const double m = 10;
  const RobotDescription r = testing::single_body("<mesh filename=\"box.obj\"/>", m, testing::box_inertia(m, s), dir);
  ASSERT_EQ(r.links[0].collisions[0].geometry.hull_m.size(), 8u);  // 14 vertices, the 8 corners on the hull
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  const PlantOptions o;
  const double x = m * kG / (4 * o.contact_params.point_stiffness_N_per_m);
  const double half = static_cast<double>(static_cast<float>(s.z() / 2));  // a mesh keeps its vertices as floats
  expect_rests_at(r, o, half - x, x, "box mesh");
  Plant p(r, o);
  ASSERT_EQ(p.contacts().size(), 1u);
  EXPECT_EQ(p.contacts()[0].kind, Geometry::Kind::Mesh);
  EXPECT_NEAR(p.contacts()[0].force_W.z(), m * kG, 1e-9 * m * kG);  // placed: carries the weight
}

TEST(PlantShapes, CylinderRestsOnItsFaceAndOnItsSide) {
  const double R = 0.05, L = 0.12, m = 5;
  const RobotDescription r = testing::single_body(testing::cylinder_xml(R, L), m, testing::cylinder_inertia(m, R, L));
  PlantOptions o;
  const double kappa = o.contact_params.rim_stiffness_N_per_m2;
  const double x_face = m * kG / (2 * kPi * kappa * R);
  expect_rests_at(r, o, L / 2 - x_face, x_face, "cylinder on its face");
  // On its side each rim carries m g / 2 = 2 kappa R^2 (sin pm - pm cos pm): pm by bisection.
  double lo = 0, hi = kPi / 2;
  for (int k = 0; k < 200; ++k) {
    const double pm = 0.5 * (lo + hi);
    (2 * kappa * R * R * (std::sin(pm) - pm * std::cos(pm)) < m * kG / 2 ? lo : hi) = pm;
  }
  const double x_side = R * (1 - std::cos(0.5 * (lo + hi)));
  o.X_WB = rotated(Eigen::Vector3d::UnitX(), kPi / 2);
  expect_rests_at(r, o, R - x_side, x_side, "cylinder on its side");
}

TEST(PlantShapes, MeshWithMoreThan64HullVerticesKeeps64AndWarnsOnce) {
  const testing::TempDir tmp("ball_mesh");
  const std::string& dir = tmp.path;
  testing::write_sphere_obj(dir + "/ball.obj", 0.05, 15, 24);  // 362 vertices, all on the hull
  const RobotDescription r = testing::single_body("<mesh filename=\"ball.obj\"/>", 1.0, Eigen::Vector3d::Constant(1e-3), dir);
  const std::vector<Eigen::Vector3d>& hull = r.links[0].collisions[0].geometry.hull_m;
  EXPECT_EQ(hull.size(), 64u);
  ASSERT_EQ(r.warnings.size(), 1u);
  const std::string& w = r.warnings[0];
  EXPECT_EQ(w.rfind(dir + "/body.urdf:6: link 'body': ", 0), 0u) << w;  // the <mesh> line
  EXPECT_NE(w.find("362 convex-hull vertices"), std::string::npos) << w;
  EXPECT_NE(w.find("64"), std::string::npos) << w;
  for (const Eigen::Vector3d& p : hull) EXPECT_NEAR(p.norm(), 0.05, 1e-6);  // hull vertices (floats) of the ball
  Plant p(r);
  ASSERT_EQ(p.contacts().size(), 1u);
  EXPECT_GT(p.contacts()[0].force_W.z(), 0.5 * kG);
}

TEST(PlantShapes, MissingCollisionMeshIsSkippedWithOneWarning) {
  const testing::TempDir tmp("no_mesh");
  const std::string& dir = tmp.path;
  const RobotDescription r = testing::single_body("<mesh filename=\"nothere.obj\"/>", 1.0, Eigen::Vector3d::Constant(1e-3), dir);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0].rfind(dir + "/body.urdf:6: link 'body': ", 0), 0u) << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("collision shape is skipped (no contact)"), std::string::npos) << r.warnings[0];
  PlantOptions o;
  o.X_WB.translation().z() = 1.0;
  Plant p(r, o);
  EXPECT_TRUE(p.contacts().empty());
  EXPECT_EQ(p.base_pose().translation().z(), 1.0);  // nothing to place on the ground
}

TEST(PlantShapes, RefusesBadContactParametersAndADownwardGround) {
  const RobotDescription r = testing::single_body(testing::box_xml({0.1, 0.1, 0.1}), 1.0, Eigen::Vector3d::Constant(1e-3));
  auto error = [&](PlantOptions o) {
    try {
      Plant p(r, o);
    } catch (const ModelError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  PlantOptions o;
  o.contact_params.point_stiffness_N_per_m = -1e5;
  EXPECT_EQ(error(o).rfind("plant: contact_params.point_stiffness_N_per_m = -100000", 0), 0u) << error(o);
  o = {};
  o.contact_params.rim_stiffness_N_per_m2 = 0;
  EXPECT_NE(error(o).find("rim_stiffness_N_per_m2 = 0.000000 (expected a finite value > 0)"), std::string::npos) << error(o);
  o = {};
  o.contact_params.point_dissipation_s_per_m = std::nan("");
  EXPECT_NE(error(o).find("point_dissipation_s_per_m"), std::string::npos) << error(o);
  o = {};
  o.ground_normal = Eigen::Vector3d(0, 0.2, -1);
  EXPECT_NE(error(o).find("ground_normal (0.000000, 0.200000, -1.000000) is not a finite upward direction"), std::string::npos)
      << error(o);
  o = {};
  o.contact = false;
  o.contact_params.point_stiffness_N_per_m = -1;  // no contact: not used
  EXPECT_EQ(error(o), "(accepted)");
}

// Pushed at its centre of mass to 1.2 m/s, then let go: it decelerates at mu g
// while it slides (|v| >> v_s = 0.01 m/s, the friction on the cone).
TEST(PlantShapes, BoxSlidesToAStopAtMuG) {
  const Eigen::Vector3d s(0.3, 0.3, 0.04);
  const double m = 4, mu = 0.5;
  const RobotDescription r = testing::single_body(testing::box_xml(s), m, testing::box_inertia(m, s));
  for (Integration mode : {Integration::Fixed, Integration::Accurate}) {
    PlantOptions o = with(mode);
    o.contact_params.friction = mu;
    Plant p(r, o);
    p.set_external_force(0, Eigen::Vector3d::Zero(), Eigen::Vector3d(m * (mu * kG + 4), 0, 0));
    p.advance_to(0.3);
    p.clear_external_forces();
    p.advance_to(0.35);
    const double v1 = p.base_velocity()[3];
    p.advance_to(0.5);
    const double v2 = p.base_velocity()[3], a = (v1 - v2) / 0.15;
    std::printf("box sliding, %s: %.3f -> %.3f m/s, deceleration %.5f m/s^2 against mu g = %.5f (%.2g)\n", name(mode), v1, v2, a,
                mu * kG, a / (mu * kG) - 1);
    EXPECT_GT(v2, 0.1);
    EXPECT_LT(std::abs(a / (mu * kG) - 1), 0.02);
  }
}

// A cylinder (axis along y, in the slope) on ground tilted by theta about y: rolls at
// (2/3) g sin(theta) when mu > tan(theta) / 3, else slides at g (sin - mu cos) with its
// centre while friction mu m g cos spins it up.
double slope_acceleration(double theta, double mu, Integration mode, double* slip) {
  const double R = 0.05, L = 0.1, m = 2;
  const RobotDescription r = testing::single_body(testing::cylinder_xml(R, L), m, testing::cylinder_inertia(m, R, L));
  PlantOptions o = with(mode);
  o.contact_params.friction = mu;
  o.ground_normal = Eigen::Vector3d(-std::sin(theta), 0, std::cos(theta));
  o.X_WB = rotated(Eigen::Vector3d::UnitX(), -kPi / 2);  // the cylinder's z along world y
  Plant p(r, o);
  const Eigen::Vector3d down(-std::cos(theta), 0, -std::sin(theta));
  p.advance_to(0.1);
  const double v1 = down.dot(p.base_velocity().tail<3>());
  p.advance_to(0.6);
  const double v2 = down.dot(p.base_velocity().tail<3>());
  *slip = v2 + p.base_velocity()[1] * R;  // rolling down (-x): v = -omega_y R
  return (v2 - v1) / 0.5;
}

TEST(PlantShapes, CylinderRollsDownASlopeAtTwoThirdsGSinTheta) {
  const double theta = 10 * kPi / 180, mu = 0.8;  // tan(theta) / 3 = 0.059
  for (Integration mode : {Integration::Fixed, Integration::Accurate}) {
    double slip = 0;
    const double a = slope_acceleration(theta, mu, mode, &slip), expected = 2.0 / 3.0 * kG * std::sin(theta);
    std::printf("rolling, %s: %.5f m/s^2 against (2/3) g sin = %.5f (%.2g); slip speed %.2e m/s\n", name(mode), a, expected,
                a / expected - 1, slip);
    EXPECT_LT(std::abs(a / expected - 1), 0.02);
    EXPECT_LT(std::abs(slip), 0.01);
  }
}

TEST(PlantShapes, CylinderSlidesDownASteepSlopeAtGSinMinusMuCos) {
  const double theta = 20 * kPi / 180, mu = 0.05;  // tan(theta) / 3 = 0.121
  double slip = 0;
  const double a = slope_acceleration(theta, mu, Integration::Fixed, &slip);
  const double expected = kG * (std::sin(theta) - mu * std::cos(theta));
  std::printf("sliding down: %.5f m/s^2 against g (sin - mu cos) = %.5f (%.2g); slip speed %.3f m/s\n", a, expected,
              a / expected - 1, slip);
  EXPECT_LT(std::abs(a / expected - 1), 0.02);
  EXPECT_GT(slip, 0.3);  // v - omega R = (g sin - 3 mu g cos) t grows: it slides
}

// On a 10-degree slope with mu = 0.8 a box sticks; its centre's height along n is half
// its height less the mean corner sinkage m g cos(theta) / (4 k).
TEST(PlantShapes, BoxStaysPutOnASlopeAtItsSinkageAlongTheNormal) {
  const Eigen::Vector3d s(0.2, 0.15, 0.05);
  const double m = 10, theta = 10 * kPi / 180;
  PlantOptions o = with(Integration::Fixed);
  o.ground_normal = Eigen::Vector3d(-std::sin(theta), 0, std::cos(theta));
  o.X_WB = rotated(Eigen::Vector3d::UnitY(), -theta);  // its bottom face on the slope
  Plant p(testing::single_body(testing::box_xml(s), m, testing::box_inertia(m, s)), o);
  const Eigen::Vector3d c0 = p.base_pose().translation();
  p.advance_to(1.0);
  const Eigen::Vector3d c1 = p.base_pose().translation();
  const double x = m * kG * std::cos(theta) / (4 * o.contact_params.point_stiffness_N_per_m);
  const double err = std::abs(o.ground_normal.dot(c1) - (s.z() / 2 - x)) / x;
  std::printf("box on a 10-degree slope, 1 s: moved %.2e m, height along n off by %.2g of the sinkage %.4f mm\n",
              (c1 - c0).norm(), err, x * 1e3);
  EXPECT_LT((c1 - c0).norm(), 1e-3);  // sticks (the tangential springs take up < delta_s = 1 mm)
  EXPECT_LT(err, 1e-3);               // the friction moment tilts it by ~1e-3 rad: second order
}

// Three spheres under a body (a tripod) on a 10-degree slope: placed along n, each sinks
// by the Hertz deflection of a third of m g cos(theta); with mu = 0.8 the tripod sticks
// and stays at that height along n.
TEST(PlantShapes, SphereTripodOnASlopeIsPlacedAlongTheNormal) {
  const double R = 0.03, m = 6, theta = 10 * kPi / 180;
  RobotDescription r;
  r.name = "tripod";
  Link l;
  l.name = "body";
  l.mass_kg = m;
  l.inertia_kgm2 = Eigen::Vector3d(0.05, 0.05, 0.08).asDiagonal();
  for (int k = 0; k < 3; ++k) {
    Shape s;
    s.geometry.kind = Geometry::Kind::Sphere;
    s.geometry.radius_m = R;
    s.X_LG.translation() = 0.15 * Eigen::Vector3d(std::cos(2 * kPi * k / 3), std::sin(2 * kPi * k / 3), 0);
    l.collisions.push_back(s);
  }
  r.links.push_back(l);
  PlantOptions o = with(Integration::Fixed);
  o.ground_normal = Eigen::Vector3d(-std::sin(theta), 0, std::cos(theta));
  o.X_WB = rotated(Eigen::Vector3d::UnitY(), -theta);
  Plant p(r, o);
  // The Hertz sinkage, from its closed form c = 4/3 k sqrt(R k), k = E^(2/3) / 2.
  const double k = 0.5 * std::cbrt(o.contact_params.stiffness_Pa * o.contact_params.stiffness_Pa);
  const double x = std::pow(m * kG * std::cos(theta) / 3 / (4.0 / 3.0 * k * std::sqrt(R * k)), 2.0 / 3.0);
  const double placed = std::abs(o.ground_normal.dot(p.base_pose().translation()) - (R - x)) / x;
  const Eigen::Vector3d c0 = p.base_pose().translation();
  p.advance_to(1.0);
  const double settled = std::abs(o.ground_normal.dot(p.base_pose().translation()) - (R - x)) / x;
  std::printf("sphere tripod on a 10-degree slope: sinkage %.4f mm; placed %.2g, after 1 s %.2g of it off; moved %.2e m\n",
              x * 1e3, placed, settled, (p.base_pose().translation() - c0).norm());
  EXPECT_LT(placed, 1e-9);
  EXPECT_LT(settled, 1e-3);  // sticks: the friction moment tilts it to second order
  EXPECT_LT((p.base_pose().translation() - c0).norm(), 1e-3);
}

// No damping, no friction, accurate integration: a tilted box and a tilted cylinder
// dropped 3 cm bounce on their springs; the total energy stays.
TEST(PlantShapes, UndampedDropsConserveEnergy) {
  const Eigen::Vector3d s(0.2, 0.15, 0.05);
  const double m = 3, R = 0.05, L = 0.1;
  const RobotDescription shapes[] = {testing::single_body(testing::box_xml(s), m, testing::box_inertia(m, s)),
                                     testing::single_body(testing::cylinder_xml(R, L), m, testing::cylinder_inertia(m, R, L))};
  for (const RobotDescription& r : shapes) {
    PlantOptions o;
    o.contact_params.point_dissipation_s_per_m = 0;
    o.contact_params.friction = 0;
    o.accuracy = 1e-9;
    o.X_WB = rotated(Eigen::Vector3d(1, 2, 0), 0.3);
    Plant p(r, o);
    drop_and_settle(p, 0.0, 0.0);
    Eigen::Isometry3d X = p.base_pose();
    X.translation().z() += 0.03;
    p.set_base_pose(X);
    const double e0 = p.kinetic_energy() + p.potential_energy(), scale = m * kG * 0.03;
    double worst = 0, most_pen = 0;
    for (int k = 1; k <= 50; ++k) {
      p.advance_to(0.01 * k);
      worst = std::max(worst, std::abs(p.kinetic_energy() + p.potential_energy() - e0));
      for (const ContactReading& c : p.contacts()) most_pen = std::max(most_pen, c.penetration_m);
    }
    std::printf("undamped %s drop, 0.5 s: max |dE| %.3g J of the 3 cm drop's %.3f J (%.2g); deepest %.2f mm\n",
                r.links[0].collisions[0].geometry.kind == Geometry::Kind::Box ? "box" : "cylinder", worst, scale, worst / scale,
                most_pen * 1e3);
    EXPECT_GT(most_pen, 1e-4);  // it did land
    EXPECT_LT(worst / scale, 1e-5);
  }
}

}  // namespace
}  // namespace dmbd::model
