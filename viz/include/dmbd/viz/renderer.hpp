#pragma once
// The mesh renderer: an engineer's 3-D view of rigid bodies (a simulated robot) on a
// gridded ground plane, drawn into an OpenCV BGR 8-bit image by one or a few threads.
//
//   dmbd::viz::Renderer renderer(1280, 720);
//   renderer.set_scene(dmbd::viz::scene_from_robot(robot));   // once: geometry is converted here
//   dmbd::viz::Overlays ov;
//   ov.text_lines = {"t = 1.234 s", "phase: double support"};
//   ov.com_W = p_WCom;
//   ov.forces.push_back({p_WFoot, f_W_N});
//   ov.paths.push_back({desired_points_W, {0, 190, 255}, /*dashed=*/true, "desired"});
//   const cv::Mat& frame = renderer.render(X_WB, camera, ov);  // per frame: only poses change
//
// World frame: z up, the ground is the plane z = 0. Camera frame C (OpenCV): x right,
// y down, z forward. Pixel (c, r) covers [c, c+1) x [r, r+1) in the continuous pixel
// coordinates that project() returns; its centre, where the image is sampled, is
// (c + 0.5, r + 0.5). Distances in m, forces in N, angles in degrees where named _deg.
//
// After the first render() with a scene, render() does not allocate: it reuses the
// image, the depth and id buffers and the per-mesh scratch arrays sized by set_scene().
//
// Threads: a frame is drawn by `threads` threads (the caller's and threads - 1 helpers
// the renderer starts once and wakes per frame). They share the background's rows in
// small chunks, then each rasterises every triangle restricted to its band of rows.
// Every pixel is computed as with one thread, so the image, the depth and the ids are
// the same bytes for any thread count.
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "dmbd/viz/plot.hpp"  // Color

namespace dmbd::viz {

namespace detail {
struct RowBand;  // the rows one thread draws (renderer.cpp)
}  // namespace detail

// ---------------------------------------------------------------------------------
// Camera: a pinhole looking from `position` at `look_at`, `up` giving the image's
// upward direction (it need not be orthogonal to the view direction, only not parallel).
struct Camera {
  Eigen::Vector3d position{3.0, 2.0, 1.5};  // m, world
  Eigen::Vector3d look_at{0.0, 0.0, 0.6};   // m, world
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  double fov_y_deg = 40;  // vertical field of view, (0, 180)
  int width_px = 1280, height_px = 720;
  double near_m = 0.05;  // near clipping plane (camera z), > 0
};

// Throws std::invalid_argument naming the problem: sizes < 1 px, fov outside (0, 180),
// near_m <= 0, position == look_at, up parallel to the view direction, non-finite values.
void validate(const Camera& camera);
// Focal length in pixels: (height_px / 2) / tan(fov_y / 2). Square pixels.
double focal_length_px(const Camera& camera);
// World frame in camera frame (OpenCV axes: x right, y down, z forward).
Eigen::Isometry3d camera_from_world(const Camera& camera);  // X_CW
// Continuous pixel coordinates (u right, v down) of a world point:
//   u = W/2 + f x_C / z_C,  v = H/2 + f y_C / z_C,
// or nullopt when the point is not in front of the near plane (z_C < near_m).
// Points outside the image still project (u, v may be outside [0, W] x [0, H]).
std::optional<Eigen::Vector2d> project(const Camera& camera, const Eigen::Vector3d& p_W);

// ---------------------------------------------------------------------------------
// Scene: rigid bodies, each a list of triangle meshes fixed in the body frame B.
struct SceneMesh {
  std::vector<Eigen::Vector3f> vertices;         // m, body frame
  std::vector<Eigen::Vector3f> normals;          // per vertex, unit; empty: flat face normals
  std::vector<std::array<int, 3>> triangles;     // indices into vertices, counter-clockwise seen from outside
  Eigen::Vector4f rgba{0.7f, 0.7f, 0.7f, 1.0f};  // display (sRGB) colour in [0, 1]; alpha 0 hides the mesh,
                                                 // other alphas draw it opaque
  // Back-face culling is used only where it is safe: Auto culls when the mesh is closed
  // and consistently wound outward (every edge, with vertices welded by position, shared
  // by exactly two triangles in opposite directions, and positive enclosed volume), so
  // its back faces can only be seen from inside it; TwoSided never culls and shades each
  // triangle from the side the camera sees (open meshes are always drawn that way).
  enum class Faces { Auto, TwoSided };
  Faces faces = Faces::Auto;
};

struct SceneBody {
  std::string name;
  std::vector<SceneMesh> meshes;
};

struct Scene {
  std::vector<SceneBody> bodies;
  std::size_t triangle_count() const;
  std::size_t vertex_count() const;
};

// Axis-aligned bounds of all vertices with the bodies at X_WB (empty box for no vertices).
// Throws std::invalid_argument if X_WB.size() != scene.bodies.size().
Eigen::AlignedBox3d scene_bounds(const Scene& scene, const std::vector<Eigen::Isometry3d>& X_WB);
// Shifts every pose vertically so that the lowest vertex lies on the ground (z = 0);
// returns the shift in m (0 for a scene without vertices). Same throw as scene_bounds.
double place_on_ground(const Scene& scene, std::vector<Eigen::Isometry3d>& X_WB);

// ---------------------------------------------------------------------------------
// Overlays, drawn in 2-D after the 3-D pass (not hidden by geometry), anti-aliased.
struct ForceArrow {
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();    // application point, m
  Eigen::Vector3d f_W_N = Eigen::Vector3d::Zero();  // force, N (arrow points along it)
  Color color{230, 50, 40};
};

// A polyline through world points (a trajectory: where a point was or should be), drawn
// in its colour over a thin dark halo, solid or dashed (the dashes run on across its
// vertices). Segments are clipped at the camera's near plane, so points behind the
// camera are left out; a non-finite point breaks the line. Vertices closer than 2 px
// on screen to the last one drawn are merged (a path logged at 1 kHz has many), except
// the last one.
struct PathOverlay {
  std::vector<Eigen::Vector3d> points_W;  // m, world, in order
  Color color{0, 190, 255};
  bool dashed = false;
  std::string label;  // not empty: an entry in the legend (top-right corner): a sample
                      // of the line in its colour and style, then the label (ASCII)
};

// A point marked where it is (a planned foothold): a ring of ring_m radius in the
// horizontal plane through it and a cross at its centre, over a dark halo.
struct MarkerOverlay {
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();  // m, world
  Color color{255, 140, 0};
  double ring_m = 0.06;
  std::string label;  // not empty: an entry in the legend (top-right corner), as a path's
};

struct Overlays {
  std::vector<std::string> text_lines;   // top-left corner, one per line, on a dark panel (ASCII)
  std::optional<Eigen::Vector3d> com_W;  // centre of mass: circled crosshair, a dashed drop line
                                         // and a ring on the ground at its projection (z = 0)
  std::vector<ForceArrow> forces;
  std::vector<PathOverlay> paths;      // drawn first, under the arrows and the CoM marker
  std::vector<MarkerOverlay> markers;  // after the paths
  double force_scale_m_per_N = 0.001;  // arrow length in the world per newton
  double line_width_px = 2.0;          // arrows, CoM marker, paths
  Color com_color{255, 210, 0};
};

// ---------------------------------------------------------------------------------
// Looks: lights, ground, background. Public fields; change them between frames.
struct RenderStyle {
  // Directional key light: direction from the scene towards the light (need not be
  // unit). The default comes from the front-right and above, so in the default 3/4 view
  // from the front-left the front faces are lit, the left faces shaded, and the shadow
  // falls to the back-left where the camera sees it.
  Eigen::Vector3d light_from_W{0.7, -0.35, 1.0};
  // Lambert + ambient in linear light, times the linear albedo:
  //   ambient (lerped from ambient_down to ambient_up as the normal turns from -z to +z)
  //   + diffuse max(0, n.l) + fill max(0, n.v) (a headlight from the camera)
  //   + specular max(0, n.h)^32 (white, Blinn half vector of l and the view axis),
  // then converted to sRGB.
  double ambient_up = 0.3, ambient_down = 0.16, diffuse = 0.85, fill = 0.25, specular = 0.2;
  // Ground plane z = 0 with grid lines (constant width in pixels, the minor ones fading
  // out as they crowd together), the world x (red) and y (green) axes, and a fade into
  // the horizon haze with distance.
  bool ground = true;
  bool grid = true;
  bool axes = true;
  bool shadows = true;              // soft projected shadow of all meshes on the ground
  double shadow_strength = 0.55;    // fraction of ground light removed under the full shadow
  double shadow_softness_m = 0.02;  // blur radius
  double grid_minor_m = 0.1, grid_major_m = 1.0;
  double ground_fade_start_m = 6, ground_fade_end_m = 25;  // camera distance
  Color ground_color{196, 196, 190};
  Color grid_minor_color{160, 160, 156};
  Color grid_major_color{110, 110, 108};
  Color axis_x_color{200, 70, 60}, axis_y_color{70, 160, 70};
  // Background: sky gradient by elevation of the view ray (horizon -> zenith); below the
  // horizon (no ground drawn) it goes from the horizon colour to `floor_color`.
  Color sky_zenith{92, 124, 168}, sky_horizon{214, 222, 230}, floor_color{150, 154, 160};
};

// ---------------------------------------------------------------------------------
// Z-buffered triangle rasteriser written by hand (OpenCV has no 3-D rasteriser: its
// drawing functions are 2-D only and have no depth test). Near-plane and guard-band
// clipping in camera space, exact fixed-point coverage (8 sub-pixel bits, a top-left
// tie rule so shared edges have no cracks or double pixels), per-pixel shading with
// perspective-correct normal interpolation.
class Renderer {
 public:
  // Throws std::invalid_argument unless both sizes are in [16, 16384] px and threads is
  // in [0, 64]. threads: how many threads draw a frame (1: the caller's alone); 0 picks
  // min(2, std::thread::hardware_concurrency()) (2 when that is unknown).
  Renderer(int width_px, int height_px, int threads = 0);
  ~Renderer();
  Renderer(Renderer&&);
  Renderer& operator=(Renderer&&);
  Renderer(const Renderer&) = delete;  // owns large buffers; make another one instead
  Renderer& operator=(const Renderer&) = delete;

  // Converts and keeps the geometry (the Scene itself is not referenced afterwards).
  // Throws std::invalid_argument naming the body and mesh for an index out of range,
  // a normals array of the wrong size or a non-finite vertex.
  void set_scene(const Scene& scene);
  std::size_t body_count() const { return bodies_.empty() ? 0 : bodies_.size() - 1; }
  std::size_t triangle_count() const { return triangle_count_; }
  int width_px() const { return width_; }
  int height_px() const { return height_; }
  int thread_count() const { return threads_; }
  // Meshes found closed and outward wound, so drawn with back-face culling.
  std::size_t closed_mesh_count() const;

  RenderStyle& style() { return style_; }
  const RenderStyle& style() const { return style_; }

  // Draws the scene with body b at X_WB[b] and then the overlays. Returns the image
  // (BGR, width x height), owned by the renderer and overwritten by the next call.
  // Throws std::invalid_argument if X_WB.size() != body_count(), if the camera is not
  // valid or its size differs from the renderer's.
  const cv::Mat& render(const std::vector<Eigen::Isometry3d>& X_WB, const Camera& camera,
                        const Overlays& overlays = {});

  // Buffers of the last render(), same size as the image:
  const cv::Mat& image() const { return image_; }
  // CV_32F: 1 / (camera z in m) of the nearest surface, 0 where nothing (sky) was drawn.
  const cv::Mat& inverse_depth() const { return inv_depth_; }
  // CV_16S: index of the body seen at each pixel, -1 for ground or background.
  const cv::Mat& body_ids() const { return ids_; }

  // Counts from the last render().
  struct Stats {
    std::size_t meshes_drawn = 0, meshes_culled = 0;  // whole meshes outside the view
    std::size_t triangles_in = 0, triangles_rasterised = 0;
    std::size_t triangles_backfacing = 0, triangles_clipped = 0;
  };
  const Stats& stats() const { return stats_; }

  // Overlays alone, on the current image (render() calls it last). Allocation free.
  void draw_overlays(const Camera& camera, const Overlays& overlays);

 private:
  struct Glyph {
    int advance = 0;     // px
    int x0 = 0, y0 = 0;  // offset of the mask's top-left from the pen (baseline) position
    cv::Mat coverage;    // CV_8U anti-aliased mask
  };
  struct PreparedMesh;    // converted geometry (defined in renderer.cpp)
  struct Vertex;          // per-frame scratch
  struct BackgroundPlan;  // what the bands draw of the background this frame
  class Workers;          // the helper threads

  void build_shadow_map(const std::vector<Eigen::Isometry3d>& X_WB);
  // Serial part of the background (sky table, the kept background's bookkeeping).
  BackgroundPlan plan_background(const Camera& camera, const Eigen::Isometry3d& X_WC);
  // Rows [r_begin, r_end) of the background, by thread `thread` (its row buffer).
  void draw_background_and_ground(const Camera& camera, const Eigen::Isometry3d& X_WC, const BackgroundPlan& plan,
                                  int r_begin, int r_end, int thread);
  // The meshes in one band's rows; the bands run at the same time.
  void draw_meshes(const std::vector<Eigen::Isometry3d>& X_WB, const Eigen::Isometry3d& X_CW, double f_px,
                   double near_m, const detail::RowBand& band, Stats& stats);

  int width_, height_;
  int threads_ = 1;
  // Helper threads (threads_ - 1 of them; none for one thread). Behind a pointer so
  // that they keep their address when the renderer moves.
  std::unique_ptr<Workers> workers_;
  RenderStyle style_;
  cv::Mat image_, inv_depth_, ids_;
  std::vector<PreparedMesh> meshes_;  // all bodies' meshes, flattened
  std::vector<std::size_t> bodies_;   // index of each body's first mesh in meshes_ (+ end)
  std::size_t triangle_count_ = 0;
  std::vector<Vertex> scratch_;  // per-frame transformed vertices of one mesh, per band
  std::size_t scratch_stride_ = 0;  // vertices per band in scratch_
  // Shadow map: coverage of the ground by the meshes' projections along the light.
  std::vector<float> shadow_, shadow_tmp_;
  int shadow_n_ = 0;
  double shadow_x0_ = 0, shadow_y0_ = 0, shadow_texel_m_ = 1;
  bool shadow_valid_ = false;
  std::vector<unsigned char> linear_to_srgb_;  // 4096 entries over [0, 1]
  std::vector<unsigned char> sky_lut_;         // BGR by elevation
  std::vector<float> row_;                     // row buffer of the sky, per band
  // The background (sky, ground, grid) without the shadow, kept for a camera seen twice
  // in a row: what decides it (the camera and the looks), and its image and 1/z.
  static constexpr std::size_t kBackgroundKeyN = 43;
  std::array<double, kBackgroundKeyN> background_key_{};
  bool background_seen_ = false, background_cached_ = false;
  cv::Mat cached_image_, cached_inv_depth_;
  std::array<Glyph, 95> glyphs_;  // ' ' .. '~'
  int text_line_px_ = 0, text_ascent_px_ = 0;
  Stats stats_;
};

}  // namespace dmbd::viz
