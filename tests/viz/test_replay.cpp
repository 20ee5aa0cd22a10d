// The 3-D replay's data files and page section (viz/replay.hpp, viz/report.hpp): base64
// against RFC 4648's vectors and a decoder of the test's own, a scene's meshes and a
// track's poses, forces and overlays read back as written, the mistakes refused, the
// page's replay section (its scripts, the setup the player reads, paths checked) and
// three.js copied with its licence.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../../viz/src/base64.hpp"
#include "dmbd/base/error.hpp"
#include "dmbd/viz/primitives.hpp"
#include "dmbd/viz/replay.hpp"
#include "dmbd/viz/report.hpp"
#include "replay_script.hpp"
#include "viz_test_support.hpp"

namespace dmbd::viz {
namespace {

namespace fs = std::filesystem;
namespace rs = dmbd::test::replay;

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// RFC 4648 section 10, and every byte value through the test's own decoder.
TEST(ReplayData, Base64MatchesRfc4648AndDecodesBack) {
  const std::vector<std::pair<std::string, std::string>> rfc = {
      {"", ""}, {"f", "Zg=="}, {"fo", "Zm8="}, {"foo", "Zm9v"}, {"foob", "Zm9vYg=="}, {"fooba", "Zm9vYmE="}, {"foobar", "Zm9vYmFy"}};
  for (const auto& [in, out] : rfc)
    EXPECT_EQ(detail::base64(reinterpret_cast<const unsigned char*>(in.data()), in.size()), out) << in;
  std::vector<unsigned char> all;
  for (int i = 0; i < 256; ++i) all.push_back(static_cast<unsigned char>(255 - i));
  for (std::size_t n : {253u, 254u, 255u, 256u}) {
    const std::vector<unsigned char> part(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(n));
    EXPECT_EQ(rs::decode_base64(detail::base64(part.data(), part.size())), part) << n << " bytes";
  }
  // float32 little-endian: 1.0f is 00 00 80 3f.
  EXPECT_EQ(detail::base64_float32({1.0f}), "AACAPw==");
  const std::vector<float> values = {0.0f, -2.5f, 1e-30f, 3.4e38f, std::numeric_limits<float>::quiet_NaN()};
  const std::vector<float> back = rs::floats(detail::base64_float32(values));
  ASSERT_EQ(back.size(), values.size());
  for (std::size_t i = 0; i + 1 < values.size(); ++i) EXPECT_EQ(back[i], values[i]);
  EXPECT_TRUE(std::isnan(back.back()));
  EXPECT_EQ(rs::uints(detail::base64_uint({1, 65535, 258}, 2), 2), (std::vector<std::uint32_t>{1, 65535, 258}));
  EXPECT_EQ(rs::uints(detail::base64_uint({70000, 0}, 4), 4), (std::vector<std::uint32_t>{70000, 0}));
}

// Two bodies: a box with its normals, a hand-made triangle without; read back exactly.
TEST(ReplayData, SceneScriptHoldsTheMeshesAsGiven) {
  Scene scene;
  SceneMesh box = box_mesh({0.1, 0.2, 0.3});
  box.rgba = {0.25f, 0.5f, 0.75f, 1.0f};
  SceneMesh tri;
  tri.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0.5f}};
  tri.triangles = {{0, 1, 2}};
  scene.bodies = {{"base", {box}}, {"arm", {tri}}};
  const rs::Script s = rs::parse(replay_scene_script(scene, "replay/scene_0.js"));
  EXPECT_EQ(s.table, "scenes");
  EXPECT_EQ(s.key, "replay/scene_0.js");
  const auto& bodies = s.value.at("bodies");
  ASSERT_EQ(bodies.size(), 2u);
  EXPECT_EQ(bodies[1].at("name"), "arm");
  const auto& m0 = bodies[0].at("meshes").at(0);
  EXPECT_EQ(m0.at("index_bytes"), 2);
  const std::vector<float> p = rs::floats(m0.at("positions")), n = rs::floats(m0.at("normals"));
  ASSERT_EQ(p.size(), 3 * box.vertices.size());
  ASSERT_EQ(n.size(), 3 * box.normals.size());
  for (std::size_t i = 0; i < box.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(p[3 * i + static_cast<std::size_t>(k)], box.vertices[i][k]);
      EXPECT_EQ(n[3 * i + static_cast<std::size_t>(k)], box.normals[i][k]);
    }
  const std::vector<std::uint32_t> idx = rs::uints(m0.at("indices"), 2);
  ASSERT_EQ(idx.size(), 3 * box.triangles.size());
  for (std::size_t t = 0; t < box.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(idx[3 * t + static_cast<std::size_t>(k)], static_cast<std::uint32_t>(box.triangles[t][k]));
  EXPECT_EQ(m0.at("rgba").get<std::vector<float>>(), (std::vector<float>{0.25f, 0.5f, 0.75f, 1.0f}));
  const auto& m1 = bodies[1].at("meshes").at(0);
  EXPECT_TRUE(rs::floats(m1.at("normals")).empty()) << "no normals: the player shades flat faces";
  EXPECT_EQ(rs::floats(m1.at("positions")), (std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0.5f}));
  // More than 65536 vertices: 4-byte indices.
  SceneMesh big;
  big.vertices.assign(70000, Eigen::Vector3f::Zero());
  big.triangles = {{0, 1, 69999}};
  const rs::Script b = rs::parse(replay_scene_script(Scene{{{"big", {big}}}}, "k"));
  EXPECT_EQ(b.value["bodies"][0]["meshes"][0]["index_bytes"], 4);
  EXPECT_EQ(rs::uints(b.value["bodies"][0]["meshes"][0]["indices"], 4), (std::vector<std::uint32_t>{0, 1, 69999}));
  // The renderer's rules: an index out of range, normals of the wrong count.
  tri.triangles = {{0, 1, 3}};
  EXPECT_THROW(replay_scene_script(Scene{{{"arm", {tri}}}}, "k"), std::invalid_argument);
  tri.triangles = {{0, 1, 2}};
  tri.normals = {{0, 0, 1}};
  EXPECT_THROW(replay_scene_script(Scene{{{"arm", {tri}}}}, "k"), std::invalid_argument);
}

ReplayTrack two_samples() {
  ReplayTrack t;
  t.name = "walk/fast";
  t.time_s = {0.0, 0.02};
  Eigen::Isometry3d a = Eigen::Isometry3d::Identity(), b = Eigen::Isometry3d::Identity();
  a.translation() << 1.0, -2.0, 0.5;
  b.linear() = Eigen::AngleAxisd(2.5, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  b.translation() << 0.1, 0.2, 0.3;
  t.X_WB = {{a, b}, {b, a}};
  t.com_W = {{0, 0, 1}, {0, 0, 0.9}};
  t.forces = {{{{0.1, 0, 0}, {0, 0, 100}}}, {{{0.2, 0, 0}, {5, 0, 90}}}};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  t.paths = {{"desired", Color{0, 190, 255}, true, 1.5, {{nan, nan, nan}, {1, 2, 3}}}};
  t.markers = {{"foothold", Color{255, 140, 0}, 0.06, {{0, 0, 0}, {0.3, 0, 0}}}};
  t.texts = {{"phase", {"double", "left"}, {0, 1}}};
  return t;
}

// Every pose, force, point and value back as written (float32), the quaternion giving
// the rotation (to float32's precision).
TEST(ReplayData, TrackScriptHoldsEverySample) {
  const ReplayTrack t = two_samples();
  const rs::Script s = rs::parse(replay_track_script(t, "replay/variant_0.js"));
  EXPECT_EQ(s.table, "tracks");
  const auto& j = s.value;
  EXPECT_EQ(j.at("name"), "walk/fast");
  EXPECT_EQ(j.at("samples"), 2);
  EXPECT_EQ(j.at("bodies"), 2);
  EXPECT_EQ(rs::floats(j.at("times")), (std::vector<float>{0.0f, 0.02f}));
  const std::vector<float> P = rs::floats(j.at("poses"));
  ASSERT_EQ(P.size(), 2u * 2u * 7u);
  for (std::size_t k = 0; k < 2; ++k)
    for (std::size_t b = 0; b < 2; ++b) {
      const float* p = &P[7 * (2 * k + b)];
      const Eigen::Isometry3d& X = t.X_WB[k][b];
      EXPECT_NEAR((Eigen::Vector3d(p[0], p[1], p[2]) - X.translation()).norm(), 0, 1e-6);
      const Eigen::Quaterniond q(p[6], p[3], p[4], p[5]);
      EXPECT_NEAR(q.norm(), 1, 1e-6);
      EXPECT_NEAR((q.normalized().toRotationMatrix() - X.linear()).norm(), 0, 1e-6) << "sample " << k << " body " << b;
    }
  EXPECT_EQ(rs::floats(j.at("com")), (std::vector<float>{0, 0, 1, 0, 0, 0.9f}));
  EXPECT_EQ(j.at("sites"), 1);
  EXPECT_EQ(rs::floats(j.at("forces")), (std::vector<float>{0.1f, 0, 0, 0, 0, 100, 0.2f, 0, 0, 5, 0, 90}));
  const auto& path = j.at("paths").at(0);
  EXPECT_EQ(path.at("label"), "desired");
  EXPECT_EQ(path.at("dashed"), true);
  EXPECT_EQ(path.at("window_s"), 1.5);
  EXPECT_EQ(path.at("rgb"), nlohmann::json::array({0, 190, 255}));
  const std::vector<float> pts = rs::floats(path.at("points"));
  ASSERT_EQ(pts.size(), 6u);
  EXPECT_TRUE(std::isnan(pts[0]));
  EXPECT_EQ(pts[5], 3.0f);
  EXPECT_EQ(rs::floats(j.at("markers").at(0).at("points")), (std::vector<float>{0, 0, 0, 0.3f, 0, 0}));
  EXPECT_EQ(j.at("texts").at(0).at("names"), nlohmann::json::array({"double", "left"}));
  EXPECT_EQ(rs::floats(j.at("texts").at(0).at("values")), (std::vector<float>{0, 1}));
}

TEST(ReplayData, TrackScriptRefusesInconsistentSamples) {
  auto refused = [](void (*spoil)(ReplayTrack&)) {
    ReplayTrack t = two_samples();
    spoil(t);
    EXPECT_THROW(replay_track_script(t, "k"), std::invalid_argument);
  };
  refused([](ReplayTrack& t) { t.time_s.clear(); t.X_WB.clear(); t.com_W.clear(); t.forces.clear(); });
  refused([](ReplayTrack& t) { t.time_s[1] = 0.0; });                                   // not increasing
  refused([](ReplayTrack& t) { t.time_s[1] = std::numeric_limits<double>::infinity(); });
  refused([](ReplayTrack& t) { t.X_WB[1].pop_back(); });                                // another body count
  refused([](ReplayTrack& t) { t.X_WB.pop_back(); });                                   // fewer poses than times
  refused([](ReplayTrack& t) { t.com_W.pop_back(); });
  refused([](ReplayTrack& t) { t.forces[1].clear(); });                                 // another site count
  refused([](ReplayTrack& t) { t.paths[0].points_W.pop_back(); });
  refused([](ReplayTrack& t) { t.markers[0].points_W.push_back({0, 0, 0}); });
  refused([](ReplayTrack& t) { t.texts[0].values.pop_back(); });
  ReplayTrack none = two_samples();
  none.com_W.clear();
  none.forces.clear();
  const rs::Script s = rs::parse(replay_track_script(none, "k"));
  EXPECT_TRUE(rs::floats(s.value.at("com")).empty());
  EXPECT_EQ(s.value.at("sites"), 0);
}

Report replay_report() {
  Report r;
  r.title = "walk";
  r.replay.variants = {{"slow", "replay/variant_0.js", "replay/scene_0.js"}, {"fast & <b>", "replay/variant 1.js", "replay/scene_0.js"}};
  r.replay.initial = 1;
  r.replay.scripts = {"replay/three.min.js", "replay/OrbitControls.js"};
  r.replay.licence = "replay/three.js-LICENSE.txt";
  r.replay.camera.position = {1.5, -2, 1};
  r.replay.camera.look_at = {0, 0, 0.7};
  r.replay.camera.width_px = 640;
  r.replay.camera.height_px = 360;
  r.replay.title = "walk </script><b>";
  return r;
}

// The section: its controls, the variants with their scripts (percent-encoded, escaped
// names, the initial one selected), the setup the player reads (the camera), the library
// scripts before the player at the end of the body; '<' in the setup escaped.
TEST(ReplayPage, SectionScriptsAndSetup) {
  const std::string html = render_report_html(replay_report());
  for (const char* id : {"replay-play", "replay-time", "replay-clock", "replay-speed", "replay-variant", "replay-ground",
                         "replay-overlays", "replay-reset", "replay-canvas", "replay-hud", "replay-setup"})
    EXPECT_NE(html.find(std::string("id=\"") + id + "\""), std::string::npos) << id;
  EXPECT_NE(html.find("<option value=\"1\" data-track=\"replay/variant%201.js\" data-scene=\"replay/scene_0.js\" selected>"
                      "fast &amp; &lt;b&gt;</option>"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("<a href=\"replay/three.js-LICENSE.txt\">"), std::string::npos);
  const std::size_t three = html.find("<script src=\"replay/three.min.js\"></script>"),
                    orbit = html.find("<script src=\"replay/OrbitControls.js\"></script>"), player = html.find("<script>("),
                    main_end = html.find("</main>");
  ASSERT_NE(three, std::string::npos);
  EXPECT_LT(main_end, three);
  EXPECT_LT(three, orbit);
  EXPECT_LT(orbit, player);
  EXPECT_EQ(html.find("</script><b>"), std::string::npos) << "the title's '</script>' ended the setup";
  const std::string open = "<script type=\"application/json\" id=\"replay-setup\">";
  const std::size_t a = html.find(open) + open.size(), b = html.find("</script>", a);
  const nlohmann::json setup = nlohmann::json::parse(html.substr(a, b - a));
  EXPECT_EQ(setup["camera"]["position"], nlohmann::json::array({1.5, -2, 1}));
  EXPECT_EQ(setup["camera"]["look_at"], nlohmann::json::array({0, 0, 0.7}));
  EXPECT_EQ(setup["camera"]["fov_y_deg"], 40);
  EXPECT_EQ(setup["camera"]["width"], 640);
  EXPECT_EQ(setup["initial"], 1);
  EXPECT_EQ(setup["title"], "walk </script><b>");
  EXPECT_EQ(html.find("http"), std::string::npos) << "no external URL in the player either";
  // Without variants: no section, no script.
  Report none = replay_report();
  none.replay.variants.clear();
  EXPECT_EQ(render_report_html(none).find("<script"), std::string::npos);
}

TEST(ReplayPage, RefusesPathsOutsideTheDirectoryAndBadSetups) {
  for (const std::string bad : {"/tmp/x.js", "../x.js", "http://example.com/x.js", ""}) {
    Report r = replay_report();
    r.replay.variants[0].track = bad;
    EXPECT_THROW(render_report_html(r), std::invalid_argument) << bad;
    r = replay_report();
    r.replay.scripts[0] = bad;
    EXPECT_THROW(render_report_html(r), std::invalid_argument) << bad;
  }
  Report r = replay_report();
  r.replay.initial = 2;
  EXPECT_THROW(render_report_html(r), std::invalid_argument);
  r = replay_report();
  r.replay.scripts.pop_back();
  EXPECT_THROW(render_report_html(r), std::invalid_argument);
  r = replay_report();
  r.replay.camera.look_at = r.replay.camera.position;
  EXPECT_THROW(render_report_html(r), std::invalid_argument);
}

// Debian's three.js copied byte for byte with its licence; a folder without it is named.
TEST(ReplayPage, ThreeJsCopiedWithItsLicence) {
  test::TempDir dir("dmbd_test_replay");
  const std::vector<std::string> names = copy_three_js(dir.path().string());
  ASSERT_EQ(names, (std::vector<std::string>{"three.min.js", "OrbitControls.js", "three.js-LICENSE.txt"}));
  EXPECT_EQ(read_text(dir / "three.min.js"), read_text(three_js_dir() + "/three.min.js"));
  EXPECT_EQ(read_text(dir / "OrbitControls.js"), read_text(three_js_dir() + "/examples/js/controls/OrbitControls.js"));
  EXPECT_NE(read_text(dir / "three.min.js").find("REVISION=\"111\""), std::string::npos) << "Debian's r111";
  EXPECT_NE(read_text(dir / "three.js-LICENSE.txt").find("Permission is hereby granted"), std::string::npos);
  ::setenv("DMBD_THREE_JS_DIR", dir.path().string().c_str(), 1);
  fs::remove(dir.path() / "three.min.js");
  try {
    copy_three_js((dir.path() / "elsewhere").string());
    ADD_FAILURE() << "no error without three.min.js";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("libjs-three"), std::string::npos) << e.what();
  }
  ::unsetenv("DMBD_THREE_JS_DIR");
}

}  // namespace
}  // namespace dmbd::viz
