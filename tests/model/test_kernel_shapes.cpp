// The contact laws of boxes, meshes and cylinders (model/src/contact.hpp,
// rim_contact.hpp, convex_hull.hpp) against independent computations: the rim's force,
// moment and energy against a quadrature over its points (penetration along n written
// out here), the sub-arcs against the whole; the point law against k x (1 + d xdot) and
// its K, D against central differences; qhull's hull of a cube with points on and inside
// it against its 8 corners; farthest-point sampling against its definition.
#include "contact.hpp"
#include "convex_hull.hpp"
#include "ground_frame.hpp"
#include "rim_contact.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <random>

namespace dmbd::model::detail {
namespace {

constexpr double kPi = 3.14159265358979323846;

// int x dphi, the moment about c of the forces n x (per unit kappa R) and int x^2/2 dphi,
// over the ring's points c + R (e1 cos t + e2 sin t), x = max(0, -n . p): midpoint rule,
// any basis e1, e2 of the rim's plane.
struct Quadrature {
  double load = 0, energy = 0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
};
Quadrature quadrature(const Eigen::Vector3d& c, const Eigen::Vector3d& a, double R, const Eigen::Vector3d& n, int N) {
  const Eigen::Vector3d e1 = a.unitOrthogonal(), e2 = a.cross(e1);
  Quadrature q;
  const double dt = 2 * kPi / N;
  for (int k = 0; k < N; ++k) {
    const double t = (k + 0.5) * dt;
    const Eigen::Vector3d p = c + R * (std::cos(t) * e1 + std::sin(t) * e2);
    const double x = std::max(0.0, -n.dot(p));
    q.load += x * dt;
    q.energy += 0.5 * x * x * dt;
    q.moment += (p - c).cross(n) * x * dt;
  }
  return q;
}

struct RimCase {
  const char* what;
  Eigen::Vector3d c, a;
};

TEST(ContactRim, ForceMomentAndEnergyEqualAQuadratureOverTheRing) {
  const double R = 0.05;
  const Eigen::Vector3d n = Eigen::Vector3d(0.1, -0.2, 1.0).normalized();
  const RimCase cases[] = {
      {"tilted, partly in", Eigen::Vector3d(0.3, 0.1, 0.02), Eigen::Vector3d(0.2, 0.9, 0.3).normalized()},
      {"lying on its side", Eigen::Vector3d(0, 0, 0.0495), n.unitOrthogonal()},
      {"flat, wholly in", Eigen::Vector3d(0.1 * n.unitOrthogonal() - 0.001 * n), n},
      {"nearly flat, wholly in", Eigen::Vector3d(0, 0, -0.004), (n + Eigen::Vector3d(0.02, 0, 0)).normalized()},
  };
  double worst = 0;
  for (const RimCase& rc : cases) {
    const double h = n.dot(rc.c);
    const RimPenetration r = rim_penetration(rc.c, rc.a, R, n, h);
    ASSERT_TRUE(r.touching) << rc.what;
    // 2e5 midpoints: the integrand has a kink where x reaches 0 (error ~ dt^2 there).
    const Quadrature q = quadrature(rc.c, rc.a, R, n, 200000);
    Eigen::Vector3d moment = Eigen::Vector3d::Zero();
    double load = 0;
    for (const RimArc& arc : r.arcs) {
      load += arc.load_m;
      moment += (arc.p_W - rc.c).cross(n) * arc.load_m;
    }
    const Eigen::Vector3d cop_moment = (r.cop_W - rc.c).cross(n) * r.load_m;
    const double e_load = std::abs(r.load_m - q.load) / q.load, e_arcs = std::abs(load - r.load_m) / r.load_m;
    const double e_moment = (moment - q.moment).norm() / (R * q.load), e_cop = (cop_moment - q.moment).norm() / (R * q.load);
    const double e_energy = std::abs(r.energy_m2 - q.energy) / q.energy;
    std::printf("%-24s load %.6e m rad: quadrature %.2g, sub-arcs %.2g; moment: sub-arcs %.2g, CoP %.2g; energy %.2g\n",
                rc.what, r.load_m, e_load, e_arcs, e_moment, e_cop, e_energy);
    for (double e : {e_load, e_moment, e_cop, e_energy}) worst = std::max(worst, e);
    EXPECT_LT(e_arcs, 1e-12) << rc.what;  // the same integral split four ways
  }
  EXPECT_LT(worst, 1e-8);  // quadrature error ~ (2 pi / 2e5)^2 at the kinks
}

TEST(ContactRim, ClosedFormsOfTheRestingCylinder) {
  const double R = 0.05, x = 2e-4;
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  // Standing on its face: the whole ring sinks by x, int x dphi = 2 pi x.
  const RimPenetration face = rim_penetration(Eigen::Vector3d(0, 0, -x), n, R, n, -x);
  EXPECT_NEAR(face.load_m, 2 * kPi * x, 1e-15);
  EXPECT_LT((face.cop_W - Eigen::Vector3d(0, 0, -x)).norm(), 1e-15);
  // On its side: pm = acos(1 - x/R), int x dphi = 2 R (sin pm - pm cos pm).
  const double pm = std::acos(1 - x / R);
  const RimPenetration side = rim_penetration(Eigen::Vector3d(0, 0, R - x), Eigen::Vector3d::UnitX(), R, n, R - x);
  EXPECT_LT(std::abs(side.load_m - 2 * R * (std::sin(pm) - pm * std::cos(pm))) / side.load_m, 1e-9);
  EXPECT_NEAR(side.deepest_m, x, 1e-15);
  EXPECT_NEAR(side.cop_W.x(), 0.0, 1e-15);
  EXPECT_NEAR(side.cop_W.y(), 0.0, 1e-15);
  EXPECT_LT(side.cop_W.z(), 0.0);  // the CoP lies inside the penetrated segment
  EXPECT_GT(side.cop_W.z(), -x);
  EXPECT_DOUBLE_EQ(rim_load(R, 1.0, R - x), side.load_m);
  // Above the ground: nothing.
  EXPECT_FALSE(rim_penetration(Eigen::Vector3d(0, 0, R + 1e-9), Eigen::Vector3d::UnitX(), R, n, R + 1e-9).touching);
  EXPECT_EQ(rim_load(R, 1.0, R + 1e-9), 0.0);
}

TEST(ContactPoint, LinearHuntCrossleyAndItsJacobians) {
  ContactParams cp;
  const double k = cp.point_stiffness_N_per_m, d = cp.point_dissipation_s_per_m;
  const double x = 4e-4, xdot = 0.05;
  const ContactForce c = point_contact(cp, x, Eigen::Vector3d(0, 0, -xdot), Eigen::Vector2d::Zero());
  EXPECT_NEAR(c.normal_force_N, k * x * (1 + d * xdot), 1e-12);
  EXPECT_NEAR(c.potential_J, 0.5 * k * x * x, 1e-15);
  // -dF/dp_z and -dF/dv_z by central differences (F is bilinear in x and xdot: exact up
  // to rounding).
  auto F = [&](double xx, double vz) { return point_contact(cp, xx, Eigen::Vector3d(0, 0, vz), Eigen::Vector2d::Zero()).force_W.z(); };
  const double hx = 1e-7, hv = 1e-5;
  const double K = (F(x + hx, -xdot) - F(x - hx, -xdot)) / (2 * hx), D = -(F(x, -xdot + hv) - F(x, -xdot - hv)) / (2 * hv);
  EXPECT_LT(std::abs(K - c.K(2, 2)) / c.K(2, 2), 1e-8);
  EXPECT_LT(std::abs(D - c.D(2, 2)) / c.D(2, 2), 1e-8);
  // No pull: separating faster than 1/d.
  EXPECT_EQ(point_contact(cp, x, Eigen::Vector3d(0, 0, 1.01 / d), Eigen::Vector2d::Zero()).normal_force_N, 0.0);
  EXPECT_FALSE(point_contact(cp, -1e-9, Eigen::Vector3d::Zero(), Eigen::Vector2d::Zero()).touching);
}

TEST(ContactGround, TiltedFrameIsOrthonormalAndLevelGroundIsTheIdentity) {
  const GroundFrame level(Eigen::Vector3d(0, 0, 3));
  EXPECT_TRUE(level.is_z());
  const Eigen::Vector3d v(0.1, -0.2, 0.3);
  EXPECT_EQ(level.to_ground(v), v);
  EXPECT_EQ(level.height(v), v.z());
  const Eigen::Vector3d n = Eigen::Vector3d(-std::sin(0.2), 0, std::cos(0.2));
  const GroundFrame slope(n);
  EXPECT_FALSE(slope.is_z());
  const Eigen::Vector3d g = slope.to_ground(v);
  EXPECT_NEAR(g.norm(), v.norm(), 1e-15);
  EXPECT_NEAR(g.z(), n.dot(v), 1e-15);
  EXPECT_THROW(GroundFrame(Eigen::Vector3d(1, 0, 0)), ModelError);
  EXPECT_THROW(GroundFrame(Eigen::Vector3d(0, 0, std::nan(""))), ModelError);
}

TEST(ConvexHull, CubeWithPointsOnAndInsideItHasItsEightCorners) {
  std::vector<Eigen::Vector3f> pts;
  for (int k = 0; k < 8; ++k) pts.emplace_back(k & 1 ? 0.05f : -0.05f, k & 2 ? 0.05f : -0.05f, k & 4 ? 0.05f : -0.05f);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-0.049f, 0.049f);
  for (int k = 0; k < 200; ++k) pts.emplace_back(u(rng), u(rng), u(rng));  // inside
  for (int f = 0; f < 3; ++f) pts.push_back(0.05f * Eigen::Vector3f::Unit(f));  // face centres: on the hull, not vertices
  const std::vector<Eigen::Vector3d> hull = convex_hull_vertices(pts);
  ASSERT_EQ(hull.size(), 8u);
  for (const Eigen::Vector3d& p : hull) EXPECT_NEAR(p.cwiseAbs().minCoeff(), 0.05, 1e-8);
  // A flat set: joggled, and its corners are among the vertices.
  std::vector<Eigen::Vector3f> flat;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) flat.emplace_back(0.01f * i, 0.01f * j, 0.0f);
  const std::vector<Eigen::Vector3d> fh = convex_hull_vertices(flat);
  int corners = 0;
  for (const Eigen::Vector3d& p : fh)
    if ((std::abs(p.x()) < 1e-6 || std::abs(p.x() - 0.04) < 1e-6) && (std::abs(p.y()) < 1e-6 || std::abs(p.y() - 0.04) < 1e-6)) ++corners;
  EXPECT_EQ(corners, 4);
  std::printf("hull of a cube with 203 more points: %zu vertices; of a flat 5 x 5 grid: %zu\n", hull.size(), fh.size());
}

TEST(ConvexHull, FarthestPointSamplingSpreadsThePoints) {
  // Points on a line at 0, 1, ..., 10: the farthest from the centroid 5 is 0 (the first of
  // the tie with 10), then 10, then 5; then 2, 3, 7 and 8 tie at distance 2: the first, 2.
  std::vector<Eigen::Vector3d> line;
  for (int k = 0; k <= 10; ++k) line.emplace_back(k, 0, 0);
  const std::vector<Eigen::Vector3d> four = farthest_points(line, 4);
  ASSERT_EQ(four.size(), 4u);
  EXPECT_EQ(four[0].x(), 0.0);
  EXPECT_EQ(four[1].x(), 10.0);
  EXPECT_EQ(four[2].x(), 5.0);
  EXPECT_EQ(four[3].x(), 2.0);
  EXPECT_EQ(farthest_points(line, 20).size(), line.size());
}

}  // namespace
}  // namespace dmbd::model::detail
