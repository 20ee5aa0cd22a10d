// Where the frames draw the logged contact forces (report/src/contact_sites.hpp, an
// internal header of report/, included here to test it against the plant): the sites
// are the plant's colliding shapes in its order (model::Plant::contacts(), also the
// log's contact.K), and a shape at rest on the ground gets, from its pose alone, the
// plant's centre of pressure, which in statics lies under the centre of mass.
#include "../../report/src/contact_sites.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "contact_fixtures.hpp"
#include "dmbd/model/plant.hpp"

namespace dmbd::report::detail {
namespace {

namespace t = dmbd::model::testing;
using model::Geometry;

// base (box; a cylinder of zero radius and a missing mesh, which the plant skips) ->
// revolute -> arm (sphere, cylinder, a box mesh) -> fixed -> tip (no collision) ->
// fixed -> pad (sphere).
std::string mixed_urdf() {
  auto col = [](const std::string& geometry, const std::string& xyz) {
    return "<collision><origin xyz=\"" + xyz + "\"/><geometry>" + geometry + "</geometry></collision>";
  };
  return "<?xml version=\"1.0\"?>\n<robot name=\"mixed\">\n"
         "<link name=\"base\">" + t::inertial(5, {0.1, 0.1, 0.1}) + col(t::box_xml({0.3, 0.2, 0.05}), "0 0 0") +
         col(t::cylinder_xml(0, 0.1), "0 0 0.1") + col("<mesh filename=\"missing.obj\"/>", "0 0 0.2") + "</link>\n"
         "<joint name=\"j\" type=\"revolute\"><parent link=\"base\"/><child link=\"arm\"/><origin xyz=\"0 0 0.3\"/>"
         "<axis xyz=\"0 1 0\"/><limit lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"5\"/></joint>\n"
         "<link name=\"arm\">" + t::inertial(1, {0.01, 0.01, 0.01}) + col("<sphere radius=\"0.04\"/>", "0 0 0.1") +
         col(t::cylinder_xml(0.03, 0.2), "0 0 0.2") + col("<mesh filename=\"cube.obj\"/>", "0 0 0.3") + "</link>\n"
         "<joint name=\"f1\" type=\"fixed\"><parent link=\"arm\"/><child link=\"tip\"/><origin xyz=\"0 0 0.4\"/></joint>\n"
         "<link name=\"tip\">" + t::inertial(0.1, {1e-4, 1e-4, 1e-4}) + "</link>\n"
         "<joint name=\"f2\" type=\"fixed\"><parent link=\"tip\"/><child link=\"pad\"/><origin xyz=\"0 0 0.1\"/></joint>\n"
         "<link name=\"pad\">" + t::inertial(0.1, {1e-4, 1e-4, 1e-4}) + col("<sphere radius=\"0.02\"/>", "0 0 0") + "</link>\n"
         "</robot>\n";
}

TEST(ContactSites, NumberedAsThePlantNumbersItsContacts) {
  const t::TempDir tmp("contact_sites");
  t::write_box_obj(tmp.path + "/cube.obj", {0.05, 0.05, 0.05});
  const model::RobotDescription robot = model::parse_urdf(mixed_urdf(), tmp.path, tmp.path + "/mixed.urdf");
  const std::vector<ContactSite> sites = contact_sites(robot);
  const model::Plant plant(robot);
  const std::vector<model::ContactReading> c = plant.contacts();
  ASSERT_EQ(sites.size(), 5u);  // box; sphere, cylinder, mesh; sphere
  ASSERT_EQ(c.size(), sites.size());
  for (std::size_t k = 0; k < c.size(); ++k) {
    EXPECT_EQ(sites[k].link, c[k].link) << k;
    EXPECT_EQ(sites[k].shape, c[k].shape) << k;
    EXPECT_EQ(sites[k].kind, c[k].kind) << k;
  }
  EXPECT_EQ(sites[1].kind, Geometry::Kind::Sphere);
  EXPECT_EQ(sites[3].kind, Geometry::Kind::Mesh);
  EXPECT_EQ(sites[3].points_L.size(), 8u);  // the cube's hull: its corners
  EXPECT_EQ(sites[4].link, robot.link_index("pad"));
}

// One floating body of 20 kg whose centre of mass is `com` (body frame) off the centre of
// its one collision shape, posed by X_WB and left to settle for 10 s (fixed step; a
// cylinder on its face rocks for seconds, 7 mm off after 1 s, 2 mm after 3 s): the
// site's point from the body's pose against the plant's reading (its closed-form centre of
// pressure) and against the centre of mass's ground projection (statics).
struct Rest {
  Eigen::Vector3d site, plant, com_W;
};
Rest rest(const std::string& geometry, const std::string& origin, const Eigen::Isometry3d& X_WB, const Eigen::Vector3d& com,
          const std::string& dir = ".") {
  const std::string xml = "<?xml version=\"1.0\"?>\n<robot name=\"body\">\n<link name=\"body\">" +
                          t::inertial(20, {0.2, 0.2, 0.2}, com) + "<collision><origin " + origin + "/><geometry>" + geometry +
                          "</geometry></collision></link>\n</robot>\n";
  const model::RobotDescription robot = model::parse_urdf(xml, dir, dir + "/body.urdf");
  model::PlantOptions o;
  o.integration = model::Integration::Fixed;
  o.X_WB = X_WB;
  model::Plant p(robot, o);
  for (int k = 1; k <= 1000; ++k) p.advance_to(0.01 * k);
  const std::vector<ContactSite> sites = contact_sites(robot);
  const Eigen::Isometry3d X = p.link_poses()[0];
  return {contact_point(sites.at(0), X), p.contacts().at(0).p_W, X * com};
}

Eigen::Isometry3d pose(double yaw, const Eigen::Vector3d& axis = Eigen::Vector3d::UnitX(), double tilt = 0) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() << 0.3, -0.2, 0.5;
  X.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(tilt, axis)).toRotationMatrix();
  return X;
}

void expect_near_xy(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double tol, const char* what) {
  EXPECT_NEAR(a.x(), b.x(), tol) << what;
  EXPECT_NEAR(a.y(), b.y(), tol) << what;
}

// A box on its face and a box mesh (its 8 hull corners), at rest: the depth-weighted
// corners are the plant's centre of pressure (within 1e-9 m, measured 7e-16 m: at rest the
// law's damping term is nil) and lie under the centre of mass, 4 cm and 3 cm off the
// face's centre (within 1e-6 m, measured 2e-8 m).
TEST(ContactSites, BoxAndMeshAtRestGetThePlantsCentreOfPressure) {
  const t::TempDir tmp("contact_sites_rest");
  t::write_box_obj(tmp.path + "/box.obj", {0.3, 0.2, 0.05});
  const Eigen::Vector3d com(0.04, 0.03, 0.01);
  for (const char* geometry : {"<box size=\"0.3 0.2 0.05\"/>", "<mesh filename=\"box.obj\"/>"}) {
    const Rest r = rest(geometry, "", pose(0.4), com, tmp.path);
    std::printf("%s: site - plant %.3g m, site - com %.3g m (xy)\n", geometry, (r.site - r.plant).norm(),
                (r.site - r.com_W).head<2>().norm());
    EXPECT_LT((r.site - r.plant).norm(), 1e-9) << geometry;
    expect_near_xy(r.site, r.com_W, 1e-6, geometry);
    EXPECT_LT(std::abs(r.site.z()), 1e-3) << geometry;  // at the sunk face: m g / (4 k) = 0.5 mm deep
  }
}

// A cylinder (R 5 cm, L 12 cm) on its side, its centre of mass 3 cm along its axis off
// centre, so its rims carry unequal loads, and standing on an end face, its centre of mass
// 2 cm off the axis: the rims sampled every 5 deg give the plant's closed-form ring centre
// of pressure, and the point under the centre of mass, to within 1 mm (measured: on its
// side 0.26 mm, both; on its face 1e-16 m and 6e-6 m, the whole rim touching).
TEST(ContactSites, CylinderAtRestGetsThePlantsCentreOfPressureToTheSampling) {
  const std::string cyl = t::cylinder_xml(0.05, 0.12);
  struct Case {
    const char* what;
    Eigen::Isometry3d X_WB;
    Eigen::Vector3d com;
  };
  for (const Case& c : {Case{"on its side", pose(0.4, Eigen::Vector3d::UnitX(), M_PI / 2), {0, 0, 0.03}},
                        Case{"on its face", pose(0.4), {0.02, 0, 0}}}) {
    const Rest r = rest(cyl, "", c.X_WB, c.com);
    std::printf("cylinder %s: site - plant %.3g m, site - com %.3g m (xy)\n", c.what, (r.site - r.plant).norm(),
                (r.site - r.com_W).head<2>().norm());
    EXPECT_LT((r.site - r.plant).norm(), 1e-3) << c.what;
    expect_near_xy(r.site, r.com_W, 1e-3, c.what);
  }
}

}  // namespace
}  // namespace dmbd::report::detail
