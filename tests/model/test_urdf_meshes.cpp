// Meshes of a URDF: package:// / file:// / relative resolution, STL (binary and
// ASCII), OBJ and COLLADA through assimp, URDF scale, COLLADA units, missing and
// unreadable files (warnings, or errors with `strict`).
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <unistd.h>

#include <filesystem>

#include "test_urdf_support.hpp"

namespace dmbd::model {
namespace {

namespace fs = std::filesystem;
using test::line_of;
using test::slurp;
using test::urdf_data;

struct Bounds {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = Eigen::Vector3d::Constant(-INFINITY);
};
Bounds bounds(const TriangleMesh& m) {
  Bounds b;
  for (const auto& v : m.vertices) {
    b.lo = b.lo.cwiseMin(v.cast<double>());
    b.hi = b.hi.cwiseMax(v.cast<double>());
  }
  return b;
}
// Divergence theorem: positive for a closed mesh whose triangles face outwards.
double signed_volume(const TriangleMesh& m) {
  double v = 0;
  for (const auto& t : m.triangles) {
    const Eigen::Vector3d a = m.vertices[t[0]].cast<double>(), b = m.vertices[t[1]].cast<double>(),
                          c = m.vertices[t[2]].cast<double>();
    v += a.dot(b.cross(c)) / 6;
  }
  return v;
}
void expect_bounds(const TriangleMesh& m, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const Bounds b = bounds(m);
  // Vertices are floats: 1e-7 m on numbers below 1 m.
  EXPECT_LT((b.lo - lo).cwiseAbs().maxCoeff(), 1e-7) << b.lo.transpose() << " vs " << lo.transpose();
  EXPECT_LT((b.hi - hi).cwiseAbs().maxCoeff(), 1e-7) << b.hi.transpose() << " vs " << hi.transpose();
}
bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  return fs::equivalent(a, b, ec);
}

const Link& link_named(const RobotDescription& r, const std::string& name) {
  const int i = r.link_index(name);
  EXPECT_GE(i, 0) << name;
  return r.links.at(static_cast<std::size_t>(std::max(i, 0)));
}

class TempDir {
 public:
  TempDir() {
    path_ = fs::temp_directory_path() /
            ("dmbd_urdf_" + std::string(testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
             std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  std::string str() const { return path_.string(); }
  fs::path path() const { return path_; }

 private:
  fs::path path_;
};

const std::string kPackageCube = R"(<robot name="pkg">
  <link name="base">
    <visual><geometry><mesh filename="package://arm_description/meshes/cube_binary.stl"/></geometry></visual>
  </link>
</robot>)";

TEST(UrdfMeshes, PackageUriFoundFromTheUrdfsParentFolders) {
  // urdf/arm.urdf names package://arm_description/meshes/...: found at
  // ws/arm_description/meshes/... (a parent of the URDF's folder is the package).
  const RobotDescription r = load_urdf(urdf_data("ws/arm_description/urdf/arm.urdf"));
  EXPECT_EQ(r.meshes_loaded, 2u);
  EXPECT_TRUE(r.meshes_missing.empty());
  const Geometry& g = link_named(r, "base").visuals[0].geometry;
  EXPECT_EQ(g.kind, Geometry::Kind::Mesh);
  EXPECT_EQ(g.mesh_uri, "package://arm_description/meshes/cube_binary.stl");
  EXPECT_EQ(g.mesh_scale, Eigen::Vector3d(0.5, 0.5, 0.5));
  ASSERT_TRUE(g.mesh);
  EXPECT_TRUE(same_file(g.mesh->path, urdf_data("ws/arm_description/meshes/cube_binary.stl"))) << g.mesh->path;
}

TEST(UrdfMeshes, BinaryStlUnitCubeScaledByHalf) {
  const RobotDescription r = load_urdf(urdf_data("ws/arm_description/urdf/arm.urdf"));
  const auto& m = link_named(r, "base").visuals[0].geometry.mesh;
  ASSERT_TRUE(m);
  EXPECT_EQ(m->triangles.size(), 12u);
  EXPECT_EQ(m->vertices.size(), 24u);  // 4 per face: corners shared within a face (same normal), not across
  expect_bounds(*m, Eigen::Vector3d::Constant(-0.25), Eigen::Vector3d::Constant(0.25));
  EXPECT_NEAR(signed_volume(*m), 0.125, 1e-7);  // (1 m * 0.5)^3, outward faces
  ASSERT_EQ(m->normals.size(), m->vertices.size());
  for (const auto& n : m->normals) {
    EXPECT_NEAR(n.norm(), 1.0f, 1e-6f);
    EXPECT_NEAR(n.cwiseAbs().maxCoeff(), 1.0f, 1e-6f);  // flat faces of a cube: axis-aligned
  }
}

TEST(UrdfMeshes, AsciiStl) {
  const RobotDescription r = load_urdf(urdf_data("ws/arm_description/urdf/arm.urdf"));
  const auto& m = link_named(r, "upper_arm").visuals[0].geometry.mesh;
  ASSERT_TRUE(m);
  EXPECT_EQ(m->triangles.size(), 12u);
  expect_bounds(*m, Eigen::Vector3d(-0.03, -0.03, 0), Eigen::Vector3d(0.03, 0.03, 0.3));
  EXPECT_NEAR(signed_volume(*m), 0.06 * 0.06 * 0.3, 1e-9);
}

TEST(UrdfMeshes, ColladaUnitIsAppliedAndZUpIsKept) {
  // tetra_cm.dae: <unit meter="0.01">, <up_axis>Z_UP, corners (0 0 0) (10 0 0) (0 20 0)
  // (0 0 30) cm, node translated 5 cm up. assimp's default would turn a Z_UP file
  // -90 deg about x (to its Y-up convention); the loader keeps URDF (Z-up) coordinates.
  const RobotDescription r = load_urdf(urdf_data("mixed/mixed.urdf"));
  const auto& m = link_named(r, "base_link").visuals[0].geometry.mesh;
  ASSERT_TRUE(m);
  EXPECT_EQ(m->vertices.size(), 4u);
  EXPECT_EQ(m->triangles.size(), 4u);
  expect_bounds(*m, Eigen::Vector3d(0, 0, 0.05), Eigen::Vector3d(0.1, 0.2, 0.35));
  EXPECT_NEAR(signed_volume(*m), 0.1 * 0.2 * 0.3 / 6, 1e-9);
}

TEST(UrdfMeshes, ColladaUpAxisIsIgnored) {
  // plate_yup.dae declares Y_UP; its square lies at z = 0.01 m in the file. Taken as
  // link-frame coordinates (scale 2): z = 0.02, x and y in +-0.2. Honouring Y_UP
  // (turning the file +90 deg about x into Z-up) would have put it in the x-z plane.
  const RobotDescription r = load_urdf(urdf_data("mixed/mixed.urdf"));
  const auto& m = link_named(r, "base_link").visuals[1].geometry.mesh;
  ASSERT_TRUE(m);
  EXPECT_EQ(m->triangles.size(), 2u);  // a 4-vertex polygon, triangulated
  expect_bounds(*m, Eigen::Vector3d(-0.2, -0.2, 0.02), Eigen::Vector3d(0.2, 0.2, 0.02));
}

TEST(UrdfMeshes, ObjQuadsTriangulatedAndMirrorScaleKeepsFacesOutward) {
  const RobotDescription r = load_urdf(urdf_data("mixed/mixed.urdf"));
  const Link& puck = link_named(r, "puck");
  const auto& plain = puck.collisions[0].geometry.mesh;  // meshes/wedge.obj
  const auto& mirrored = puck.visuals[0].geometry.mesh;  // file://meshes/wedge.obj, scale 1 1 -1
  ASSERT_TRUE(plain);
  ASSERT_TRUE(mirrored);
  EXPECT_TRUE(same_file(plain->path, mirrored->path));
  EXPECT_EQ(plain->vertices.size(), 6u);
  EXPECT_EQ(plain->triangles.size(), 8u);  // 2 triangles + 3 quads
  expect_bounds(*plain, Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.2, 0.3, 0.1));
  expect_bounds(*mirrored, Eigen::Vector3d(0, 0, -0.1), Eigen::Vector3d(0.2, 0.3, 0));
  const double volume = 0.5 * 0.2 * 0.1 * 0.3;
  EXPECT_NEAR(signed_volume(*plain), volume, 1e-9);
  EXPECT_NEAR(signed_volume(*mirrored), volume, 1e-9);  // re-wound: still outward
  // Distinct URIs read: tetra, plate, file://meshes/wedge.obj, meshes/wedge.obj.
  EXPECT_EQ(r.meshes_loaded, 4u);
}

TEST(UrdfMeshes, SameFileAndScaleIsReadOnce) {
  const std::string xml = R"(<robot name="twice">
  <link name="base">
    <visual><geometry><mesh filename="meshes/wedge.obj"/></geometry></visual>
    <collision><geometry><mesh filename="meshes/wedge.obj"/></geometry></collision>
    <collision><geometry><mesh filename="meshes/wedge.obj" scale="2 2 2"/></geometry></collision>
  </link>
</robot>)";
  const RobotDescription r = parse_urdf(xml, urdf_data("mixed"), "twice.urdf");
  const Link& l = r.links[0];
  ASSERT_TRUE(l.visuals[0].geometry.mesh);
  EXPECT_EQ(l.visuals[0].geometry.mesh, l.collisions[0].geometry.mesh);
  EXPECT_NE(l.collisions[0].geometry.mesh, l.collisions[1].geometry.mesh);
  expect_bounds(*l.collisions[1].geometry.mesh, Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.4, 0.6, 0.2));
  EXPECT_EQ(r.meshes_loaded, 1u);  // one URI
}

TEST(UrdfMeshes, PackagePathsOption) {
  const TempDir elsewhere;  // no package in it or its parents
  {
    const RobotDescription r = parse_urdf(kPackageCube, elsewhere.str(), "pkg.urdf");
    EXPECT_FALSE(r.links[0].visuals[0].geometry.mesh);
    EXPECT_EQ(r.meshes_missing, std::vector<std::string>{"package://arm_description/meshes/cube_binary.stl"});
  }
  UrdfOptions o;
  o.package_paths = {urdf_data("ws")};  // <dir>/NAME/PATH
  {
    const RobotDescription r = parse_urdf(kPackageCube, elsewhere.str(), "pkg.urdf", o);
    ASSERT_TRUE(r.links[0].visuals[0].geometry.mesh);
    EXPECT_TRUE(same_file(r.links[0].visuals[0].geometry.mesh->path, urdf_data("ws/arm_description/meshes/cube_binary.stl")));
    EXPECT_TRUE(r.meshes_missing.empty());
  }
  o.package_paths = {elsewhere.str(), urdf_data("ws/arm_description")};  // <dir>/PATH, second folder
  {
    const RobotDescription r = parse_urdf(kPackageCube, elsewhere.str(), "pkg.urdf", o);
    ASSERT_TRUE(r.links[0].visuals[0].geometry.mesh);
    expect_bounds(*r.links[0].visuals[0].geometry.mesh, Eigen::Vector3d::Constant(-0.5), Eigen::Vector3d::Constant(0.5));
  }
}

TEST(UrdfMeshes, PackagePathsComeBeforeTheUrdfsFolders) {
  // A package folder given as an option holds another "cube_binary.stl" (the upper-arm
  // box): it wins over the one next to the URDF.
  const TempDir tmp;
  fs::create_directories(tmp.path() / "arm_description" / "meshes");
  fs::copy_file(urdf_data("ws/arm_description/meshes/upper_arm.stl"),
                tmp.path() / "arm_description" / "meshes" / "cube_binary.stl");
  UrdfOptions o;
  o.package_paths = {tmp.str()};
  const RobotDescription r = load_urdf(urdf_data("ws/arm_description/urdf/arm.urdf"), o);
  const auto& m = link_named(r, "base").visuals[0].geometry.mesh;
  ASSERT_TRUE(m);
  EXPECT_TRUE(same_file(m->path, (tmp.path() / "arm_description" / "meshes" / "cube_binary.stl").string()));
  expect_bounds(*m, Eigen::Vector3d(-0.015, -0.015, 0), Eigen::Vector3d(0.015, 0.015, 0.15));  // scale 0.5
}

TEST(UrdfMeshes, FileUrisAndAbsolutePaths) {
  const std::string abs = fs::absolute(urdf_data("ws/arm_description/meshes/cube_binary.stl")).lexically_normal().string();
  const std::string xml = "<robot name=\"f\"><link name=\"a\">"
                          "<visual><geometry><mesh filename=\"file://" + abs + "\"/></geometry></visual>"
                          "<visual><geometry><mesh filename=\"" + abs + "\" scale=\"2 2 2\"/></geometry></visual>"
                          "</link></robot>";
  const TempDir elsewhere;
  const RobotDescription r = parse_urdf(xml, elsewhere.str(), "f.urdf");
  ASSERT_TRUE(r.links[0].visuals[0].geometry.mesh);
  ASSERT_TRUE(r.links[0].visuals[1].geometry.mesh);
  expect_bounds(*r.links[0].visuals[1].geometry.mesh, Eigen::Vector3d::Constant(-1), Eigen::Vector3d::Constant(1));
  EXPECT_EQ(r.meshes_loaded, 2u);
}

TEST(UrdfMeshes, MissingAndUnreadableMeshesWarnAndStillLoad) {
  const std::string path = urdf_data("partial/missing_meshes.urdf");
  const std::string text = slurp(path);
  const RobotDescription r = load_urdf(path);
  // ghost.stl is named twice (visual and collision): listed and warned once.
  EXPECT_EQ(r.meshes_missing,
            (std::vector<std::string>{"package://nowhere_description/meshes/ghost.stl", "garbage.stl"}));
  EXPECT_EQ(r.meshes_loaded, 1u);  // ../mixed/meshes/wedge.obj
  ASSERT_EQ(r.warnings.size(), 3u);  // the two meshes, then the massless moving link 'arm'
  EXPECT_NE(r.warnings[2].find("link 'arm': moved by continuous joint 'arm'"), std::string::npos) << r.warnings[2];
  const std::string ghost_at = path + ":" + std::to_string(line_of(text, "ghost.stl")) + ": link 'base': ";
  EXPECT_EQ(r.warnings[0].rfind(ghost_at, 0), 0u) << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("'package://nowhere_description/meshes/ghost.stl' not found"), std::string::npos) << r.warnings[0];
  const std::string garbage_at = path + ":" + std::to_string(line_of(text, "garbage.stl")) + ": link 'arm': ";
  EXPECT_EQ(r.warnings[1].rfind(garbage_at, 0), 0u) << r.warnings[1];
  EXPECT_NE(r.warnings[1].find("'garbage.stl'"), std::string::npos);
  EXPECT_NE(r.warnings[1].find("cannot be read"), std::string::npos);
  const Link& base = link_named(r, "base");
  EXPECT_FALSE(base.visuals[0].geometry.mesh);
  EXPECT_EQ(base.visuals[0].geometry.mesh_uri, "package://nowhere_description/meshes/ghost.stl");
  EXPECT_FALSE(base.collisions[0].geometry.mesh);
  EXPECT_EQ(base.visuals[1].geometry.kind, Geometry::Kind::Box);
  const Link& arm = link_named(r, "arm");
  EXPECT_FALSE(arm.visuals[0].geometry.mesh);
  EXPECT_TRUE(arm.visuals[1].geometry.mesh);
  // Height skips the missing meshes: box [-0.05, 0.05], wedge at z = 0.2: [0.2, 0.3].
  const ModelSummary s = summarize(r);
  EXPECT_NEAR(s.height_m, 0.35, 1e-7);
  EXPECT_EQ(s.meshes_missing, r.meshes_missing);
  EXPECT_EQ(s.meshes_loaded, 1u);
}

TEST(UrdfMeshes, StrictMakesAMissingMeshAnError) {
  const std::string path = urdf_data("partial/missing_meshes.urdf");
  UrdfOptions o;
  o.strict = true;
  test::expect_model_error([&] { load_urdf(path, o); },
                           {path + ":" + std::to_string(line_of(slurp(path), "ghost.stl")) + ": ", "link 'base'",
                            "package://nowhere_description/meshes/ghost.stl", "not found", "strict"});
}

TEST(UrdfMeshes, StrictMakesAnUnreadableMeshAnError) {
  const std::string xml = "<robot name=\"g\">\n<link name=\"a\">\n<visual><geometry>\n"
                          "<mesh filename=\"garbage.stl\"/>\n</geometry></visual>\n</link>\n</robot>\n";
  UrdfOptions o;
  o.strict = true;
  test::expect_model_error([&] { parse_urdf(xml, urdf_data("partial"), "g.urdf", o); },
                           {"g.urdf:4: link 'a': mesh 'garbage.stl'", "cannot be read"});
}

TEST(UrdfMeshes, UnsupportedSchemeIsMissing) {
  const std::string xml = R"(<robot name="h"><link name="a"><visual><geometry><mesh filename="http://example.com/a.stl"/></geometry></visual></link></robot>)";
  const RobotDescription r = parse_urdf(xml, ".", "h.urdf");
  EXPECT_EQ(r.meshes_missing, std::vector<std::string>{"http://example.com/a.stl"});
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("unsupported URI scheme 'http://'"), std::string::npos) << r.warnings[0];
}

TEST(UrdfMeshes, LoadMeshesOffRecordsUrisOnly) {
  UrdfOptions o;
  o.load_meshes = false;
  const RobotDescription r = load_urdf(urdf_data("partial/missing_meshes.urdf"), o);
  EXPECT_EQ(r.meshes_loaded, 0u);
  EXPECT_TRUE(r.meshes_missing.empty());
  ASSERT_EQ(r.warnings.size(), 1u);  // no mesh warning; the massless moving link 'arm' only
  EXPECT_NE(r.warnings[0].find("link 'arm': moved by continuous joint 'arm'"), std::string::npos) << r.warnings[0];
  EXPECT_FALSE(link_named(r, "arm").visuals[1].geometry.mesh);
  EXPECT_EQ(link_named(r, "arm").visuals[1].geometry.mesh_uri, "../mixed/meshes/wedge.obj");
}

}  // namespace
}  // namespace dmbd::model
