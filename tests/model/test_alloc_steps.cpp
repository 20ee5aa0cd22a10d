// No heap allocation in a fixed simulation step or in a controller's dynamics update
// after warm-up (issue 12). The C allocator is interposed in this executable to
// count allocations (malloc, calloc, realloc: what operator new, Eigen and Simbody all
// use). Simbody's calcM, for one, allocates 52 blocks a call, which this test would catch.
#include "robot_files.hpp"
#include "dmbd/model/dynamics.hpp"
#include "dmbd/model/plant.hpp"

#include <gtest/gtest.h>

#include "malloc_counter.hpp"
#include "plant_fixtures.hpp"


using dmbd::test::g_allocations;

namespace dmbd::model {
namespace {

const RobotDescription& draco() {
  static const RobotDescription r = load_urdf(DMBD_ROBOTS_DIR "/draco/draco.urdf", UrdfOptions{{}, false, false});
  return r;
}

TEST(NoAllocation, FixedStepOfTheRobotStandingOnItsActuators) {
  DMBD_SKIP_UNDER_ASAN();
  PlantOptions o;
  o.actuators = dmbd::test::draco_actuators();
  o.integration = Integration::Fixed;
  o.step_s = 5e-4;
  Plant p(draco(), o);
  Eigen::VectorXd i = Eigen::VectorXd::Constant(p.num_actuators(), 0.5);
  p.set_currents(i);
  p.set_external_force(0, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 40, 0));
  p.advance_to(0.01);  // warm-up: contacts engage, odeint and Eigen buffers exist
  const long before = g_allocations.load();
  for (int k = 2; k <= 200; ++k) {
    i[k % p.num_actuators()] = 0.01 * k;
    p.set_currents(i);  // inputs change every millisecond, as under a controller
    p.advance_to(0.005 * k);
  }
  EXPECT_EQ(g_allocations.load() - before, 0) << "allocations in 398 fixed steps";
  EXPECT_GT(p.integrator_steps(), 390);
  // The counter sees allocations made inside the library: a reading that returns a vector.
  const long b = g_allocations.load();
  EXPECT_EQ(p.joint_positions().size(), 10);
  EXPECT_GT(g_allocations.load() - b, 0);
}

// One floating body on a box, a lying cylinder and a mesh (its hull points given), all
// touching the ground, pushed so that every contact law and its friction run.
RobotDescription three_shapes() {
  RobotDescription r;
  r.name = "three_shapes";
  Link l;
  l.name = "body";
  l.mass_kg = 6;
  l.inertia_kgm2 = Eigen::Vector3d(0.05, 0.1, 0.1).asDiagonal();
  Shape box, cyl, mesh;
  box.geometry.kind = Geometry::Kind::Box;
  box.geometry.box_size_m = Eigen::Vector3d(0.1, 0.1, 0.1);
  box.X_LG.translation() = Eigen::Vector3d(-0.2, 0, 0);
  cyl.geometry.kind = Geometry::Kind::Cylinder;
  cyl.geometry.radius_m = 0.05;
  cyl.geometry.length_m = 0.1;
  cyl.X_LG.linear() = Eigen::AngleAxisd(1.5707963267948966, Eigen::Vector3d::UnitX()).toRotationMatrix();
  mesh.geometry.kind = Geometry::Kind::Mesh;
  for (int k = 0; k < 8; ++k) mesh.geometry.hull_m.emplace_back(k & 1 ? 0.05 : -0.05, k & 2 ? 0.05 : -0.05, k & 4 ? 0.05 : -0.05);
  mesh.X_LG.translation() = Eigen::Vector3d(0.2, 0, 0);
  l.collisions = {box, cyl, mesh};
  r.links.push_back(l);
  return r;
}

TEST(NoAllocation, FixedStepOnABoxACylinderAndAMesh) {
  DMBD_SKIP_UNDER_ASAN();
  PlantOptions o;
  o.integration = Integration::Fixed;
  o.ground_normal = Eigen::Vector3d(-0.1, 0, 1);  // a slope: the general ground frame
  Plant p(three_shapes(), o);
  p.set_external_force(0, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 30, 0));
  p.advance_to(0.01);
  const long before = g_allocations.load();
  for (int k = 2; k <= 100; ++k) p.advance_to(0.005 * k);
  EXPECT_EQ(g_allocations.load() - before, 0) << "allocations in 198 fixed steps";
  int touching = 0;
  for (const ContactReading& c : p.contacts()) touching += c.force_W.z() > 0.1;  // the rims, softer at 0.1 mm, carry ~0.7 N
  EXPECT_EQ(touching, 3);  // every law ran
}

// A hip, knee and ankle chain on a geared ROTARY (no spring
// coordinate) and two ROTARY_SEAs, with Coulomb friction moving in and out of its cone.
TEST(NoAllocation, FixedStepOnRotaryActuators) {
  DMBD_SKIP_UNDER_ASAN();
  RobotDescription r;
  r.name = "chain";
  r.links.push_back(testing::point_link("base", 1.0, {0, 0, 0}, 0.01));
  r.links.push_back(testing::point_link("thigh", 2.0, {0, 0, -0.2}, 0.02));
  r.links.push_back(testing::point_link("shank", 1.5, {0, 0, -0.2}, 0.01));
  r.links.push_back(testing::point_link("foot", 0.5, {0.05, 0, -0.03}, 0.001));
  r.joints.push_back(testing::revolute("hip", "base", "thigh", {0, 0, 0}, {0, 1, 0}));
  r.joints.push_back(testing::revolute("knee", "thigh", "shank", {0, 0, -0.4}, {0, 1, 0}));
  r.joints.push_back(testing::revolute("ankle", "shank", "foot", {0, 0, -0.4}, {0, 1, 0}));
  PlantOptions o;
  o.base = BaseMode::Fixed;
  o.contact = false;
  o.integration = Integration::Fixed;
  for (const char* j : {"hip", "knee", "ankle"}) {
    ActuatorParams a;
    a.joint = j;
    a.kind = std::string(j) == "hip" ? ActuatorKind::ROTARY : ActuatorKind::ROTARY_SEA;
    a.N_m_rad_per_m = 50;
    a.K_s_N_per_m = 300;
    a.B_s_Ns_per_m = 0.5;
    a.B_l_Ns_per_m = 0.02;
    a.torque_limit_Nm = 30;
    a.viscous_friction_Nms = 0.1;
    a.coulomb_friction_Nm = 0.5;
    a.M_r_kg = 0;
    o.actuators.push_back(a);
  }
  Plant p(r, o);
  Eigen::VectorXd i = Eigen::VectorXd::Constant(3, 0.5);
  p.set_currents(i);
  p.advance_to(0.01);
  const long before = g_allocations.load();
  for (int k = 2; k <= 200; ++k) {
    i[k % 3] = (k % 7 - 3) * 0.5;
    p.set_currents(i);
    p.advance_to(0.005 * k);
  }
  EXPECT_EQ(g_allocations.load() - before, 0) << "allocations in 398 fixed steps";
  EXPECT_GT(p.integrator_steps(), 390);
}

TEST(NoAllocation, ControllerUpdateOfRobotDynamics) {
  DMBD_SKIP_UNDER_ASAN();
  RobotDynamics d(draco());
  const int nq = d.nq(), nv = d.nv();
  Eigen::VectorXd q = d.neutral_configuration(), v = Eigen::VectorXd::Constant(nv, 0.1), bg(nv);
  Eigen::MatrixXd A(nv, nv), Jl(6, nv), Jr(6, nv), Jc(3, nv);
  const int lf = d.link_index("l_foot"), rf = d.link_index("r_foot");
  ASSERT_GE(lf, 0);
  ASSERT_GE(rf, 0);
  auto update = [&](double s) {
    q[nq - 1] = s;
    d.set_state(q, v);
    d.mass_matrix(A);
    d.coriolis_and_gravity(bg);
    d.frame_jacobian(lf, Eigen::Vector3d::Zero(), Jl);
    d.frame_jacobian(rf, Eigen::Vector3d::Zero(), Jr);
    const auto al = d.frame_jacobian_dot_v(lf, Eigen::Vector3d::Zero());
    const auto ar = d.frame_jacobian_dot_v(rf, Eigen::Vector3d::Zero());
    d.com_jacobian(Jc);
    return al.sum() + ar.sum() + d.com_jacobian_dot_v().sum() + d.com_position().sum();
  };
  double sink = update(0.0);
  const long before = g_allocations.load();
  for (int k = 0; k < 100; ++k) sink += update(0.001 * k);
  EXPECT_EQ(g_allocations.load() - before, 0) << "allocations in 100 controller updates";
  EXPECT_TRUE(std::isfinite(sink));
}

}  // namespace
}  // namespace dmbd::model
