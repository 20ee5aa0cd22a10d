// Robots on feet that are not spheres: a hopper (torso, thigh, shank and a box, a
// cylinder or a mesh foot) standing under a joint PD, and Simbody's Atlas (box feet)
// dropped onto the ground; docs/model.md, "Contact".
#include "dmbd/model/plant.hpp"

#include "contact_fixtures.hpp"

#include <gtest/gtest.h>

#include <sys/types.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace dmbd::model {
namespace {

namespace fs = std::filesystem;

// Crouched (hip 0.2, knee -0.4, ankle 0.2 rad: torso and foot level), placed on the
// ground, it stands 2 s under a 1 kHz joint PD holding that posture (hip and knee 400
// N m/rad and 8 N m s/rad, ankle 200 and 1: stiffer than the body's toppling
// m g h ~ 40 N m/rad about the ankle) and a 10 N push on the torso from 0.5 to 0.6 s. The
// PD is soft and little damped (a sampled derivative gain is bounded by the light links'
// inertia): the hopper still sways at the end; the test is about its foot holding it.
void stand(const RobotDescription& r, const char* foot) {
  PlantOptions o;
  o.integration = Integration::Fixed;
  Plant p(r, o);
  ASSERT_EQ(p.num_joints(), 3);
  const Eigen::VectorXd q0 = Eigen::Vector3d(0.2, -0.4, 0.2);
  p.set_joint_positions(q0);
  p.place_on_ground();
  const Eigen::VectorXd kp = Eigen::Vector3d(400, 400, 200), kd = Eigen::Vector3d(8, 8, 1);
  const double z0 = p.base_pose().translation().z();
  double dz = 0, tilt = 0, dx = 0;
  for (int k = 1; k <= 2000; ++k) {
    if (k == 500) p.set_external_force(0, Eigen::Vector3d::Zero(), Eigen::Vector3d(10, 0, 0));
    if (k == 600) p.clear_external_forces();
    p.set_joint_torques(kp.cwiseProduct(q0 - p.joint_positions()) - kd.cwiseProduct(p.joint_velocities()));
    p.advance_to(k * 1e-3);
    const Eigen::Isometry3d X = p.base_pose();
    dz = std::max(dz, std::abs(X.translation().z() - z0));
    dx = std::max(dx, std::abs(X.translation().x()));
    tilt = std::max(tilt, std::acos(std::clamp(X.linear()(2, 2), -1.0, 1.0)));
  }
  double fz = 0;
  const std::vector<ContactReading> contacts = p.contacts();
  for (const ContactReading& c : contacts) fz += c.force_W.z();
  const ContactReading& f = contacts.back();
  const double tilt_end = std::acos(std::clamp(p.base_pose().linear()(2, 2), -1.0, 1.0)), speed = p.base_velocity().norm();
  std::printf("hopper on a %s foot, 2 s with a push: torso at %.4f m, height change %.2e m, sway %.2e m, tilt %.2e rad "
              "(at the end %.2e rad, torso speed %.2e); foot carries %.2f N of %.2f N\n", foot, z0, dz, dx, tilt, tilt_end, speed,
              f.force_W.z(), p.total_mass_kg() * 9.81);
  EXPECT_GT(dx, 1e-3);           // the push moved it
  EXPECT_LT(dz, 0.01);           // steady within 1 cm
  EXPECT_LT(tilt, 0.15);         // the PD lets the torso lean under the push (below 0.1 rad)
  EXPECT_EQ(p.contacts().size(), 4u);  // torso box, thigh and shank cylinders, foot
  EXPECT_EQ(f.link, 3);
  EXPECT_EQ(f.kind, r.links[3].collisions[0].geometry.kind);
  EXPECT_NEAR(f.force_W.z(), fz, 1e-12);  // only the foot touches
  EXPECT_NEAR(fz, p.total_mass_kg() * 9.81, 0.02 * p.total_mass_kg() * 9.81);
}

TEST(PlantRobots, HopperStandsOnABoxFoot) {
  stand(testing::hopper(testing::box_xml({0.24, 0.12, 0.06})), "box");
}

TEST(PlantRobots, HopperStandsOnACylinderFoot) {
  stand(testing::hopper(testing::cylinder_xml(0.08, 0.06)), "cylinder");
}

TEST(PlantRobots, HopperStandsOnAMeshFoot) {
  const testing::TempDir tmp("hopper_mesh");
  const std::string& dir = tmp.path;
  testing::write_box_obj(dir + "/foot.obj", {0.24, 0.12, 0.06});
  stand(testing::hopper("<mesh filename=\"foot.obj\"/>", dir), "mesh");
}

// Simbody's Atlas example (Debian's simbody docs): every joint locked at 0, dropped from
// 5 cm above where it rests; the feet's boxes stop it. Its collision mesh (the backpack)
// is missing: skipped, with the loader's warning saying so.
const char* const kAtlasGz =
    "/usr/share/doc/simbody/examples/src/TaskSpaceControl-Atlas/models/atlas_v4_free_pelvis.urdf.gz";

TEST(PlantRobots, AtlasDroppedFiveCentimetresLandsOnItsFeet) {
  if (!fs::exists(kAtlasGz)) GTEST_SKIP() << kAtlasGz << " is absent (Debian package simbody-doc / libsimbody-dev docs)";
  const fs::path dir = fs::temp_directory_path() / ("dmbd_atlas_drop_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path urdf = dir / "atlas_v4_free_pelvis.urdf";
  ASSERT_EQ(std::system(("gzip -dc '" + std::string(kAtlasGz) + "' > '" + urdf.string() + "'").c_str()), 0);
  const RobotDescription r = load_urdf(urdf.string());
  fs::remove_all(dir);
  const auto skipped = std::count_if(r.warnings.begin(), r.warnings.end(), [](const std::string& w) {
    return w.find("utorso_pack.stl") != std::string::npos && w.find("collision shape is skipped") != std::string::npos;
  });
  EXPECT_EQ(skipped, 1);
  PlantOptions o;
  o.integration = Integration::Fixed;
  Plant p(r, o);
  for (int j = 0; j < p.num_joints(); ++j) p.lock_joint(j, 0.0);
  const double z_rest = p.base_pose().translation().z();
  Eigen::Isometry3d X = p.base_pose();
  X.translation().z() += 0.05;
  p.set_base_pose(X);
  double lowest = 1e9;
  for (int k = 1; k <= 100; ++k) {
    p.advance_to(k * 0.01);
    lowest = std::min(lowest, p.base_pose().translation().z());
  }
  const double z_end = p.base_pose().translation().z();
  double feet = 0, total = 0;
  for (const ContactReading& c : p.contacts()) {
    total += c.force_W.z();
    if (r.links[static_cast<std::size_t>(c.link)].name.find("foot") != std::string::npos) feet += c.force_W.z();
  }
  std::printf("Atlas (%.1f kg, %zu contact shapes) dropped 5 cm: pelvis at rest %.4f m, lowest %.4f m, after 1 s %.4f m; "
              "feet carry %.1f N of %.1f N\n", p.total_mass_kg(), p.contacts().size(), z_rest, lowest, z_end, feet, total);
  EXPECT_GT(lowest, z_rest - 0.01);          // the feet stop it within 1 cm of where it rests
  EXPECT_NEAR(z_end, z_rest, 0.005);         // and it stands there after 1 s
  EXPECT_NEAR(feet, p.total_mass_kg() * 9.81, 0.02 * p.total_mass_kg() * 9.81);
  EXPECT_NEAR(feet, total, 1e-9);            // on its feet alone
}

}  // namespace
}  // namespace dmbd::model
