#pragma once
// The data of a 3-D replay in a web page (report.html's replay section, viz/report.hpp):
// a scene's meshes and the bodies' poses over time, each written as a small JavaScript
// file that the page loads with a <script> element (a page opened from file:// cannot
// fetch() a JSON file in Chromium; a script can be loaded). The numbers are float32
// (meshes' indices uint16 or uint32), little-endian, base64 text inside the file:
//
//   dmbdReplay.scenes["replay/scene_0.js"] = {bodies: [{name, meshes: [{rgba, positions,
//       normals, indices, index_bytes}]}]};
//   dmbdReplay.tracks["replay/variant_0.js"] = {name, bodies, samples, times, poses, com,
//       sites, forces, paths: [{label, rgb, dashed, window_s, points}],
//       markers: [{label, rgb, ring_m, points}], texts: [{label, names, values}]};
//
// poses: per sample, per body, x y z (m, world) and the rotation's quaternion x y z w;
// com: per sample x y z (NaN: none); forces: per sample, per site, the point x y z (m)
// and the force x y z (N); a path's or marker's points: per sample x y z (NaN: not
// logged yet); a text's values: per sample (names[k] for a value k).
//
//   dmbd::viz::ReplayTrack t;
//   t.name = "actuated";
//   t.time_s = {0, 0.02};
//   t.X_WB = {poses_at_0, poses_at_0_02};          // one pose per scene body
//   dmbd::write_file_atomic("replay/variant_0.js", replay_track_script(t, "replay/variant_0.js"));
//   // The page's copy of three.js (Debian's libjs-three) beside them:
//   copy_three_js("out/replay");
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "dmbd/viz/plot.hpp"  // Color
#include "dmbd/viz/renderer.hpp"

namespace dmbd::viz {

struct ReplayPath {  // a polyline over the last window_s of the run (a PathOverlay's data)
  std::string label;
  Color color{0, 190, 255};
  bool dashed = false;
  double window_s = 2.0;
  std::vector<Eigen::Vector3d> points_W;  // one per sample; non-finite: not there yet
};

struct ReplayMarker {  // a ring and a cross at a point (a MarkerOverlay's data)
  std::string label;
  Color color{255, 140, 0};
  double ring_m = 0.06;
  std::vector<Eigen::Vector3d> points_W;  // one per sample
};

struct ReplayText {  // a line "LABEL: VALUE" (or the value's name) under the time
  std::string label;
  std::vector<std::string> value_names;
  std::vector<double> values;  // one per sample
};

struct ReplayForce {
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero(), f_W_N = Eigen::Vector3d::Zero();  // a zero force is not drawn
};

// One variant's replay: the scene's bodies at each sample time and what is drawn over them.
struct ReplayTrack {
  std::string name;
  std::vector<double> time_s;                        // increasing
  std::vector<std::vector<Eigen::Isometry3d>> X_WB;  // [sample][body], the same body count every sample
  std::vector<Eigen::Vector3d> com_W;                // empty, or one per sample
  std::vector<std::vector<ReplayForce>> forces;      // empty, or [sample][site], the same site count every sample
  std::vector<ReplayPath> paths;
  std::vector<ReplayMarker> markers;
  std::vector<ReplayText> texts;
};

// `key` is the file's path relative to the page, the name under which the page finds it.
// Throws std::invalid_argument naming the body and mesh for an index out of range or a
// normals array of the wrong size (the renderer's rules).
std::string replay_scene_script(const Scene& scene, const std::string& key);
// Throws std::invalid_argument naming what is wrong: no sample, times not increasing or
// not finite, a sample with another body or site count, a per-sample list of another
// length than time_s.
std::string replay_track_script(const ReplayTrack& track, const std::string& key);

// Where the page's three.js comes from: Debian's libjs-three (r111), unless
// DMBD_THREE_JS_DIR names another folder with the same layout.
std::string three_js_dir();
// Copies three.min.js and examples/js/controls/OrbitControls.js into `folder` (which
// must exist; each file written atomically), with three.js's licence as
// three.js-LICENSE.txt (the package's copyright file, /usr/share/doc/libjs-three/copyright,
// or the MIT licence's text where the documentation was not installed), and returns the
// three names. Throws InputError naming the file when three.js is not installed
// ("install libjs-three") and OutputError when a copy cannot be written.
std::vector<std::string> copy_three_js(const std::string& folder);

}  // namespace dmbd::viz
