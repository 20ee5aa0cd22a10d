// The sphere-on-ground contact law (model/src/contact.hpp) against independent
// computations: the Hertz constant and sinkage against the closed form written out here
// (k = E^(2/3)/2, c = 4/3 k sqrt(R k)); the implicit parts K = -dF/dp and D = -dF/dv
// against central differences of force_W with respect to the contact point's position
// (penetration and anchor offset) and velocity; the stick force against -k_t offset with
// k_t = mu F_n / delta_s built here from the closed-form F_n; the slip force against the
// Coulomb cone; the anchor's return map against the cone; the potential's derivative
// against the elastic force.
#include "contact.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace dmbd::model::detail {
namespace {

constexpr double kRadius = 0.03;  // DRACO's collision spheres (draco.urdf)

// The Hertz constant from the closed form, written independently of contact.cpp.
double closed_form_hertz(double radius, double E) {
  const double k = 0.5 * std::cbrt(E * E);
  return 4.0 / 3.0 * k * std::sqrt(radius * k);
}

// The elastic normal force c x^1.5 from the closed form.
double closed_form_elastic(const ContactParams& p, double x) {
  return closed_form_hertz(kRadius, p.stiffness_Pa) * std::pow(x, 1.5);
}

// The force on the robot at a contact point at p (world, ground z = 0) with velocity v,
// anchored at a: penetration -p_z, anchor offset p_xy - a.
Eigen::Vector3d force_at(const ContactParams& cp, const Eigen::Vector3d& p, const Eigen::Vector3d& v,
                         const Eigen::Vector2d& a) {
  return sphere_contact(cp, kRadius, -p.z(), v, p.head<2>() - a).force_W;
}

bool all_zero(const Eigen::MatrixXd& m) { return (m.array() == 0.0).all(); }

double rel(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); }

TEST(ContactHertz, SinkageInvertsTheElasticForce) {
  const ContactParams cp;
  double worst = 0;
  for (double F : {0.5, 45.0, 88.0, 363.0, 2000.0}) {
    const double x = hertz_sinkage(F, kRadius, cp.stiffness_Pa);
    const SphereContact c = sphere_contact(cp, kRadius, x, Eigen::Vector3d::Zero(), Eigen::Vector2d::Zero());
    worst = std::max(worst, rel(c.normal_force_N, F));
  }
  // pow(., 2/3) then x * sqrt(x): a few roundings of relative 1e-16 each.
  EXPECT_LT(worst, 1e-12);
  EXPECT_EQ(hertz_sinkage(0.0, kRadius, cp.stiffness_Pa), 0.0);
  EXPECT_EQ(hertz_sinkage(-5.0, kRadius, cp.stiffness_Pa), 0.0);
  std::printf("hertz_sinkage inverted by the elastic force (0.5 .. 2000 N): worst relative error %.2g\n", worst);
}

TEST(ContactHertz, DracoSphereSinkageMatchesClosedForm) {
  const double E = 1e7, F = 45.0;  // plane-strain modulus; 37 kg x 9.81 on eight spheres
  const double c = closed_form_hertz(kRadius, E);
  const double x = std::pow(F / c, 2.0 / 3.0);
  // Both are the same closed form evaluated with different rounding (cbrt vs pow).
  EXPECT_LT(rel(hertz_constant(kRadius, E), c), 1e-14);
  EXPECT_LT(rel(hertz_sinkage(F, kRadius, E), x), 1e-14);
  // A gross check of the closed form itself: c = 4/3 E* sqrt(R) with E* = k^1.5 = E / 2^1.5.
  EXPECT_LT(rel(c, 4.0 / 3.0 * E / std::pow(2.0, 1.5) * std::sqrt(kRadius)), 1e-14);
  std::printf("3 cm sphere, E = 1e7 Pa: c = %.6g N/m^1.5, sinkage under 45 N %.4f mm (library %.4f mm)\n", c,
              x * 1e3, hertz_sinkage(F, kRadius, E) * 1e3);
}

TEST(ContactNormal, NoForceWhenNotTouching) {
  const ContactParams cp;
  for (double x : {0.0, -1e-9, -0.01}) {
    const SphereContact c = sphere_contact(cp, kRadius, x, Eigen::Vector3d(0.1, 0.2, -0.5), Eigen::Vector2d(1e-4, 0));
    EXPECT_FALSE(c.touching);
    EXPECT_FALSE(c.sliding);
    EXPECT_TRUE(all_zero(c.force_W));
    EXPECT_TRUE(all_zero(c.K));
    EXPECT_TRUE(all_zero(c.D));
    EXPECT_EQ(c.potential_J, 0.0);
  }
}

TEST(ContactNormal, NoPullWhenSeparatingFast) {
  const ContactParams cp;  // d = 2 s/m: 1 + 1.5 d xdot = 0 at xdot = -1/3 m/s
  const double x = 1e-3, xdot_zero = -1.0 / (1.5 * cp.dissipation_s_per_m);
  for (double xdot : {xdot_zero * 1.001, 2 * xdot_zero, -5.0}) {
    // Separating: the point moves up (+z), xdot = -v_z < 0.
    const SphereContact c = sphere_contact(cp, kRadius, x, Eigen::Vector3d(0.05, 0, -xdot), Eigen::Vector2d(5e-4, 0));
    EXPECT_TRUE(c.touching);
    EXPECT_EQ(c.normal_force_N, 0.0);
    EXPECT_TRUE(all_zero(c.force_W));  // no friction without load either
  }
  // Just inside the limit the force is the positive Hunt-Crossley value.
  const double xdot = 0.9 * xdot_zero;
  const SphereContact c = sphere_contact(cp, kRadius, x, Eigen::Vector3d(0, 0, -xdot), Eigen::Vector2d::Zero());
  const double expected = closed_form_elastic(cp, x) * (1 + 1.5 * cp.dissipation_s_per_m * xdot);
  EXPECT_GT(c.normal_force_N, 0.0);
  EXPECT_LT(rel(c.normal_force_N, expected), 1e-12);  // the same product, different rounding
}

// -dF/dp and -dF/dv by central differences.
void finite_difference_jacobians(const ContactParams& cp, const Eigen::Vector3d& p, const Eigen::Vector3d& v,
                                 const Eigen::Vector2d& a, double hp, double hv, Eigen::Matrix3d& K,
                                 Eigen::Matrix3d& D) {
  for (int j = 0; j < 3; ++j) {
    const Eigen::Vector3d dp = hp * Eigen::Vector3d::Unit(j), dv = hv * Eigen::Vector3d::Unit(j);
    K.col(j) = -(force_at(cp, p + dp, v, a) - force_at(cp, p - dp, v, a)) / (2 * hp);
    D.col(j) = -(force_at(cp, p, v + dv, a) - force_at(cp, p, v - dv, a)) / (2 * hv);
  }
}

TEST(ContactJacobians, StickKAndDMatchFiniteDifferences) {
  const ContactParams cp;
  const Eigen::Vector2d a(0.1, -0.2);
  const Eigen::Vector3d p(a.x() + 2e-4, a.y() - 1e-4, -1e-3);  // 1 mm deep, offset 0.22 mm
  const Eigen::Vector3d v(1e-3, -5e-4, -0.01);                 // approaching at 1 cm/s
  const SphereContact c = sphere_contact(cp, kRadius, -p.z(), v, p.head<2>() - a);
  ASSERT_FALSE(c.sliding);
  const double ft = c.force_W.head<2>().norm(), cap = cp.friction * c.normal_force_N;
  ASSERT_LT(ft, 0.5 * cap);  // well inside the cone: the +-h steps cannot cross it
  Eigen::Matrix3d Kfd, Dfd;
  // Position step 1e-7 m = 1e-4 x: truncation (h/x)^2 x 0.03 ~ 3e-10 relative on dF_n/dx
  // (the third derivative of x^1.5); rounding eps F / h ~ 3e-8 N/m against 4e4 N/m. The
  // force is linear in the offset and the velocity, so those columns carry rounding only.
  finite_difference_jacobians(cp, p, v, a, 1e-7, 1e-6, Kfd, Dfd);
  // The law is load-proportional in stick, f_t = F_n g(offset, v_t): the tangential force
  // also varies with the penetration and its rate, -df_t/dp_z = (f_t / F_n) dF_n/dx. The
  // header keeps these couplings out of K and D (only the stiff diagonal is implicit), so
  // the full Jacobian is K plus them.
  Eigen::Matrix3d Kfull = c.K, Dfull = c.D;
  Kfull.block<2, 1>(0, 2) = c.force_W.head<2>() / c.normal_force_N * c.K(2, 2);
  Dfull.block<2, 1>(0, 2) = c.force_W.head<2>() / c.normal_force_N * c.D(2, 2);
  const double eK = (Kfd - Kfull).cwiseAbs().maxCoeff() / c.K.cwiseAbs().maxCoeff();
  const double eD = (Dfd - Dfull).cwiseAbs().maxCoeff() / c.D.cwiseAbs().maxCoeff();
  EXPECT_LT(eK, 1e-7);
  EXPECT_LT(eD, 1e-7);
  // The diagonal the stepper uses: K(2,2) = dF_n/dx, K(0,0) = K(1,1) = k_t, D likewise.
  const double Fn = closed_form_elastic(cp, -p.z()) * (1 + 1.5 * cp.dissipation_s_per_m * -v.z());
  EXPECT_LT(rel(c.K(0, 0), cp.friction * Fn / cp.stiction_displacement_m), 1e-12);
  EXPECT_LT(rel(c.D(0, 0), cp.friction * Fn / cp.stiction_velocity_m_s), 1e-12);
  EXPECT_EQ(c.K(1, 1), c.K(0, 0));
  EXPECT_EQ(c.D(1, 1), c.D(0, 0));
  std::printf("stick K, D vs central differences: %.2g, %.2g relative (K diag %.4g %.4g %.4g N/m, D diag %.4g %.4g "
              "%.4g N s/m; omitted couplings |K(0:1,2)| %.3g N/m, |D(0:1,2)| %.3g N s/m)\n",
              eK, eD, c.K(0, 0), c.K(1, 1), c.K(2, 2), c.D(0, 0), c.D(1, 1), c.D(2, 2),
              Kfull.block<2, 1>(0, 2).norm(), Dfull.block<2, 1>(0, 2).norm());
}

TEST(ContactFriction, StickForceIsTheSpring) {
  const ContactParams cp;
  const double x = 1.5e-3;
  const Eigen::Vector2d offset(3e-4, -4e-4);  // |offset| = 0.5 delta_s
  const SphereContact c = sphere_contact(cp, kRadius, x, Eigen::Vector3d::Zero(), offset);
  const double kt = cp.friction * closed_form_elastic(cp, x) / cp.stiction_displacement_m;
  EXPECT_FALSE(c.sliding);
  // The same products in another order: a few ulps.
  EXPECT_LT((c.force_W.head<2>() + kt * offset).norm() / (kt * offset.norm()), 1e-13);
  EXPECT_LT(rel(c.normal_force_N, closed_form_elastic(cp, x)), 1e-13);
}

TEST(ContactFriction, SlipForceIsOnTheCone) {
  const ContactParams cp;
  const double x = 1.5e-3;
  const Eigen::Vector2d offset(1.5e-3, 2e-3);  // |offset| = 2.5 delta_s
  const Eigen::Vector3d v(0.03, -0.01, 0.0);
  const SphereContact c = sphere_contact(cp, kRadius, x, v, offset);
  const double Fn = closed_form_elastic(cp, x);
  const Eigen::Vector2d trial =
      -cp.friction * Fn * (offset / cp.stiction_displacement_m + v.head<2>() / cp.stiction_velocity_m_s);
  const Eigen::Vector2d ft = c.force_W.head<2>();
  EXPECT_TRUE(c.sliding);
  EXPECT_LT(rel(ft.norm(), cp.friction * Fn), 1e-13);
  // Along the trial spring-damper force (against the offset and the slip velocity):
  // unit vectors agree to rounding.
  EXPECT_LT((ft.normalized() - trial.normalized()).norm(), 1e-13);
  EXPECT_TRUE(all_zero(c.K.block<2, 2>(0, 0)));  // sliding friction is explicit
  EXPECT_TRUE(all_zero(c.D.block<2, 2>(0, 0)));
  EXPECT_GT(c.K(2, 2), 0.0);  // the normal direction stays implicit
  std::printf("slip: |f_t| = %.6g N, mu F_n = %.6g N\n", ft.norm(), cp.friction * Fn);
}

TEST(ContactFriction, SlideAnchorReturnMap) {
  const ContactParams cp;
  const double x = 1.5e-3, Fn = closed_form_elastic(cp, x);
  const Eigen::Vector2d inside(6e-4, 7e-4);  // 0.92 delta_s
  EXPECT_EQ(slide_anchor(cp, inside), inside);
  const Eigen::Vector2d outside(-3e-3, 4e-3);  // 5 delta_s
  const Eigen::Vector2d mapped = slide_anchor(cp, outside);
  EXPECT_LT(rel(mapped.norm(), cp.stiction_displacement_m), 1e-14);
  EXPECT_LT(std::abs(mapped.x() * outside.y() - mapped.y() * outside.x()), 1e-20);  // parallel (cross ~ eps |.|^2)
  EXPECT_GT(mapped.dot(outside), 0.0);                                                 // and the same way
  // After the map the spring force -k_t offset is on the cone.
  const SphereContact c = sphere_contact(cp, kRadius, x, Eigen::Vector3d::Zero(), mapped);
  const double kt = cp.friction * Fn / cp.stiction_displacement_m;
  EXPECT_LT(rel(kt * mapped.norm(), cp.friction * Fn), 1e-13);
  EXPECT_LT(rel(c.force_W.head<2>().norm(), cp.friction * Fn), 1e-13);
  std::printf("slide_anchor: |offset| 5 mm -> %.6g mm; spring force %.6g N on the cone %.6g N\n",
              mapped.norm() * 1e3, c.force_W.head<2>().norm(), cp.friction * Fn);
}

TEST(ContactPotential, DerivativeIsTheElasticForce) {
  const ContactParams cp;
  const double x = 1e-3, h = 1e-8;  // h / x = 1e-5: truncation ~1e-11, rounding eps U / h ~ 1e-10 N of 26 N
  auto U = [&](double xx, const Eigen::Vector2d& off) {
    return sphere_contact(cp, kRadius, xx, Eigen::Vector3d::Zero(), off).potential_J;
  };
  const Eigen::Vector2d zero = Eigen::Vector2d::Zero();
  const double dU = (U(x + h, zero) - U(x - h, zero)) / (2 * h);
  const double e = rel(dU, closed_form_elastic(cp, x));
  EXPECT_LT(e, 1e-8);
  // And the tangential spring: dU/d(offset) = k_t offset = -f_t (U is quadratic in it: exact
  // up to rounding eps U / h).
  const Eigen::Vector2d off(3e-4, 1e-4);
  const double ho = 1e-6;
  Eigen::Vector2d grad;
  for (int j = 0; j < 2; ++j) {
    const Eigen::Vector2d d = ho * Eigen::Vector2d::Unit(j);
    grad[j] = (U(x, off + d) - U(x, off - d)) / (2 * ho);
  }
  const Eigen::Vector2d ft = sphere_contact(cp, kRadius, x, Eigen::Vector3d::Zero(), off).force_W.head<2>();
  const double et = (grad + ft).norm() / ft.norm();
  EXPECT_LT(et, 1e-7);
  std::printf("potential: dU/dx vs c x^1.5 %.2g relative; dU/doffset vs -f_t %.2g relative\n", e, et);
}

}  // namespace
}  // namespace dmbd::model::detail
