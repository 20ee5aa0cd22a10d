// The mesh renderer: camera, scene preparation, background and ground, soft projected
// shadows, a z-buffered triangle rasteriser and 2-D overlays.
//
// OpenCV has no 3-D rasteriser (its drawing functions are 2-D and have no depth test),
// so the triangles are rasterised here by hand:
//   * per mesh: bounding-sphere test against the view frustum, vertices to camera frame
//     (float), projection and an outcode per vertex;
//   * per triangle: trivial reject (all vertices beyond one image side or behind the near
//     plane), back-face culling for meshes found closed and outward wound, clipping in
//     camera space against the near plane and a guard band only for the few triangles
//     that need it;
//   * coverage: fixed-point edge functions (8 sub-pixel bits, int64), exact per row: the
//     span where all three edge functions are non-negative is estimated in double and
//     corrected with the exact integer test at its ends, so thin slanted triangles cost
//     their pixels, not their bounding box. A tie rule (include an edge's pixels when
//     a > 0, or a == 0 and b < 0, for E = a x + b y + c) draws a pixel centre lying on an
//     edge shared by two triangles exactly once;
//   * attributes: 1/z and the normal times 1/z are affine in screen space, evaluated
//     per pixel from plane equations; normalising the interpolated n/z gives the
//     perspective-correct normal for free (the 1/z factor cancels);
//   * shading per pixel in linear light, converted to sRGB through a table.
// The z-buffer holds 1/z (0 = nothing): larger is nearer.
//
// No allocation happens in render() after set_scene(): every buffer is sized before.
//
// Threads: the background is drawn by chunks of kBandRows rows, which the threads take
// in turn; then the rows are dealt out in chunks to the bands (RowBand), and each band,
// on its own thread, rasterises every triangle restricted to its rows. A row's
// background, and a pixel's triangles, are computed from the same floats in the same
// order as by one thread (triangle setup does not depend on the band), so the bytes do
// not depend on the thread count. The shadow map, the sky table and the overlays are
// drawn by the calling thread alone.
#include "dmbd/viz/renderer.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <condition_variable>
#include <cstring>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <type_traits>
#include <unordered_map>
#include <utility>

#include <opencv2/imgproc.hpp>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace dmbd::viz {

// ---------------------------------------------------------------------------------
// Internal types.

struct Renderer::PreparedMesh {
  int body = 0;
  std::vector<Eigen::Vector3f> pos;  // body frame
  std::vector<Eigen::Vector3f> nrm;  // unit, or empty (flat)
  std::vector<std::array<int, 3>> tri;
  float albedo[3] = {0, 0, 0};                       // linear RGB
  bool cull = false;                                 // closed and outward: back faces are never seen
  bool visible = true;                               // alpha > 0
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();  // bounding sphere, body frame
  float radius = 0;
};

struct Renderer::Vertex {
  float x, y, z;     // camera frame
  float nx, ny, nz;  // camera frame, unit (smooth meshes)
  float sx, sy, iz;  // pixel coordinates and 1/z (valid unless behind the near plane)
  unsigned code;     // outcode bits below
};

// What the bands draw of the background (plan_background decides it for the frame):
// every pixel (kDraw); every pixel without the shadow, kept, then the shaded ground
// again (kDrawAndKeep); the kept pixels, then the shaded ground again (kFromKept).
// The shaded ground: the ground's segments that may be on the shadow map, in rows
// [r_lo, r_hi] and columns [c_lo, c_hi].
struct Renderer::BackgroundPlan {
  enum Mode { kDraw, kDrawAndKeep, kFromKept } mode = kDraw;
  bool shaded = false;
  int r_lo = 0, r_hi = -1, c_lo = 0, c_hi = -1;
};

// Helper threads for bands 1 .. n (the caller draws band 0): started by the renderer's
// constructor, woken once per frame, joined by the destructor. A frame's job is handed
// over as a function pointer and a context pointer, so nothing is allocated per frame.
class Renderer::Workers {
 public:
  explicit Workers(int helpers) {
    threads_.reserve(std::size_t(helpers));
    for (int i = 0; i < helpers; ++i) threads_.emplace_back([this, i] { loop(i + 1); });
  }
  ~Workers() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : threads_) t.join();
  }
  Workers(const Workers&) = delete;
  Workers& operator=(const Workers&) = delete;

  // job(band) for every band, band 0 on the calling thread; returns when all are done
  // (also if job(0) throws: the helpers' bands refer to the caller's frame).
  template <class Job>
  void run(Job& job) {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      fn_ = [](void* ctx, int band) { (*static_cast<Job*>(ctx))(band); };
      ctx_ = &job;
      pending_ = static_cast<int>(threads_.size());
      ++generation_;
    }
    wake_.notify_all();
    struct Wait {
      Workers& w;
      ~Wait() {
        std::unique_lock<std::mutex> lock(w.mutex_);
        w.done_.wait(lock, [this] { return w.pending_ == 0; });
      }
    } wait{*this};
    job(0);
  }

 private:
  void loop(int band) {
    std::uint64_t seen = 0;
    for (;;) {
      void (*fn)(void*, int) = nullptr;
      void* ctx = nullptr;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
        if (stop_) return;
        seen = generation_;
        fn = fn_;
        ctx = ctx_;
      }
      fn(ctx, band);
      const std::lock_guard<std::mutex> lock(mutex_);
      if (--pending_ == 0) done_.notify_one();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_, done_;
  void (*fn_)(void*, int) = nullptr;
  void* ctx_ = nullptr;
  std::uint64_t generation_ = 0;  // one per frame: a helper runs each job once
  int pending_ = 0;               // helpers still drawing this frame
  bool stop_ = false;
  std::vector<std::thread> threads_;
};

namespace {

constexpr unsigned kNear = 1, kLeft = 2, kRight = 4, kTop = 8, kBottom = 16, kGuard = 32;
constexpr unsigned kOutside = kNear | kLeft | kRight | kTop | kBottom;
constexpr float kGuardPx = 2048.0f;  // beyond the image; keeps fixed-point products far from overflow
constexpr int kSubBits = 8;
constexpr std::int64_t kSub = std::int64_t{1} << kSubBits;
constexpr std::int64_t kHalfSub = kSub / 2;
constexpr int kShadowN = 256;  // shadow map texels per side
constexpr int kLutN = 4096;    // linear -> sRGB table entries over [0, 1]
constexpr int kSkyN = 1024;    // sky colours over the elevation sine in [-1, 1]
constexpr int kRowArrays = 1;  // float row buffers of the sky, W + 4 floats each (per band)
// Rows per chunk, of the background (taken by the threads in turn) and of the meshes
// (dealt out to the bands in turn): small, so that every band gets its share of the
// robot, and large enough that a small triangle usually lies in one band's rows (the
// others skip it after its bounding box).
constexpr int kBandRows = 8;
constexpr int kMaxThreads = 64;

}  // namespace

namespace detail {

// The rows of band `index` of `count`: chunk q (rows [q kBandRows, (q + 1) kBandRows))
// belongs to band q mod count. Iterate with
//   for (int r = band.first_from(lo); r <= hi; r = band.next(r)).
struct RowBand {
  int index = 0, count = 1;
  // The band's first row at or after r (past the image when none is left).
  int first_from(int r) const {
    if (count == 1) return r;
    const int q = r / kBandRows, k = q % count;
    return k == index ? r : (q + (index - k + count) % count) * kBandRows;
  }
  // The band's row after its row r.
  int next(int r) const {
    ++r;
    return count == 1 || r % kBandRows != 0 ? r : r + (count - 1) * kBandRows;
  }
};

}  // namespace detail

namespace {

using detail::RowBand;

// ---------------------------------------------------------------------------------
// Small helpers.

double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }
double linear_to_srgb(double c) { return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055; }

std::int64_t floor_div(std::int64_t n, std::int64_t d) {
  std::int64_t q = n / d;
  const std::int64_t r = n % d;
  if (r != 0 && ((r < 0) != (d < 0))) --q;
  return q;
}
std::int64_t ceil_div(std::int64_t n, std::int64_t d) { return -floor_div(-n, d); }

float clamp01(float v) { return v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v); }

// Four floats at a time through GCC/Clang vector extensions (SSE2 on x86-64, NEON on
// ARM): branch-free arithmetic the ground pass needs, which GCC does not vectorise
// from scalar code (the float selects stay branches).
typedef float v4f __attribute__((vector_size(16)));
typedef int v4i __attribute__((vector_size(16)));
v4f vset(float x) { return v4f{x, x, x, x}; }
void vstore(float* p, v4f v) { std::memcpy(p, &v, sizeof v); }
#if defined(__SSE2__)
// x86-64: single instructions where the generic selects below would take four.
v4f vmin(v4f a, v4f b) { return _mm_min_ps(a, b); }
v4f vmax(v4f a, v4f b) { return _mm_max_ps(a, b); }
v4f vabs(v4f a) { return _mm_andnot_ps(_mm_set1_ps(-0.0f), a); }
v4f vclamp01(v4f a) { return vmin(vmax(a, vset(0.0f)), vset(1.0f)); }
v4f vsqrt(v4f a) { return _mm_sqrt_ps(a); }
// Distance to the nearest integer (|x| clamped to 1e6 first; rounds to nearest).
v4f vfrac_dist(v4f x) {
  x = vmin(vmax(x, vset(-1e6f)), vset(1e6f));
  return vabs(x - _mm_cvtepi32_ps(_mm_cvtps_epi32(x)));
}
bool vany(v4i m) { return _mm_movemask_ps(_mm_castsi128_ps(reinterpret_cast<__m128i>(m))) != 0; }
#else
bool vany(v4i m) { return (m[0] | m[1] | m[2] | m[3]) != 0; }
v4f vmin(v4f a, v4f b) { return a < b ? a : b; }
v4f vmax(v4f a, v4f b) { return a > b ? a : b; }
v4f vabs(v4f a) { return a < vset(0.0f) ? -a : a; }
v4f vclamp01(v4f a) { return vmin(vmax(a, vset(0.0f)), vset(1.0f)); }
v4f vsqrt(v4f a) { return v4f{std::sqrt(a[0]), std::sqrt(a[1]), std::sqrt(a[2]), std::sqrt(a[3])}; }
v4f vfrac_dist(v4f x) {
  x = vmin(vmax(x, vset(-1e6f)), vset(1e6f));
  const v4f h = x >= vset(0.0f) ? vset(0.5f) : vset(-0.5f);
  const v4i i = __builtin_convertvector(x + h, v4i);
  return vabs(x - __builtin_convertvector(i, v4f));
}
#endif

struct Rgbf {
  float r, g, b;
};
Rgbf rgbf(const Color& c) { return {float(c.r), float(c.g), float(c.b)}; }
Rgbf lerp(const Rgbf& a, const Rgbf& b, float t) {
  return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t};
}
void put_bgr(unsigned char* p, const Rgbf& c) {
  p[0] = static_cast<unsigned char>(c.b + 0.5f);
  p[1] = static_cast<unsigned char>(c.g + 0.5f);
  p[2] = static_cast<unsigned char>(c.r + 0.5f);
}

// ---------------------------------------------------------------------------------
// Rasteriser.

struct Target {
  unsigned char* rgb;
  float* z;
  std::int16_t* id;
  std::size_t rgb_step, z_step, id_step;  // bytes, floats, int16s per row
  int W, H;
};

struct Shader {
  float L[3], U[3], Hv[3];  // light, world up, half vector (camera frame, unit)
  float amb_mid, amb_half, kd, kf, ks;
  const unsigned char* lut;
  float albedo[3];
  std::int16_t id;

  void shade(float nx, float ny, float nz, unsigned char* bgr) const {
    const float len2 = nx * nx + ny * ny + nz * nz;
    const float inv = len2 > 0.0f ? 1.0f / std::sqrt(len2) : 0.0f;
    nx *= inv;
    ny *= inv;
    nz *= inv;
    const float nl = nx * L[0] + ny * L[1] + nz * L[2];
    const float nu = nx * U[0] + ny * U[1] + nz * U[2];
    float nh = nx * Hv[0] + ny * Hv[1] + nz * Hv[2];
    nh = nh > 0.0f ? nh : 0.0f;
    nh *= nh;  // ^2
    nh *= nh;  // ^4
    nh *= nh;  // ^8
    nh *= nh;  // ^16
    nh *= nh;  // ^32
    const float light = amb_mid + amb_half * nu + kd * (nl > 0.0f ? nl : 0.0f) + kf * (nz < 0.0f ? -nz : 0.0f);
    const float spec = ks * nh;
    const float scale = static_cast<float>(kLutN - 1);
    const auto idx = [&](float lin) { return static_cast<int>(clamp01(lin) * scale + 0.5f); };
    bgr[0] = lut[idx(albedo[2] * light + spec)];
    bgr[1] = lut[idx(albedo[1] * light + spec)];
    bgr[2] = lut[idx(albedo[0] * light + spec)];
  }
};

// A vertex ready for rasterisation: pixel coordinates, 1/z and (smooth) n/z.
struct RVert {
  float sx, sy, iz;
  float nx, ny, nz;
};

// Rasterises one triangle. kSmooth: interpolate n/z per pixel and shade each pixel;
// otherwise the whole triangle has the colour `flat`.
template <bool kSmooth>
void raster_triangle(const RVert& va, const RVert& vb, const RVert& vc, const Target& t, const Shader& sh,
                     const unsigned char* flat, const RowBand& band) {
  const RVert* v[3] = {&va, &vb, &vc};
  std::int64_t X[3], Y[3];
  for (int i = 0; i < 3; ++i) {
    X[i] = static_cast<std::int64_t>(std::lrint(double(v[i]->sx) * double(kSub)));
    Y[i] = static_cast<std::int64_t>(std::lrint(double(v[i]->sy) * double(kSub)));
  }
  std::int64_t area = (X[1] - X[0]) * (Y[2] - Y[0]) - (Y[1] - Y[0]) * (X[2] - X[0]);
  if (area == 0) return;
  if (area < 0) {  // make the edge functions positive inside
    std::swap(v[1], v[2]);
    std::swap(X[1], X[2]);
    std::swap(Y[1], Y[2]);
    area = -area;
  }
  // Pixel-centre bounding box, clamped to the image.
  const std::int64_t minX = std::min({X[0], X[1], X[2]}), maxX = std::max({X[0], X[1], X[2]});
  const std::int64_t minY = std::min({Y[0], Y[1], Y[2]}), maxY = std::max({Y[0], Y[1], Y[2]});
  const std::int64_t c_lo = std::max<std::int64_t>(0, ceil_div(minX - kHalfSub, kSub));
  const std::int64_t c_hi = std::min<std::int64_t>(t.W - 1, floor_div(maxX - kHalfSub, kSub));
  const std::int64_t r_lo = std::max<std::int64_t>(0, ceil_div(minY - kHalfSub, kSub));
  const std::int64_t r_hi = std::min<std::int64_t>(t.H - 1, floor_div(maxY - kHalfSub, kSub));
  if (c_lo > c_hi || r_lo > r_hi) return;
  const std::int64_t r_first = band.first_from(static_cast<int>(r_lo));
  if (r_first > r_hi) return;  // none of the band's rows

  // Edge i from v[i] to v[i+1]: E = a x + b y + c, >= 0 inside (after the tie bias).
  std::int64_t ea[3], eb[3], ec[3], A[3];
  double invA[3];
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    ea[i] = Y[i] - Y[j];
    eb[i] = X[j] - X[i];
    ec[i] = X[i] * Y[j] - X[j] * Y[i];
    const bool include_ties = ea[i] > 0 || (ea[i] == 0 && eb[i] < 0);
    ec[i] += ea[i] * kHalfSub + (include_ties ? 0 : -1);  // pixel centre offset in x, tie bias
    A[i] = ea[i] * kSub;                                  // per pixel step in x
    invA[i] = A[i] != 0 ? 1.0 / double(A[i]) : 0.0;
  }

  // Attribute planes in pixel units, anchored at vertex 0.
  const double x0 = double(X[0]) / kSub, y0 = double(Y[0]) / kSub;
  const double e1x = double(X[1] - X[0]) / kSub, e1y = double(Y[1] - Y[0]) / kSub;
  const double e2x = double(X[2] - X[0]) / kSub, e2y = double(Y[2] - Y[0]) / kSub;
  const double inv_det = 1.0 / (e1x * e2y - e2x * e1y);
  struct Plane {
    double f0, dx, dy;
  };
  const auto plane = [&](float f0, float f1, float f2) {
    const double d1 = double(f1) - f0, d2 = double(f2) - f0;
    return Plane{double(f0), (d1 * e2y - d2 * e1y) * inv_det, (d2 * e1x - d1 * e2x) * inv_det};
  };
  const Plane piz = plane(v[0]->iz, v[1]->iz, v[2]->iz);
  Plane pnx{}, pny{}, pnz{};
  if constexpr (kSmooth) {
    pnx = plane(v[0]->nx, v[1]->nx, v[2]->nx);
    pny = plane(v[0]->ny, v[1]->ny, v[2]->ny);
    pnz = plane(v[0]->nz, v[1]->nz, v[2]->nz);
  }

  const double dc_lo = double(c_lo), dc_hi = double(c_hi);
  for (std::int64_t r = r_first; r <= r_hi; r = band.next(static_cast<int>(r))) {
    const std::int64_t py = r * kSub + kHalfSub;
    std::int64_t E[3];
    double lo = dc_lo - 1.0, hi = dc_hi + 1.0;
    bool empty = false;
    for (int i = 0; i < 3; ++i) {
      E[i] = eb[i] * py + ec[i];  // value at column 0
      if (A[i] > 0) {
        lo = std::max(lo, -double(E[i]) * invA[i]);
      } else if (A[i] < 0) {
        hi = std::min(hi, -double(E[i]) * invA[i]);
      } else if (E[i] < 0) {
        empty = true;
      }
    }
    if (empty || lo > hi + 2.0) continue;
    // The double estimate is within a fraction of a pixel; widen by one and trim exactly.
    std::int64_t x_a =
        std::max<std::int64_t>(c_lo, static_cast<std::int64_t>(std::ceil(std::min(lo, dc_hi + 1.0))) - 1);
    std::int64_t x_b =
        std::min<std::int64_t>(c_hi, static_cast<std::int64_t>(std::floor(std::max(hi, dc_lo - 1.0))) + 1);
    const auto inside = [&](std::int64_t x) {
      return E[0] + A[0] * x >= 0 && E[1] + A[1] * x >= 0 && E[2] + A[2] * x >= 0;
    };
    while (x_a <= x_b && !inside(x_a)) ++x_a;
    while (x_b >= x_a && !inside(x_b)) --x_b;
    if (x_a > x_b) continue;

    const double yc = double(r) + 0.5 - y0, xa = double(x_a) + 0.5 - x0;
    const float iz0 = static_cast<float>(piz.f0 + piz.dx * xa + piz.dy * yc), dizx = static_cast<float>(piz.dx);
    float* zrow = t.z + std::size_t(r) * t.z_step;
    std::int16_t* idrow = t.id + std::size_t(r) * t.id_step;
    unsigned char* crow = t.rgb + std::size_t(r) * t.rgb_step;
    const int n = static_cast<int>(x_b - x_a);
    const int xs = static_cast<int>(x_a);
    if constexpr (kSmooth) {
      const float nx0 = static_cast<float>(pnx.f0 + pnx.dx * xa + pnx.dy * yc), nxx = static_cast<float>(pnx.dx);
      const float ny0 = static_cast<float>(pny.f0 + pny.dx * xa + pny.dy * yc), nyx = static_cast<float>(pny.dx);
      const float nz0 = static_cast<float>(pnz.f0 + pnz.dx * xa + pnz.dy * yc), nzx = static_cast<float>(pnz.dx);
      for (int k = 0; k <= n; ++k) {
        const float iz = iz0 + dizx * float(k);
        const int x = xs + k;
        if (iz > zrow[x]) {
          zrow[x] = iz;
          idrow[x] = sh.id;
          sh.shade(nx0 + nxx * float(k), ny0 + nyx * float(k), nz0 + nzx * float(k), crow + 3 * x);
        }
      }
    } else {
      for (int k = 0; k <= n; ++k) {
        const float iz = iz0 + dizx * float(k);
        const int x = xs + k;
        if (iz > zrow[x]) {
          zrow[x] = iz;
          idrow[x] = sh.id;
          unsigned char* p = crow + 3 * x;
          p[0] = flat[0];
          p[1] = flat[1];
          p[2] = flat[2];
        }
      }
    }
  }
}

// Camera-space vertex for clipping.
struct CVert {
  float x, y, z, nx, ny, nz;
};

// Sutherland-Hodgman against the half-space a x + b y + c z + d >= 0. Returns the count.
int clip_polygon(const CVert* in, int n, CVert* out, float a, float b, float c, float d) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const CVert& p = in[i];
    const CVert& q = in[(i + 1) % n];
    const float dp = a * p.x + b * p.y + c * p.z + d;
    const float dq = a * q.x + b * q.y + c * q.z + d;
    if (dp >= 0) out[m++] = p;
    if ((dp >= 0) != (dq >= 0)) {
      const float s = dp / (dp - dq);
      out[m++] = {p.x + (q.x - p.x) * s,    p.y + (q.y - p.y) * s,    p.z + (q.z - p.z) * s,
                  p.nx + (q.nx - p.nx) * s, p.ny + (q.ny - p.ny) * s, p.nz + (q.nz - p.nz) * s};
    }
  }
  return m;
}

// ---------------------------------------------------------------------------------
// 2-D anti-aliased overlay primitives on a BGR image (allocation free).

struct Canvas {
  unsigned char* data;
  std::size_t step;
  int W, H;
  void blend(int x, int y, const Rgbf& c, float a) const {
    if (a <= 0.0f) return;
    if (a > 1.0f) a = 1.0f;
    unsigned char* p = data + std::size_t(y) * step + 3 * std::size_t(x);
    p[0] = static_cast<unsigned char>(p[0] + (c.b - p[0]) * a + 0.5f);
    p[1] = static_cast<unsigned char>(p[1] + (c.g - p[1]) * a + 0.5f);
    p[2] = static_cast<unsigned char>(p[2] + (c.r - p[2]) * a + 0.5f);
  }
};

bool finite2(const Eigen::Vector2d& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }

// Capsule of half-width `half_px` around the segment p0-p1 (pixel coordinates).
void draw_segment(const Canvas& cn, Eigen::Vector2d p0, Eigen::Vector2d p1, double half_px, const Rgbf& col,
                  float alpha) {
  if (!finite2(p0) || !finite2(p1) || !(half_px > 0)) return;
  // Keep the coordinates sane: clip the segment to a generous box around the image.
  const double lim = 4.0 * (cn.W + cn.H);
  const Eigen::Vector2d dvec = p1 - p0;
  double t0 = 0, t1 = 1;
  for (int k = 0; k < 2; ++k) {
    const double lo = -lim, hi = (k == 0 ? cn.W : cn.H) + lim;
    const double p = p0[k], d = dvec[k];
    if (std::fabs(d) < 1e-12) {
      if (p < lo || p > hi) return;
      continue;
    }
    double a = (lo - p) / d, b = (hi - p) / d;
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  if (t0 > t1) return;
  const Eigen::Vector2d a = p0 + t0 * dvec, b = p0 + t1 * dvec;
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double R = half_px + 0.5;
  const int y_lo = std::max(0, static_cast<int>(std::floor(std::min(a.y(), b.y()) - R)));
  const int y_hi = std::min(cn.H - 1, static_cast<int>(std::ceil(std::max(a.y(), b.y()) + R)));
  for (int y = y_lo; y <= y_hi; ++y) {
    const double yc = y + 0.5;
    // Parameter range of the segment within R of this row, then its x range.
    double ta = 0, tb = 1;
    if (std::fabs(ab.y()) > 1e-9) {
      ta = (yc - R - a.y()) / ab.y();
      tb = (yc + R - a.y()) / ab.y();
      if (ta > tb) std::swap(ta, tb);
      ta = std::max(ta, 0.0);
      tb = std::min(tb, 1.0);
      if (ta > tb) continue;
    } else if (std::fabs(yc - a.y()) > R) {
      continue;
    }
    const double xa = a.x() + ta * ab.x(), xb = a.x() + tb * ab.x();
    const int x_lo = std::max(0, static_cast<int>(std::floor(std::min(xa, xb) - R)));
    const int x_hi = std::min(cn.W - 1, static_cast<int>(std::ceil(std::max(xa, xb) + R)));
    for (int x = x_lo; x <= x_hi; ++x) {
      const Eigen::Vector2d p(x + 0.5, yc);
      double s = len2 > 0 ? (p - a).dot(ab) / len2 : 0.0;
      s = std::clamp(s, 0.0, 1.0);
      const double dist = (p - (a + s * ab)).norm();
      cn.blend(x, y, col, alpha * clamp01(static_cast<float>(R - dist)));
    }
  }
}

// Ring of radius r_px and half-width half_px (fill = true: a disc of radius r_px).
void draw_ring(const Canvas& cn, const Eigen::Vector2d& c, double r_px, double half_px, const Rgbf& col, float alpha,
               bool fill = false) {
  if (!finite2(c) || std::fabs(c.x()) > 1e6 || std::fabs(c.y()) > 1e6 || !(r_px < 1e6)) return;
  const double R = r_px + half_px + 1.0;
  const int y_lo = std::max(0, static_cast<int>(std::floor(c.y() - R)));
  const int y_hi = std::min(cn.H - 1, static_cast<int>(std::ceil(c.y() + R)));
  const int x_lo = std::max(0, static_cast<int>(std::floor(c.x() - R)));
  const int x_hi = std::min(cn.W - 1, static_cast<int>(std::ceil(c.x() + R)));
  for (int y = y_lo; y <= y_hi; ++y)
    for (int x = x_lo; x <= x_hi; ++x) {
      const double d = std::hypot(x + 0.5 - c.x(), y + 0.5 - c.y());
      const double cover = fill ? r_px + 0.5 - d : half_px + 0.5 - std::fabs(d - r_px);
      cn.blend(x, y, col, alpha * clamp01(static_cast<float>(cover)));
    }
}

// Filled triangle with anti-aliased edges.
void draw_triangle(const Canvas& cn, const Eigen::Vector2d& p0, const Eigen::Vector2d& p1, const Eigen::Vector2d& p2,
                   const Rgbf& col, float alpha) {
  if (!finite2(p0) || !finite2(p1) || !finite2(p2)) return;
  const Eigen::Vector2d P[3] = {p0, p1, p2};
  const double area = (p1 - p0).x() * (p2 - p0).y() - (p1 - p0).y() * (p2 - p0).x();
  if (std::fabs(area) < 1e-9) return;
  const double sgn = area > 0 ? 1.0 : -1.0;
  Eigen::Vector2d nrm[3];
  double off[3];
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector2d e = P[(i + 1) % 3] - P[i];
    nrm[i] = sgn * Eigen::Vector2d(-e.y(), e.x()).normalized();  // inward
    off[i] = -nrm[i].dot(P[i]);
  }
  const double lim = 4.0 * (cn.W + cn.H);
  const int y_lo = std::max(0, static_cast<int>(std::floor(std::max(-lim, std::min({p0.y(), p1.y(), p2.y()}) - 1))));
  const int y_hi =
      std::min(cn.H - 1, static_cast<int>(std::ceil(std::min(lim, std::max({p0.y(), p1.y(), p2.y()}) + 1))));
  const int x_lo = std::max(0, static_cast<int>(std::floor(std::max(-lim, std::min({p0.x(), p1.x(), p2.x()}) - 1))));
  const int x_hi =
      std::min(cn.W - 1, static_cast<int>(std::ceil(std::min(lim, std::max({p0.x(), p1.x(), p2.x()}) + 1))));
  for (int y = y_lo; y <= y_hi; ++y)
    for (int x = x_lo; x <= x_hi; ++x) {
      const Eigen::Vector2d p(x + 0.5, y + 0.5);
      double d = std::numeric_limits<double>::infinity();
      for (int i = 0; i < 3; ++i) d = std::min(d, nrm[i].dot(p) + off[i]);
      cn.blend(x, y, col, alpha * clamp01(static_cast<float>(d + 0.5)));
    }
}

// Clips the world segment a-b to the camera's near plane and projects it.
bool project_segment(const Camera& cam, const Eigen::Isometry3d& X_CW, double f, const Eigen::Vector3d& a_W,
                     const Eigen::Vector3d& b_W, Eigen::Vector2d& pa, Eigen::Vector2d& pb) {
  Eigen::Vector3d a = X_CW * a_W, b = X_CW * b_W;
  const double n = cam.near_m;
  if (a.z() < n && b.z() < n) return false;
  if (a.z() < n) a = a + (b - a) * ((n - a.z()) / (b.z() - a.z()));
  if (b.z() < n) b = b + (a - b) * ((n - b.z()) / (a.z() - b.z()));
  const double cx = 0.5 * cam.width_px, cy = 0.5 * cam.height_px;
  pa = {cx + f * a.x() / a.z(), cy + f * a.y() / a.z()};
  pb = {cx + f * b.x() / b.z(), cy + f * b.y() / b.z()};
  return finite2(pa) && finite2(pb);
}

// The segment a-b drawn solid (on_px <= 0) or dashed: phase_px is the distance along
// the dash pattern (on_px drawn, off_px skipped) at a, and comes back advanced by the
// segment's length, so that a polyline's dashes run on across its vertices. Only the
// part of the segment near the image is walked (a segment clipped at the near plane
// can reach far outside it).
void draw_stroke(const Canvas& cn, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double half_px, const Rgbf& col,
                 float alpha, double on_px, double off_px, double& phase_px) {
  if (!finite2(a) || !finite2(b)) return;
  const double len = (b - a).norm();
  if (!(len > 0)) return;
  if (!(on_px > 0)) {
    draw_segment(cn, a, b, half_px, col, alpha);
    return;
  }
  // Parameter range [t0, t1] of the segment inside the image grown by the pen's reach.
  const double m = half_px + 2.0;
  const Eigen::Vector2d d = b - a;
  double t0 = 0, t1 = 1;
  for (int k = 0; k < 2; ++k) {
    const double lo = -m, hi = (k == 0 ? cn.W : cn.H) + m;
    if (std::fabs(d[k]) < 1e-12) {
      if (a[k] < lo || a[k] > hi) t1 = -1;
      continue;
    }
    double u = (lo - a[k]) / d[k], v = (hi - a[k]) / d[k];
    if (u > v) std::swap(u, v);
    t0 = std::max(t0, u);
    t1 = std::min(t1, v);
  }
  const double period = on_px + std::max(0.0, off_px);
  if (t0 >= t1) {
    phase_px = std::fmod(phase_px + len, period);
    return;
  }
  const Eigen::Vector2d dir = d / len;
  double s = t0 * len;
  phase_px = std::fmod(phase_px + s, period);
  const double end = t1 * len;
  while (s < end) {
    const double ph = std::fmod(phase_px, period);
    const double e = std::min(end, s + (ph < on_px ? on_px - ph : period - ph));
    if (ph < on_px) draw_segment(cn, a + dir * s, a + dir * e, half_px, col, alpha);
    phase_px = std::fmod(phase_px + (e - s), period);
    s = e;
  }
  phase_px = std::fmod(phase_px + (len - end), period);
}

}  // namespace

// ---------------------------------------------------------------------------------
// Camera.

void validate(const Camera& c) {
  const auto finite = [](const Eigen::Vector3d& v) { return v.allFinite(); };
  if (c.width_px < 1 || c.height_px < 1)
    throw std::invalid_argument("viz::Camera: image size " + std::to_string(c.width_px) + "x" +
                                std::to_string(c.height_px) + " px, expected at least 1x1");
  if (!(c.fov_y_deg > 0 && c.fov_y_deg < 180))
    throw std::invalid_argument("viz::Camera: fov_y_deg " + std::to_string(c.fov_y_deg) + ", expected in (0, 180)");
  if (!(c.near_m > 0) || !std::isfinite(c.near_m))
    throw std::invalid_argument("viz::Camera: near_m " + std::to_string(c.near_m) + ", expected finite and > 0");
  if (!finite(c.position) || !finite(c.look_at) || !finite(c.up))
    throw std::invalid_argument("viz::Camera: position, look_at and up must be finite");
  const Eigen::Vector3d fwd = c.look_at - c.position;
  if (!(fwd.norm() > 1e-9)) throw std::invalid_argument("viz::Camera: position and look_at coincide");
  if (!(fwd.normalized().cross(c.up).norm() > 1e-9 * c.up.norm()) || !(c.up.norm() > 0))
    throw std::invalid_argument("viz::Camera: up is zero or parallel to the view direction");
}

double focal_length_px(const Camera& c) { return 0.5 * c.height_px / std::tan(0.5 * c.fov_y_deg * M_PI / 180.0); }

Eigen::Isometry3d camera_from_world(const Camera& c) {
  const Eigen::Vector3d z = (c.look_at - c.position).normalized();
  const Eigen::Vector3d x = z.cross(c.up).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Isometry3d X_WC = Eigen::Isometry3d::Identity();
  X_WC.linear().col(0) = x;
  X_WC.linear().col(1) = y;
  X_WC.linear().col(2) = z;
  X_WC.translation() = c.position;
  return X_WC.inverse();
}

std::optional<Eigen::Vector2d> project(const Camera& c, const Eigen::Vector3d& p_W) {
  const Eigen::Vector3d p_C = camera_from_world(c) * p_W;
  if (!(p_C.z() >= c.near_m)) return std::nullopt;
  const double f = focal_length_px(c);
  return Eigen::Vector2d(0.5 * c.width_px + f * p_C.x() / p_C.z(), 0.5 * c.height_px + f * p_C.y() / p_C.z());
}

// ---------------------------------------------------------------------------------
// Scene.

std::size_t Scene::triangle_count() const {
  std::size_t n = 0;
  for (const auto& b : bodies)
    for (const auto& m : b.meshes) n += m.triangles.size();
  return n;
}

std::size_t Scene::vertex_count() const {
  std::size_t n = 0;
  for (const auto& b : bodies)
    for (const auto& m : b.meshes) n += m.vertices.size();
  return n;
}

Eigen::AlignedBox3d scene_bounds(const Scene& scene, const std::vector<Eigen::Isometry3d>& X_WB) {
  if (X_WB.size() != scene.bodies.size())
    throw std::invalid_argument("viz::scene_bounds: " + std::to_string(X_WB.size()) + " poses for " +
                                std::to_string(scene.bodies.size()) + " bodies");
  Eigen::AlignedBox3d box;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b)
    for (const auto& m : scene.bodies[b].meshes)
      for (const auto& v : m.vertices) box.extend(X_WB[b] * v.cast<double>());
  return box;
}

double place_on_ground(const Scene& scene, std::vector<Eigen::Isometry3d>& X_WB) {
  const Eigen::AlignedBox3d box = scene_bounds(scene, X_WB);
  if (box.isEmpty()) return 0;
  const double dz = -box.min().z();
  for (auto& X : X_WB) X.translation().z() += dz;
  return dz;
}

// ---------------------------------------------------------------------------------
// Renderer: construction and scene preparation.

Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) = default;
Renderer& Renderer::operator=(Renderer&&) = default;

namespace {

int default_thread_count() {
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 2 : static_cast<int>(std::min(2u, n));
}

}  // namespace

Renderer::Renderer(int width_px, int height_px, int threads) : width_(width_px), height_(height_px) {
  if (width_px < 16 || height_px < 16 || width_px > 16384 || height_px > 16384)
    throw std::invalid_argument("viz::Renderer: image size " + std::to_string(width_px) + "x" +
                                std::to_string(height_px) + " px, expected each in [16, 16384]");
  if (threads < 0 || threads > kMaxThreads)
    throw std::invalid_argument("viz::Renderer: " + std::to_string(threads) + " threads, expected 0 (default) to " +
                                std::to_string(kMaxThreads));
  threads_ = threads == 0 ? default_thread_count() : threads;
  image_.create(height_, width_, CV_8UC3);
  inv_depth_.create(height_, width_, CV_32F);
  ids_.create(height_, width_, CV_16S);
  image_.setTo(cv::Scalar::all(0));
  inv_depth_.setTo(cv::Scalar::all(0));
  ids_.setTo(cv::Scalar::all(-1));
  shadow_n_ = kShadowN;
  sky_lut_.assign(3 * kSkyN, 0);
  row_.assign(std::size_t(threads_) * kRowArrays * (std::size_t(width_) + 4), 0.0f);
  shadow_.assign(std::size_t(kShadowN) * kShadowN, 0.0f);
  shadow_tmp_.assign(std::size_t(kShadowN) * kShadowN, 0.0f);
  linear_to_srgb_.resize(kLutN);
  for (int i = 0; i < kLutN; ++i)
    linear_to_srgb_[i] = static_cast<unsigned char>(std::lround(255.0 * linear_to_srgb(double(i) / double(kLutN - 1))));

  // Glyph cache for the text overlay: each printable ASCII character rendered once by
  // OpenCV's Hershey font into an anti-aliased mask, then blended per frame by hand
  // (cv::putText allocates, render() must not).
  const double scale = std::clamp(0.55 * height_ / 720.0, 0.35, 3.0);
  const int thickness = std::max(1, static_cast<int>(std::lround(height_ / 720.0)));
  int baseline = 0;
  const cv::Size ref = cv::getTextSize("Ag", cv::FONT_HERSHEY_SIMPLEX, scale, thickness, &baseline);
  text_ascent_px_ = ref.height;
  text_line_px_ = ref.height + baseline + std::max(4, ref.height / 2);
  for (int ch = 32; ch < 127; ++ch) {
    Glyph& g = glyphs_[ch - 32];
    const std::string s(1, static_cast<char>(ch));
    int base = 0;
    const cv::Size sz = cv::getTextSize(s, cv::FONT_HERSHEY_SIMPLEX, scale, thickness, &base);
    const int m = thickness + 2;
    g.advance = sz.width;
    g.coverage = cv::Mat::zeros(ref.height + baseline + 2 * m, sz.width + 2 * m, CV_8U);
    cv::putText(g.coverage, s, cv::Point(m, m + ref.height), cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(255),
                thickness, cv::LINE_AA);
    g.x0 = -m;
    g.y0 = -(m + ref.height);
  }
  if (threads_ > 1) workers_ = std::make_unique<Workers>(threads_ - 1);
}

std::size_t Renderer::closed_mesh_count() const {
  std::size_t n = 0;
  for (const auto& m : meshes_) n += m.cull ? 1 : 0;
  return n;
}

namespace {

// Closed and consistently wound outward: with vertices welded by exact position, every
// directed edge appears once and its reverse once (degenerate triangles ignored), and
// the enclosed volume is positive.
bool closed_outward(const SceneMesh& m) {
  if (m.triangles.empty()) return false;
  struct KeyHash {
    std::size_t operator()(const std::array<std::uint32_t, 3>& k) const {
      std::uint64_t h = 1469598103934665603ull;
      for (auto v : k) h = (h ^ v) * 1099511628211ull;
      return static_cast<std::size_t>(h);
    }
  };
  std::unordered_map<std::array<std::uint32_t, 3>, int, KeyHash> weld;
  std::vector<int> id(m.vertices.size());
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    std::array<std::uint32_t, 3> k{};
    for (int c = 0; c < 3; ++c) {
      float v = m.vertices[i][c];
      if (v == 0.0f) v = 0.0f;  // -0 == +0
      std::memcpy(&k[c], &v, sizeof v);
    }
    id[i] = weld.emplace(k, static_cast<int>(weld.size())).first->second;
  }
  std::unordered_map<std::uint64_t, int> edges;
  double volume6 = 0;
  for (const auto& t : m.triangles) {
    const int a = id[t[0]], b = id[t[1]], c = id[t[2]];
    if (a == b || b == c || c == a) continue;
    for (const auto& e : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}})
      ++edges[(std::uint64_t(std::uint32_t(e.first)) << 32) | std::uint32_t(e.second)];
    const Eigen::Vector3d p0 = m.vertices[t[0]].cast<double>(), p1 = m.vertices[t[1]].cast<double>(),
                          p2 = m.vertices[t[2]].cast<double>();
    volume6 += p0.dot(p1.cross(p2));
  }
  if (edges.empty()) return false;
  for (const auto& [key, count] : edges) {
    if (count != 1) return false;
    const std::uint64_t rev = (key << 32) | (key >> 32);
    const auto it = edges.find(rev);
    if (it == edges.end() || it->second != 1) return false;
  }
  return volume6 > 0;
}

}  // namespace

void Renderer::set_scene(const Scene& scene) {
  std::vector<PreparedMesh> meshes;
  std::vector<std::size_t> bodies;
  std::size_t tris = 0, max_vertices = 0;
  if (scene.bodies.size() > 32767) throw std::invalid_argument("viz::Renderer::set_scene: more than 32767 bodies");
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    bodies.push_back(meshes.size());
    const SceneBody& body = scene.bodies[b];
    for (std::size_t k = 0; k < body.meshes.size(); ++k) {
      const SceneMesh& m = body.meshes[k];
      const auto where = [&] {
        return "viz::Renderer::set_scene: body " + std::to_string(b) + " '" + body.name + "' mesh " +
               std::to_string(k) + ": ";
      };
      if (!m.normals.empty() && m.normals.size() != m.vertices.size())
        throw std::invalid_argument(where() + std::to_string(m.normals.size()) + " normals for " +
                                    std::to_string(m.vertices.size()) + " vertices (expected as many, or none)");
      for (const auto& v : m.vertices)
        if (!v.allFinite()) throw std::invalid_argument(where() + "a vertex is not finite");
      const int nv = static_cast<int>(m.vertices.size());
      for (const auto& t : m.triangles)
        for (int i : t)
          if (i < 0 || i >= nv)
            throw std::invalid_argument(where() + "triangle index " + std::to_string(i) + " out of range [0, " +
                                        std::to_string(nv) + ")");
      PreparedMesh p;
      p.body = static_cast<int>(b);
      p.pos = m.vertices;
      p.tri = m.triangles;
      if (!m.normals.empty()) {
        p.nrm.resize(m.normals.size());
        for (std::size_t i = 0; i < m.normals.size(); ++i) {
          const float len = m.normals[i].allFinite() ? m.normals[i].norm() : 0.0f;
          p.nrm[i] = len > 0 ? Eigen::Vector3f(m.normals[i] / len) : Eigen::Vector3f::Zero();
        }
      }
      for (int c = 0; c < 3; ++c)
        p.albedo[c] = static_cast<float>(srgb_to_linear(std::clamp(double(m.rgba[c]), 0.0, 1.0)));
      p.visible = !(m.rgba[3] <= 0.0f) && !m.triangles.empty() && !m.vertices.empty();
      p.cull = m.faces == SceneMesh::Faces::Auto && closed_outward(m);
      if (!m.vertices.empty()) {
        Eigen::AlignedBox3f box;
        for (const auto& v : m.vertices) box.extend(v);
        p.centre = box.center();
        for (const auto& v : m.vertices) p.radius = std::max(p.radius, (v - p.centre).norm());
        p.radius *= 1.0001f;
        p.radius += 1e-6f;
      }
      tris += m.triangles.size();
      max_vertices = std::max(max_vertices, m.vertices.size());
      meshes.push_back(std::move(p));
    }
  }
  bodies.push_back(meshes.size());
  meshes_ = std::move(meshes);
  bodies_ = std::move(bodies);
  triangle_count_ = tris;
  scratch_.assign(max_vertices * std::size_t(threads_), Vertex{});
  scratch_stride_ = max_vertices;
}

// ---------------------------------------------------------------------------------
// Rendering.

const cv::Mat& Renderer::render(const std::vector<Eigen::Isometry3d>& X_WB, const Camera& camera,
                                const Overlays& overlays) {
  validate(camera);
  if (camera.width_px != width_ || camera.height_px != height_)
    throw std::invalid_argument("viz::Renderer::render: the camera is " + std::to_string(camera.width_px) + "x" +
                                std::to_string(camera.height_px) + " px but the renderer is " + std::to_string(width_) +
                                "x" + std::to_string(height_) + " px");
  if (X_WB.size() != body_count())
    throw std::invalid_argument("viz::Renderer::render: " + std::to_string(X_WB.size()) + " body poses for " +
                                std::to_string(body_count()) + " bodies");
  stats_ = Stats{};
  if (cached_image_.empty()) {  // the kept background's buffers (draw_background_and_ground)
    cached_image_.create(height_, width_, CV_8UC3);
    cached_inv_depth_.create(height_, width_, CV_32F);
  }
  const Eigen::Isometry3d X_CW = camera_from_world(camera);
  const Eigen::Isometry3d X_WC = X_CW.inverse();
  if (style_.shadows && style_.ground && camera.position.z() > 0)
    build_shadow_map(X_WB);
  else
    shadow_valid_ = false;
  const BackgroundPlan plan = plan_background(camera, X_WC);
  const double f = focal_length_px(camera);
  // The background: chunks of kBandRows rows taken in turn from a shared counter, so
  // that a thread that falls behind (another process on its core) leaves its share to
  // the others. Then the meshes by bands, each its own rows.
  const int chunks = (height_ + kBandRows - 1) / kBandRows;
  std::atomic<int> next_chunk{0};
  auto background_job = [&](int thread) {
    for (int c = next_chunk.fetch_add(1, std::memory_order_relaxed); c < chunks;
         c = next_chunk.fetch_add(1, std::memory_order_relaxed))
      draw_background_and_ground(camera, X_WC, plan, c * kBandRows, std::min(height_, (c + 1) * kBandRows), thread);
  };
  auto mesh_job = [&](int b) {
    Stats band_stats;  // the counts are per triangle, the same in every band: band 0's
    draw_meshes(X_WB, X_CW, f, camera.near_m, RowBand{b, threads_}, b == 0 ? stats_ : band_stats);
  };
  if (workers_) {  // each run() returns when all threads are done: the meshes follow the background
    workers_->run(background_job);
    workers_->run(mesh_job);
  } else {  // one thread (or a moved-from renderer's: the bands one after the other)
    background_job(0);
    for (int b = 0; b < threads_; ++b) mesh_job(b);
  }
  draw_overlays(camera, overlays);
  return image_;
}

namespace {

// Sets to 1 the texels of the N x N map whose centres (i + 0.5, j + 0.5) the triangle
// p = (x0, y0, x1, y1, x2, y2) covers (sgn: the sign of its area, so the edge functions
// are >= 0 inside). Four texels at a time, each with the float operations of one at a
// time (so the same texels; a lane's result does not depend on the others).
void cover_texels(const std::array<float, 6>& p, float sgn, float* map, int N) {
  const int i_lo = std::max(0, static_cast<int>(std::ceil(std::min({p[0], p[2], p[4]}) - 0.5f)));
  const int i_hi = std::min(N - 1, static_cast<int>(std::floor(std::max({p[0], p[2], p[4]}) - 0.5f)));
  const int j_lo = std::max(0, static_cast<int>(std::ceil(std::min({p[1], p[3], p[5]}) - 0.5f)));
  const int j_hi = std::min(N - 1, static_cast<int>(std::floor(std::max({p[1], p[3], p[5]}) - 0.5f)));
  // Edge k from vertex k to k + 1: e_k = sgn ((x_{k+1} - x_k) (y - y_k) - (y_{k+1} - y_k) (x - x_k)).
  float dx[3], dy[3];
  for (int k = 0; k < 3; ++k) {
    const int n = (k + 1) % 3;
    dx[k] = p[2 * n] - p[2 * k];
    dy[k] = p[2 * n + 1] - p[2 * k + 1];
  }
  const v4f lane{0.0f, 1.0f, 2.0f, 3.0f}, zero = vset(0.0f), vsgn = vset(sgn);
  for (int j = j_lo; j <= j_hi; ++j) {
    const float y = j + 0.5f;
    float* row = map + std::size_t(j) * N;
    float ky[3];  // the y terms, the same for the whole row
    for (int k = 0; k < 3; ++k) ky[k] = dx[k] * (y - p[2 * k + 1]);
    int i = i_lo;
    for (; i + 3 <= i_hi; i += 4) {
      const v4f x = vset(float(i)) + lane + vset(0.5f);
      v4i in = vset(0.0f) == zero;  // all lanes set
      for (int k = 0; k < 3; ++k) in &= vsgn * (vset(ky[k]) - vset(dy[k]) * (x - vset(p[2 * k]))) >= zero;
      v4f old;
      std::memcpy(&old, row + i, sizeof old);
      const v4i covered = (in & reinterpret_cast<v4i>(vset(1.0f))) | (~in & reinterpret_cast<v4i>(old));
      std::memcpy(row + i, &covered, sizeof covered);
    }
    for (; i <= i_hi; ++i) {
      const float x = i + 0.5f;
      bool in = true;
      for (int k = 0; k < 3; ++k) in = in && sgn * (ky[k] - dy[k] * (x - p[2 * k])) >= 0;
      if (in) row[i] = 1.0f;
    }
  }
}

// Box blur of radius rb (clipped at the ends) along each row of the N x N map `in`,
// times inv, into `out`: a running sum along the row. Eight rows at a time: each sum
// takes the same additions in the same order as alone, but eight independent sums
// keep the adder busy where one is a chain of dependent additions.
template <int kRows>
void blur_row_group(const float* in, float* out, int N, int rb, float inv) {
  float sum[kRows] = {};
  for (int i = 0; i < std::min(rb, N); ++i)
    for (int k = 0; k < kRows; ++k) sum[k] += in[std::size_t(k) * N + i];
  for (int i = 0; i < N; ++i) {
    if (i + rb < N)
      for (int k = 0; k < kRows; ++k) sum[k] += in[std::size_t(k) * N + i + rb];
    if (i - rb - 1 >= 0)
      for (int k = 0; k < kRows; ++k) sum[k] -= in[std::size_t(k) * N + i - rb - 1];
    for (int k = 0; k < kRows; ++k) out[std::size_t(k) * N + i] = sum[k] * inv;
  }
}
void blur_rows(const float* in, float* out, int N, int rb, float inv) {
  int j = 0;
  for (; j + 8 <= N; j += 8) blur_row_group<8>(in + std::size_t(j) * N, out + std::size_t(j) * N, N, rb, inv);
  for (; j < N; ++j) blur_row_group<1>(in + std::size_t(j) * N, out + std::size_t(j) * N, N, rb, inv);
}

// The same along each column: the running sums of all columns advance a row at a time
// (whole rows: contiguous, vectorised), each column's in the order of one alone.
void blur_columns(const float* in, float* out, int N, int rb, float inv) {
  std::array<float, kShadowN> sum{};
  for (int j = 0; j < std::min(rb, N); ++j)
    for (int i = 0; i < N; ++i) sum[i] += in[std::size_t(j) * N + i];
  for (int j = 0; j < N; ++j) {
    if (j + rb < N)
      for (int i = 0; i < N; ++i) sum[i] += in[std::size_t(j + rb) * N + i];
    if (j - rb - 1 >= 0)
      for (int i = 0; i < N; ++i) sum[i] -= in[std::size_t(j - rb - 1) * N + i];
    for (int i = 0; i < N; ++i) out[std::size_t(j) * N + i] = sum[i] * inv;
  }
}

}  // namespace

void Renderer::build_shadow_map(const std::vector<Eigen::Isometry3d>& X_WB) {
  shadow_valid_ = false;
  Eigen::Vector3d l = style_.light_from_W;
  if (!l.allFinite() || !(l.norm() > 0)) return;
  l.normalize();
  if (l.z() < 0.05) return;  // light at the horizon: shadows would be unbounded
  const double kx = l.x() / l.z(), ky = l.y() / l.z();

  // Extent: the bounding spheres' shadows (an ellipse within r / l_z of the centre's).
  double x_min = 1e300, x_max = -1e300, y_min = 1e300, y_max = -1e300;
  for (const auto& m : meshes_) {
    if (!m.visible) continue;
    const Eigen::Vector3d c = X_WB[m.body] * m.centre.cast<double>();
    if (!c.allFinite()) continue;
    const double qx = c.x() - c.z() * kx, qy = c.y() - c.z() * ky, r = m.radius / l.z();
    x_min = std::min(x_min, qx - r);
    x_max = std::max(x_max, qx + r);
    y_min = std::min(y_min, qy - r);
    y_max = std::max(y_max, qy + r);
  }
  if (x_min > x_max) return;
  const double soft = std::max(0.0, style_.shadow_softness_m);
  const double extent = std::max(x_max - x_min, y_max - y_min) + 6 * soft;
  if (!(extent > 0) || extent > 1e4) return;
  const int N = shadow_n_;
  const double texel = extent / (N - 4);
  shadow_texel_m_ = texel;
  shadow_x0_ = 0.5 * (x_min + x_max) - 0.5 * N * texel;
  shadow_y0_ = 0.5 * (y_min + y_max) - 0.5 * N * texel;
  std::fill(shadow_.begin(), shadow_.end(), 0.0f);

  // Each mesh's triangles projected along the light onto z = 0, in texel units
  // (texel (i, j) centred at u = i + 0.5, v = j + 0.5). For closed meshes the triangles
  // facing the light cover the whole shadow (their projection is counter-clockwise).
  for (const auto& m : meshes_) {
    if (!m.visible) continue;
    const Eigen::Isometry3d& X = X_WB[m.body];
    const Eigen::Matrix3d& R = X.linear();
    const Eigen::Vector3d& p = X.translation();
    float M[2][3], o[2];
    for (int c = 0; c < 3; ++c) {
      M[0][c] = static_cast<float>((R(0, c) - kx * R(2, c)) / texel);
      M[1][c] = static_cast<float>((R(1, c) - ky * R(2, c)) / texel);
    }
    o[0] = static_cast<float>((p.x() - kx * p.z() - shadow_x0_) / texel);
    o[1] = static_cast<float>((p.y() - ky * p.z() - shadow_y0_) / texel);
    for (std::size_t i = 0; i < m.pos.size(); ++i) {
      const Eigen::Vector3f& v = m.pos[i];
      scratch_[i].sx = M[0][0] * v.x() + M[0][1] * v.y() + M[0][2] * v.z() + o[0];
      scratch_[i].sy = M[1][0] * v.x() + M[1][1] * v.y() + M[1][2] * v.z() + o[1];
    }
    for (const auto& t : m.tri) {
      const Vertex& a = scratch_[t[0]];
      const Vertex& b = scratch_[t[1]];
      const Vertex& c = scratch_[t[2]];
      float area = (b.sx - a.sx) * (c.sy - a.sy) - (b.sy - a.sy) * (c.sx - a.sx);
      if (m.cull && area <= 0) continue;
      if (area == 0 || !std::isfinite(area)) continue;
      const float sgn = area > 0 ? 1.0f : -1.0f;
      cover_texels({a.sx, a.sy, b.sx, b.sy, c.sx, c.sy}, sgn, shadow_.data(), N);
    }
  }

  // Soften: two separable box blurs (close to a Gaussian of sigma ~ softness).
  const int rb = std::max(1, static_cast<int>(std::lround(soft / texel / 1.2)));
  const float inv = 1.0f / float(2 * rb + 1);
  for (int pass = 0; pass < 2; ++pass) {
    blur_rows(shadow_.data(), shadow_tmp_.data(), N, rb, inv);
    blur_columns(shadow_tmp_.data(), shadow_.data(), N, rb, inv);
  }
  shadow_valid_ = true;
}

namespace {

struct PixelBox {
  bool seen = true;
  int r_lo = 0, r_hi = -1, c_lo = 0, c_hi = -1;
};

// Where the square [x0, x0 + ext] x [y0, y0 + ext] on the ground (the shadow map) may
// be seen: the box of its corners' projections with two pixels' margin, clamped to the
// image; the whole image when a corner is not in front of the camera; not seen when
// the box is off the image.
PixelBox ground_square_on_image(const Camera& camera, const Eigen::Isometry3d& X_CW, double x0, double y0,
                                double ext) {
  const int W = camera.width_px, H = camera.height_px;
  const double f = focal_length_px(camera), cx = 0.5 * W, cy = 0.5 * H;
  double u_min = 1e300, u_max = -1e300, v_min = 1e300, v_max = -1e300;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d p_C = X_CW * Eigen::Vector3d(x0 + (k & 1) * ext, y0 + (k >> 1) * ext, 0.0);
    if (!(p_C.z() > 1e-3)) return PixelBox{true, 0, H - 1, 0, W - 1};
    const double u = cx + f * p_C.x() / p_C.z(), v = cy + f * p_C.y() / p_C.z();
    u_min = std::min(u_min, u), u_max = std::max(u_max, u), v_min = std::min(v_min, v), v_max = std::max(v_max, v);
  }
  if (u_max < -2 || u_min > W + 2 || v_max < -2 || v_min > H + 2) return PixelBox{false};
  return PixelBox{true, static_cast<int>(std::clamp(std::floor(v_min) - 2, 0.0, double(H - 1))),
                  static_cast<int>(std::clamp(std::ceil(v_max) + 2, 0.0, double(H - 1))),
                  static_cast<int>(std::clamp(std::floor(u_min) - 2, 0.0, double(W - 1))),
                  static_cast<int>(std::clamp(std::ceil(u_max) + 2, 0.0, double(W - 1)))};
}

}  // namespace

// The sky table, and whether the background of the last frame's camera can be kept.
//
// The background of a camera seen twice in a row (the frames of a run) is kept: the
// second frame draws it without the shadow into the cache, and every frame from then
// on copies it and draws again only the ground that may be on the shadow map: the
// segments whose hit points may be on it, in the rows and columns of the map's
// projection (its corners on the ground projected; all of them when one is behind
// the camera). A segment off the map is the same with or without the shadow, so the
// image is the same as drawing every pixel.
Renderer::BackgroundPlan Renderer::plan_background(const Camera& camera, const Eigen::Isometry3d& X_WC) {
  // Sky colours by the sine of the elevation in [-1, 1]: horizon -> zenith above,
  // horizon -> floor colour below (seen only without the ground).
  const Rgbf zenith = rgbf(style_.sky_zenith), horizon = rgbf(style_.sky_horizon), floor_c = rgbf(style_.floor_color);
  for (int i = 0; i < kSkyN; ++i) {
    const float e = -1.0f + 2.0f * float(i) / float(kSkyN - 1);
    Rgbf col;
    if (e >= 0) {
      const float w = clamp01(e / 0.75f);
      col = lerp(horizon, zenith, w * (2.0f - w));
    } else {
      col = lerp(horizon, floor_c, clamp01(-e / 0.35f));
    }
    put_bgr(sky_lut_.data() + 3 * i, col);
  }

  std::array<double, kBackgroundKeyN> key{};
  {
    std::size_t i = 0;
    const auto put = [&](double v) {
      if (i < key.size()) key[i++] = v;
    };
    const auto put3 = [&](const Eigen::Vector3d& v) { put(v.x()), put(v.y()), put(v.z()); };
    const auto put_color = [&](const Color& c) { put(c.r), put(c.g), put(c.b); };
    put3(camera.position), put3(camera.look_at), put3(camera.up), put(camera.fov_y_deg);
    put(camera.width_px), put(camera.height_px);
    put(style_.ground), put(style_.grid), put(style_.axes), put(style_.grid_minor_m), put(style_.grid_major_m);
    put(style_.ground_fade_start_m), put(style_.ground_fade_end_m);
    put_color(style_.ground_color), put_color(style_.grid_minor_color), put_color(style_.grid_major_color);
    put_color(style_.axis_x_color), put_color(style_.axis_y_color);
    put_color(style_.sky_zenith), put_color(style_.sky_horizon), put_color(style_.floor_color);
  }
  const bool same = background_seen_ && key == background_key_;
  background_key_ = key;
  background_seen_ = true;
  BackgroundPlan plan;
  if (!same) {
    background_cached_ = false;
    return plan;  // kDraw
  }
  plan.mode = background_cached_ ? BackgroundPlan::kFromKept : BackgroundPlan::kDrawAndKeep;
  background_cached_ = true;
  if (!shadow_valid_) return plan;
  const PixelBox box = ground_square_on_image(camera, X_WC.inverse(), shadow_x0_, shadow_y0_, shadow_texel_m_ * shadow_n_);
  plan.shaded = box.seen;
  plan.r_lo = box.r_lo, plan.r_hi = box.r_hi, plan.c_lo = box.c_lo, plan.c_hi = box.c_hi;
  return plan;
}

void Renderer::draw_background_and_ground(const Camera& camera, const Eigen::Isometry3d& X_WC,
                                          const BackgroundPlan& plan, int r_begin, int r_end, int thread) {
  // Per row, the view rays d(c) = d0 + c du (world axes, camera-z component 1) hit the
  // ground (d_z < 0) on one contiguous run of columns, since d_z is affine in c. The sky
  // is a table lookup by the ray's elevation; the ground is computed four pixels at a
  // time (GCC/Clang vector extensions: SSE on x86-64, NEON on ARM) in one pass, only
  // the terms a segment of the run can need (below), and packed to bytes.
  const double f = focal_length_px(camera);
  const double cx = 0.5 * width_, cy = 0.5 * height_;
  const Eigen::Matrix3d R = X_WC.linear();
  const Eigen::Vector3d C = X_WC.translation();
  const Eigen::Vector3f du = (R.col(0) / f).cast<float>();
  const Eigen::Vector3f dv = (R.col(1) / f).cast<float>();
  const Eigen::Vector3f d00 = (R * Eigen::Vector3d((0.5 - cx) / f, (0.5 - cy) / f, 1.0)).cast<float>();
  const bool ground = style_.ground && C.z() > 1e-6;
  const int W = width_;

  const Rgbf horizon = rgbf(style_.sky_horizon);  // the fade's colour (the sky table is plan_background's)
  const Rgbf ground_c = rgbf(style_.ground_color), minor_c = rgbf(style_.grid_minor_color),
             major_c = rgbf(style_.grid_major_color), ax_x = rgbf(style_.axis_x_color),
             ax_y = rgbf(style_.axis_y_color);
  const float g1 = static_cast<float>(std::max(1e-6, style_.grid_minor_m));
  const float g2 = static_cast<float>(std::max(1e-6, style_.grid_major_m));
  const float fade0 = static_cast<float>(style_.ground_fade_start_m);
  const float fade1 = static_cast<float>(std::max(style_.ground_fade_end_m, style_.ground_fade_start_m + 1e-3));
  const float shadow_k = static_cast<float>(std::clamp(style_.shadow_strength, 0.0, 1.0));
  const bool shadow = shadow_valid_;
  const int N = shadow_n_;
  const float sh_x0 = static_cast<float>(shadow_x0_), sh_y0 = static_cast<float>(shadow_y0_),
              sh_inv = static_cast<float>(1.0 / shadow_texel_m_);

  // Row buffer of W + 4 floats (whole vectors past the run's end are harmless): the
  // sky's table indices. One per thread.
  float* const ZB = row_.data() + std::size_t(thread) * kRowArrays * (std::size_t(W) + 4);

  // Constants as vectors.
  const v4f lane{0.0f, 1.0f, 2.0f, 3.0f};
  const v4f Cx = vset(static_cast<float>(C.x())), Cy = vset(static_cast<float>(C.y())),
            Cz = vset(static_cast<float>(C.z()));
  const v4f dux = vset(du.x()), duy = vset(du.y()), duz = vset(du.z());
  const v4f dvx = vset(dv.x()), dvy = vset(dv.y()), dvz = vset(dv.z());
  const v4f vg1 = vset(g1), vg2 = vset(g2), vig1 = vset(1.0f / g1), vig2 = vset(1.0f / g2);
  const v4f grid_on = vset(style_.grid ? 1.0f : 0.0f), axes_on = vset(style_.axes ? 1.0f : 0.0f);
  const v4f vfade0 = vset(fade0), vinv_fade = vset(1.0f / (fade1 - fade0));
  const v4f one = vset(1.0f), tiny = vset(1e-9f);
  const v4f vsh_x0 = vset(sh_x0), vsh_y0 = vset(sh_y0), vsh_inv = vset(sh_inv), vN1 = vset(float(N - 1));

  const bool grid = style_.grid, axes = style_.axes;
  // The segments' bounds (in the ground pass) in double.
  const double Cx_d = C.x(), Cy_d = C.y(), Cz_d = static_cast<float>(C.z());
  const double Dux = du.x(), Duy = du.y(), Duz = du.z(), Dvx = dv.x(), Dvy = dv.y(), Dvz = dv.z();
  // B | G << 8 | R << 16 per column (colours in [0, 255], rounded as the bytes are).
  const auto pack_bgr = [](v4f r, v4f g, v4f b) {
    return (__builtin_convertvector(b + vset(0.5f), v4i) & 255) | ((__builtin_convertvector(g + vset(0.5f), v4i) & 255) << 8) |
           ((__builtin_convertvector(r + vset(0.5f), v4i) & 255) << 16);
  };
  // The plain ground's bytes: no line, no shadow, no fade.
  const v4i plain = pack_bgr(vset(ground_c.r) * one, vset(ground_c.g) * one, vset(ground_c.b) * one);

  constexpr float kEps = 1e-6f;
  // One row. kAll: sky and ground; kShadedOnly: only the ground's segments that may be
  // on the shadow map, within columns [col_lo, col_hi] (the rest of the row is the
  // cached image's, drawn without shadow).
  // The mode and the shadow are template parameters (std::integral_constant), so each
  // of the three uses is compiled on its own with its branches folded.
  enum RowMode { kAll, kShadedOnly };
  const auto draw_row = [&](int r, auto mode_c, auto shadow_c, int col_lo, int col_hi) {
    constexpr RowMode mode = static_cast<RowMode>(decltype(mode_c)::value);
    constexpr bool shadow = decltype(shadow_c)::value;
    unsigned char* out = image_.ptr<unsigned char>(r);
    float* zrow = inv_depth_.ptr<float>(r);
    if (mode == kAll) {
      std::int16_t* idrow = ids_.ptr<std::int16_t>(r);
      std::fill(idrow, idrow + W, std::int16_t{-1});
    }
    const Eigen::Vector3f d0 = d00 + dv * float(r);
    const float dx0 = d0.x(), dy0 = d0.y(), dz0 = d0.z();

    // The ground run [g0, g1c]: d_z(c) < -eps holds on a prefix, a suffix, all or none.
    int g0 = 0, g1c = -1;
    if (ground) {
      const auto hits = [&](int c) { return dz0 + du.z() * float(c) < -kEps; };
      const bool first = hits(0), last = hits(W - 1);
      if (first && last) {
        g1c = W - 1;
      } else if (first || last) {
        int lo = 0, hi = W - 1;  // binary search for the switch, exact with the same predicate
        while (hi - lo > 1) {
          const int mid = (lo + hi) / 2;
          (hits(mid) == first ? lo : hi) = mid;
        }
        g0 = first ? 0 : hi;
        g1c = first ? lo : W - 1;
      }
    }

    // Sky on [0, g0) and (g1c, W): the table entry of the elevation sine of each ray,
    // four columns at a time.
    const auto sky = [&](int c_begin, int c_end) {
      const v4f scale = vset(0.5f * float(kSkyN - 1)), vdx = vset(dx0), vdy = vset(dy0), vdz = vset(dz0);
      const v4f hi = vset(float(kSkyN - 1));
      for (int c = c_begin; c < c_end; c += 4) {
        const v4f vc = vset(float(c)) + lane;
        const v4f dx = vdx + dux * vc, dy = vdy + duy * vc, dz = vdz + duz * vc;
        const v4f e = dz / vsqrt(dx * dx + dy * dy + dz * dz);
        vstore(ZB + c, vmin(vmax((e + one) * scale + vset(0.5f), vset(0.0f)), hi));
      }
      for (int c = c_begin; c < c_end; ++c) {
        const unsigned char* col = sky_lut_.data() + 3 * static_cast<int>(ZB[c]);
        unsigned char* p = out + 3 * c;
        p[0] = col[0];
        p[1] = col[1];
        p[2] = col[2];
      }
      std::fill(zrow + c_begin, zrow + c_end, 0.0f);
    };
    if (mode == kShadedOnly) {
      if (g1c < g0 || !shadow) return;
    } else if (g1c < g0) {
      sky(0, W);
      return;
    } else {
      sky(0, g0);
      sky(g1c + 1, W);
    }

    // The ground, four columns at a time in one pass: the hit point P = C + s d
    // (s = -C_z / d_z, the camera depth), 1/depth, the pixel's footprint in world metres
    // along x and y (|dP/dc| + |dP/dr|), the grid lines' and axes' opacities, the shadow,
    // the fade, then bytes.
    //
    // Most of the ground is plain: no line reaches it, it is off the shadow map and
    // nearer than the fade. The run is cut into segments of eight columns, and each is
    // classified first from bounds that hold over the whole segment (below), in double;
    // what a segment cannot need is skipped: the lines' opacities (two divisions and four
    // distances to the nearest line a column), the shadow lookup, the fade. Each bound is
    // looser than the per-pixel formula it stands for (by 1% and an absolute margin far
    // above float rounding), so a skipped term is one the formula makes exactly zero,
    // and a blend with a zero weight is a no-op (a + (b - a) * 0 == a): the bytes are
    // those of blending every pixel. Bounds over a segment [a, b], d(c) = d0 + c du:
    //   * the hit's x (and y) is monotone in c (d_z keeps its sign), so it lies between
    //     its values at a and b;
    //   * the footprint along x is C_z / d_z^2 (|K_x| + |L_x(c)|) with K_x =
    //     du_x d0_z - d0_x du_z and L_x(c) = dv_x d_z(c) - d_x(c) dv_z affine in c, so it
    //     is at most C_z max(1 / d_z^2 at a, b) (|K_x| + max |L_x| at a, b);
    //   * a line k g (g the spacing) reaches the segment only if k g is within the
    //     reach (1, 1.25, 1.75 footprints: minor, major, axes) of the hit's range;
    //   * the camera depth s is monotone in c: no fade while s <= fade start at a and b;
    //   * the shadow map's texel coordinates are affine in the hit point, so monotone
    //     in c: none while both ends are off the map on the same side.
    const v4f vdx0 = vset(dx0), vdy0 = vset(dy0), vdz0 = vset(dz0);
    const v4f zero = vset(0.0f);
    const auto blend = [](v4f a, float b, v4f t) { return a + (vset(b) - a) * t; };
    const double Dx0 = dx0, Dy0 = dy0, Dz0 = dz0;
    const double Kx = Dux * Dz0 - Dx0 * Duz, Ky = Duy * Dz0 - Dy0 * Duz;
    const double Lx0 = Dvx * Dz0 - Dx0 * Dvz, Lx1 = Dvx * Duz - Dux * Dvz;
    const double Ly0 = Dvy * Dz0 - Dy0 * Dvz, Ly1 = Dvy * Duz - Duy * Dvz;
    struct End {
      double px, py, s, iz2, lx, ly;
    };
    const auto end_at = [&](int c) {
      const double dz = Dz0 + c * Duz, s = -Cz_d / dz;
      return End{Cx_d + s * (Dx0 + c * Dux), Cy_d + s * (Dy0 + c * Duy), s, 1.0 / (dz * dz),
                 std::fabs(Lx0 + c * Lx1), std::fabs(Ly0 + c * Ly1)};
    };
    // Whether a line k g (an integer k) lies in [lo, hi]: the one nearest the middle
    // does if any does (rounded to nearest by adding and subtracting 1.5 2^52).
    const auto line_in = [](double lo, double hi, double inv_g, double g) {
      const double mid = 0.5 * (lo + hi) * inv_g;
      const double k = (mid + 6755399441055744.0) - 6755399441055744.0;
      return std::fabs(mid - k) * g <= 0.5 * (hi - lo);
    };
    const double ig1 = 1.0 / g1, ig2 = 1.0 / g2;
    for (int a = g0; a <= g1c; a += 8) {
      const int b = std::min(a + 7, g1c);
      if (mode == kShadedOnly && (b < col_lo || a > col_hi)) continue;
      const End ea = end_at(a), eb = end_at(b);
      const double iz2 = std::max(ea.iz2, eb.iz2);
      const double rx = 1.01 * Cz_d * iz2 * (std::fabs(Kx) + std::max(ea.lx, eb.lx)) + 1e-6;
      const double ry = 1.01 * Cz_d * iz2 * (std::fabs(Ky) + std::max(ea.ly, eb.ly)) + 1e-6;
      const double x_lo = std::min(ea.px, eb.px) - 1e-6 * (1 + std::fabs(ea.px) + std::fabs(eb.px));
      const double x_hi = std::max(ea.px, eb.px) + 1e-6 * (1 + std::fabs(ea.px) + std::fabs(eb.px));
      const double y_lo = std::min(ea.py, eb.py) - 1e-6 * (1 + std::fabs(ea.py) + std::fabs(eb.py));
      const double y_hi = std::max(ea.py, eb.py) + 1e-6 * (1 + std::fabs(ea.py) + std::fabs(eb.py));
      // Which lines reach the segment: minor and major lines of constant x and of
      // constant y, the y axis (x = 0) and the x axis (y = 0).
      const bool mx1 = grid && line_in(x_lo - rx, x_hi + rx, ig1, g1);
      const bool my1 = grid && line_in(y_lo - ry, y_hi + ry, ig1, g1);
      const bool mx2 = grid && line_in(x_lo - 1.25 * rx, x_hi + 1.25 * rx, ig2, g2);
      const bool my2 = grid && line_in(y_lo - 1.25 * ry, y_hi + 1.25 * ry, ig2, g2);
      const bool axis_y = axes && x_lo - 1.75 * rx <= 0 && x_hi + 1.75 * rx >= 0;
      const bool axis_x = axes && y_lo - 1.75 * ry <= 0 && y_hi + 1.75 * ry >= 0;
      const bool minor = mx1 || my1, major = mx2 || my2;
      const bool lines = minor || major || axis_y || axis_x;
      const bool fade = std::max(ea.s, eb.s) * (1 + 1e-5) > fade0;
      bool shaded = false;
      if (shadow) {
        const double m = 1e-3;  // texels
        const double ua = (ea.px - sh_x0) * sh_inv - 0.5, ub = (eb.px - sh_x0) * sh_inv - 0.5;
        const double va = (ea.py - sh_y0) * sh_inv - 0.5, vb = (eb.py - sh_y0) * sh_inv - 0.5;
        shaded = std::max(ua, ub) > -m && std::min(ua, ub) < N - 1 + m && std::max(va, vb) > -m &&
                 std::min(va, vb) < N - 1 + m;
      }
      if (mode == kShadedOnly && !shaded) continue;
      for (int c = a; c <= b; c += 4) {
        const int n = std::min(4, g1c + 1 - c);  // columns of this vector in the run
        const v4f vc = vset(float(c)) + lane;
        const v4f dz = vdz0 + duz * vc;
        const v4f zb = -dz / Cz;
        if (n == 4) {
          vstore(zrow + c, zb);
        } else {
          for (int i = 0; i < n; ++i) zrow[c + i] = zb[i];
        }
        v4i bgr = plain;
        if (lines || fade || shaded) {
          const v4f dx = vdx0 + dux * vc, dy = vdy0 + duy * vc;
          const v4f k = one / dz;
          const v4f s = -Cz * k;
          const v4f px = Cx + s * dx, py = Cy + s * dy;
          v4f m1 = zero, m2 = zero, ay = zero, ax = zero;
          if (lines) {
            // The terms the segment's bounds leave out are zero (a clamp of a negative
            // number); a max with zero, or a blend by zero, is left out with them.
            const v4f cxz = duz * k, rvz = dvz * k;
            const v4f fpx = s * (vabs(dux - dx * cxz) + vabs(dvx - dx * rvz)) + tiny;
            const v4f fpy = s * (vabs(duy - dy * cxz) + vabs(dvy - dy * rvz)) + tiny;
            const v4f ipmin = one / vmax(fpx, fpy);  // == min(1 / fpx, 1 / fpy), rounded alike
            const v4f ipx = (mx1 || mx2 || axis_y) ? one / fpx : zero;
            const v4f ipy = (my1 || my2 || axis_x) ? one / fpy : zero;
            // Minor lines 1 px wide, fading out between 8 and 3 px apart; major 1.5 px, 6 to 2 px.
            if (minor) {
              const v4f a1 = grid_on * vclamp01((vg1 * ipmin - vset(3.0f)) * vset(0.2f));
              const v4f tx = mx1 ? vclamp01(one - vfrac_dist(px * vig1) * vg1 * ipx) : zero;
              const v4f ty = my1 ? vclamp01(one - vfrac_dist(py * vig1) * vg1 * ipy) : zero;
              m1 = a1 * (mx1 && my1 ? vmax(tx, ty) : mx1 ? tx : ty);
            }
            if (major) {
              const v4f a2 = grid_on * vclamp01((vg2 * ipmin - vset(2.0f)) * vset(0.25f));
              const v4f tx = mx2 ? vclamp01(vset(1.25f) - vfrac_dist(px * vig2) * vg2 * ipx) : zero;
              const v4f ty = my2 ? vclamp01(vset(1.25f) - vfrac_dist(py * vig2) * vg2 * ipy) : zero;
              m2 = a2 * (mx2 && my2 ? vmax(tx, ty) : mx2 ? tx : ty);
            }
            if (axis_y) ay = axes_on * vclamp01(vset(1.75f) - vabs(px) * ipx);
            if (axis_x) ax = axes_on * vclamp01(vset(1.75f) - vabs(py) * ipy);
          }
          // Shadow: bilinear lookup in the blurred map, only where the hit is on it.
          v4f dk = one;
          if (shaded) {
            const v4f u = (px - vsh_x0) * vsh_inv - vset(0.5f), v = (py - vsh_y0) * vsh_inv - vset(0.5f);
            if (vany((u > zero) & (v > zero) & (u < vN1) & (v < vN1))) {
              for (int i = 0; i < 4; ++i) {
                const float ui = u[i], vi = v[i];
                if (!(ui > 0.0f && vi > 0.0f && ui < float(N - 1) && vi < float(N - 1))) continue;
                const int iu = static_cast<int>(ui), iv = static_cast<int>(vi);
                const float fu = ui - float(iu), fv = vi - float(iv);
                const float* t0 = shadow_.data() + std::size_t(iv) * N + iu;
                const float* t1 = t0 + N;
                const float sv = (t0[0] * (1 - fu) + t0[1] * fu) * (1 - fv) + (t1[0] * (1 - fu) + t1[1] * fu) * fv;
                dk[i] = 1.0f - shadow_k * sv;
              }
            }
          }
          // Colour: ground, shadow, minor, major lines, axes, fade.
          v4f cr = vset(ground_c.r) * dk, cg = vset(ground_c.g) * dk, cb = vset(ground_c.b) * dk;
          if (minor) cr = blend(cr, minor_c.r, m1), cg = blend(cg, minor_c.g, m1), cb = blend(cb, minor_c.b, m1);
          if (major) cr = blend(cr, major_c.r, m2), cg = blend(cg, major_c.g, m2), cb = blend(cb, major_c.b, m2);
          if (axis_y) cr = blend(cr, ax_y.r, ay), cg = blend(cg, ax_y.g, ay), cb = blend(cb, ax_y.b, ay);
          if (axis_x) cr = blend(cr, ax_x.r, ax), cg = blend(cg, ax_x.g, ax), cb = blend(cb, ax_x.b, ax);
          if (fade) {
            const v4f t = vclamp01((s - vfade0) * vinv_fade);
            const v4f fd = t * t * (vset(3.0f) - vset(2.0f) * t);
            cr = blend(cr, horizon.r, fd), cg = blend(cg, horizon.g, fd), cb = blend(cb, horizon.b, fd);
          }
          bgr = pack_bgr(cr, cg, cb);
        }
        // Bytes: 4 at a time (each store's fourth byte is the next column's first,
        // written after it); the run's last column 3 bytes, and the segment's last when
        // the next segment may be left as it is.
        const int last = mode == kAll ? g1c : b;
        unsigned char* p = out + 3 * c;
        if (c + 4 <= last) {
          for (int i = 0; i < 4; ++i) {
            const std::uint32_t w = static_cast<std::uint32_t>(bgr[i]);
            std::memcpy(p + 3 * i, &w, 4);
          }
        } else {
          for (int i = 0; i < n; ++i, p += 3) {
            const std::uint32_t w = static_cast<std::uint32_t>(bgr[i]);
            if (c + i < last) {
              std::memcpy(p, &w, 4);
            } else {
              p[0] = static_cast<unsigned char>(w);
              p[1] = static_cast<unsigned char>(w >> 8);
              p[2] = static_cast<unsigned char>(w >> 16);
            }
          }
        }
      }
    }
  };

  const std::integral_constant<int, kAll> kAllRow;
  const std::integral_constant<int, kShadedOnly> kShadedOnlyRow;
  const auto for_rows = [&](int lo, int hi, auto&& fn) {
    for (int r = std::max(lo, r_begin); r <= std::min(hi, r_end - 1); ++r) fn(r);
  };
  if (plan.mode == BackgroundPlan::kDraw) {  // a new camera: draw every pixel
    for_rows(0, height_ - 1, [&](int r) {
      if (shadow)
        draw_row(r, kAllRow, std::true_type{}, 0, W - 1);
      else
        draw_row(r, kAllRow, std::false_type{}, 0, W - 1);
    });
    return;
  }
  // The kept buffers are made by the first render() (no allocation later).
  const std::size_t row_bytes = std::size_t(W) * 3, depth_bytes = std::size_t(W) * sizeof(float);
  if (plan.mode == BackgroundPlan::kDrawAndKeep) {
    for_rows(0, height_ - 1, [&](int r) {
      draw_row(r, kAllRow, std::false_type{}, 0, W - 1);
      std::memcpy(cached_image_.ptr(r), image_.ptr(r), row_bytes);
      std::memcpy(cached_inv_depth_.ptr(r), inv_depth_.ptr(r), depth_bytes);
    });
  } else {
    for_rows(0, height_ - 1, [&](int r) {
      std::memcpy(image_.ptr(r), cached_image_.ptr(r), row_bytes);
      std::memcpy(inv_depth_.ptr(r), cached_inv_depth_.ptr(r), depth_bytes);
      std::int16_t* idrow = ids_.ptr<std::int16_t>(r);
      std::fill(idrow, idrow + W, std::int16_t{-1});
    });
  }
  if (!plan.shaded) return;
  for_rows(plan.r_lo, plan.r_hi, [&](int r) { draw_row(r, kShadedOnlyRow, std::true_type{}, plan.c_lo, plan.c_hi); });
}

void Renderer::draw_meshes(const std::vector<Eigen::Isometry3d>& X_WB, const Eigen::Isometry3d& X_CW, double f_px,
                           double near_m, const RowBand& band, Stats& stats) {
  // Every band transforms the vertices and sets up every triangle (the same floats),
  // and fills only its own rows.
  Vertex* const scratch = scratch_.data() + std::size_t(band.index) * scratch_stride_;
  const float f = static_cast<float>(f_px);
  const float cx = 0.5f * width_, cy = 0.5f * height_;
  const float W = float(width_), H = float(height_);
  const float znear = static_cast<float>(near_m);

  Target tgt{image_.ptr<unsigned char>(0),
             inv_depth_.ptr<float>(0),
             ids_.ptr<std::int16_t>(0),
             image_.step[0],
             inv_depth_.step[0] / sizeof(float),
             ids_.step[0] / sizeof(std::int16_t),
             width_,
             height_};

  // Lights in the camera frame.
  Shader sh{};
  Eigen::Vector3d l = style_.light_from_W;
  l = (l.allFinite() && l.norm() > 0) ? l.normalized() : Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d Lc = X_CW.linear() * l;
  const Eigen::Vector3d Uc = X_CW.linear() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d Hc = (Lc + Eigen::Vector3d(0, 0, -1)).norm() > 1e-9
                                 ? (Lc + Eigen::Vector3d(0, 0, -1)).normalized()
                                 : Eigen::Vector3d(0, 0, -1);
  for (int i = 0; i < 3; ++i) {
    sh.L[i] = static_cast<float>(Lc[i]);
    sh.U[i] = static_cast<float>(Uc[i]);
    sh.Hv[i] = static_cast<float>(Hc[i]);
  }
  sh.amb_mid = static_cast<float>(0.5 * (style_.ambient_up + style_.ambient_down));
  sh.amb_half = static_cast<float>(0.5 * (style_.ambient_up - style_.ambient_down));
  sh.kd = static_cast<float>(style_.diffuse);
  sh.kf = static_cast<float>(style_.fill);
  sh.ks = static_cast<float>(style_.specular);
  sh.lut = linear_to_srgb_.data();

  // Frustum side planes through the camera centre (inward unit normals), for spheres.
  const Eigen::Vector3f side[4] = {Eigen::Vector3f(f, 0, cx).normalized(), Eigen::Vector3f(-f, 0, W - cx).normalized(),
                                   Eigen::Vector3f(0, f, cy).normalized(), Eigen::Vector3f(0, -f, H - cy).normalized()};

  for (std::size_t b = 0; b + 1 < bodies_.size(); ++b) {
    const Eigen::Isometry3d X_CB = X_CW * X_WB[b];
    if (!X_CB.matrix().allFinite()) continue;
    const Eigen::Matrix3f R = X_CB.linear().cast<float>();
    const Eigen::Vector3f p = X_CB.translation().cast<float>();
    sh.id = static_cast<std::int16_t>(b);
    for (std::size_t mi = bodies_[b]; mi < bodies_[b + 1]; ++mi) {
      const PreparedMesh& m = meshes_[mi];
      if (!m.visible) continue;
      // Whole mesh outside the view?
      const Eigen::Vector3f c = R * m.centre + p;
      bool out = c.z() + m.radius < znear;
      for (int k = 0; k < 4 && !out; ++k) out = side[k].dot(c) < -m.radius;
      if (out) {
        ++stats.meshes_culled;
        continue;
      }
      ++stats.meshes_drawn;
      const bool smooth = !m.nrm.empty();
      for (int i = 0; i < 3; ++i) sh.albedo[i] = m.albedo[i];

      // Vertices to the camera frame, projection and outcodes.
      for (std::size_t i = 0; i < m.pos.size(); ++i) {
        Vertex& v = scratch[i];
        const Eigen::Vector3f q = R * m.pos[i] + p;
        v.x = q.x();
        v.y = q.y();
        v.z = q.z();
        if (smooth) {
          const Eigen::Vector3f n = R * m.nrm[i];
          v.nx = n.x();
          v.ny = n.y();
          v.nz = n.z();
        }
        if (v.z < znear) {
          v.code = kNear;
          continue;
        }
        v.iz = 1.0f / v.z;
        v.sx = cx + f * v.x * v.iz;
        v.sy = cy + f * v.y * v.iz;
        unsigned code = 0;
        if (v.sx < 0) code |= kLeft;
        if (v.sx > W) code |= kRight;
        if (v.sy < 0) code |= kTop;
        if (v.sy > H) code |= kBottom;
        if (v.sx < -kGuardPx || v.sx > W + kGuardPx || v.sy < -kGuardPx || v.sy > H + kGuardPx) code |= kGuard;
        v.code = code;
      }

      for (const auto& t : m.tri) {
        ++stats.triangles_in;
        const Vertex& a = scratch[t[0]];
        const Vertex& bv = scratch[t[1]];
        const Vertex& vc = scratch[t[2]];
        if (a.code & bv.code & vc.code & kOutside) continue;
        // Facing: the camera (origin) is on the front side of the triangle's plane.
        const float e1x = bv.x - a.x, e1y = bv.y - a.y, e1z = bv.z - a.z;
        const float e2x = vc.x - a.x, e2y = vc.y - a.y, e2z = vc.z - a.z;
        float fnx = e1y * e2z - e1z * e2y, fny = e1z * e2x - e1x * e2z, fnz = e1x * e2y - e1y * e2x;
        const float side_dot = fnx * a.x + fny * a.y + fnz * a.z;
        const bool facing = side_dot < 0;
        if (!facing && m.cull) {
          ++stats.triangles_backfacing;
          continue;
        }
        if (side_dot == 0) continue;  // seen edge-on (or degenerate)
        const float flip = facing ? 1.0f : -1.0f;
        unsigned char flat[3] = {0, 0, 0};
        if (!smooth) {
          const float inv = flip / std::sqrt(fnx * fnx + fny * fny + fnz * fnz);
          fnx *= inv;
          fny *= inv;
          fnz *= inv;
          sh.shade(fnx, fny, fnz, flat);
        }
        ++stats.triangles_rasterised;
        if (!((a.code | bv.code | vc.code) & (kNear | kGuard))) {
          if (smooth) {
            const RVert r0{a.sx, a.sy, a.iz, flip * a.nx * a.iz, flip * a.ny * a.iz, flip * a.nz * a.iz};
            const RVert r1{bv.sx, bv.sy, bv.iz, flip * bv.nx * bv.iz, flip * bv.ny * bv.iz, flip * bv.nz * bv.iz};
            const RVert r2{vc.sx, vc.sy, vc.iz, flip * vc.nx * vc.iz, flip * vc.ny * vc.iz, flip * vc.nz * vc.iz};
            raster_triangle<true>(r0, r1, r2, tgt, sh, flat, band);
          } else {
            const RVert r0{a.sx, a.sy, a.iz, 0, 0, 0}, r1{bv.sx, bv.sy, bv.iz, 0, 0, 0},
                r2{vc.sx, vc.sy, vc.iz, 0, 0, 0};
            raster_triangle<false>(r0, r1, r2, tgt, sh, flat, band);
          }
          continue;
        }
        // Clip in camera space: the near plane, then the guard band (needed only when a
        // vertex lies beyond it), so every projected vertex is finite and bounded.
        ++stats.triangles_clipped;
        CVert poly_a[12], poly_b[12];
        const Vertex* tv[3] = {&a, &bv, &vc};
        for (int i = 0; i < 3; ++i)
          poly_a[i] = {tv[i]->x,
                       tv[i]->y,
                       tv[i]->z,
                       smooth ? flip * tv[i]->nx : 0.0f,
                       smooth ? flip * tv[i]->ny : 0.0f,
                       smooth ? flip * tv[i]->nz : 0.0f};
        int n = clip_polygon(poly_a, 3, poly_b, 0, 0, 1, -znear);
        CVert* cur = poly_b;
        CVert* nxt = poly_a;
        const float G = kGuardPx;
        const float planes[4][4] = {
            {f, 0, G + cx, 0}, {-f, 0, W + G - cx, 0}, {0, f, G + cy, 0}, {0, -f, H + G - cy, 0}};
        for (int k = 0; k < 4 && n >= 3; ++k) {
          bool any_out = false;
          for (int i = 0; i < n; ++i)
            any_out |= planes[k][0] * cur[i].x + planes[k][1] * cur[i].y + planes[k][2] * cur[i].z < 0;
          if (!any_out) continue;
          n = clip_polygon(cur, n, nxt, planes[k][0], planes[k][1], planes[k][2], 0);
          std::swap(cur, nxt);
        }
        if (n < 3) continue;
        RVert rv[12];
        for (int i = 0; i < n; ++i) {
          const float z = std::max(cur[i].z, znear);
          const float iz = 1.0f / z;
          rv[i] = {cx + f * cur[i].x * iz, cy + f * cur[i].y * iz, iz, cur[i].nx * iz, cur[i].ny * iz, cur[i].nz * iz};
        }
        for (int i = 1; i + 1 < n; ++i) {
          if (smooth)
            raster_triangle<true>(rv[0], rv[i], rv[i + 1], tgt, sh, flat, band);
          else
            raster_triangle<false>(rv[0], rv[i], rv[i + 1], tgt, sh, flat, band);
        }
      }
    }
  }
}

// ---------------------------------------------------------------------------------
// Overlays.

void Renderer::draw_overlays(const Camera& camera, const Overlays& ov) {
  const Canvas cvs{image_.ptr<unsigned char>(0), image_.step[0], width_, height_};
  const Eigen::Isometry3d X_CW = camera_from_world(camera);
  const double f = focal_length_px(camera);
  const Rgbf black{0, 0, 0};
  const double w = std::max(0.5, ov.line_width_px);
  const double dash_on_px = 4.0 * w + 2.0, dash_off_px = 3.0 * w + 2.0;

  // Paths: each world segment clipped at the near plane and projected; on screen,
  // vertices closer than kMerge_px to the last one drawn are merged into the next
  // segment (the path's last vertex is always drawn to). A clipped or non-finite
  // segment ends the line and the next visible one starts it again. First a dark halo
  // along the whole path, then the colour over it.
  constexpr double kMerge_px = 2.0;
  for (const PathOverlay& path : ov.paths) {
    const std::vector<Eigen::Vector3d>& pts = path.points_W;
    if (pts.size() < 2) continue;
    const double on = path.dashed ? dash_on_px : 0.0;
    for (int pass = 0; pass < 2; ++pass) {
      const Rgbf col = pass == 0 ? black : rgbf(path.color);
      const double half = pass == 0 ? 0.5 * w + 1.0 : 0.5 * w;
      const float alpha = pass == 0 ? 0.35f : 1.0f;
      double phase = 0;
      bool drawing = false;       // a line is under way: pen is its last vertex drawn
      Eigen::Vector2d pen, last;  // last: the end of the line's last projected segment
      const auto finish = [&] {
        if (drawing && last != pen) draw_stroke(cvs, pen, last, half, col, alpha, on, dash_off_px, phase);
        drawing = false;
      };
      for (std::size_t i = 1; i < pts.size(); ++i) {
        Eigen::Vector2d a, b;
        if (!pts[i - 1].allFinite() || !pts[i].allFinite() ||
            !project_segment(camera, X_CW, f, pts[i - 1], pts[i], a, b)) {
          finish();
          continue;
        }
        if (!drawing || a != last) {  // first segment, or its start was clipped
          finish();
          pen = a;
          drawing = true;
        }
        last = b;
        if ((b - pen).squaredNorm() >= kMerge_px * kMerge_px) {
          draw_stroke(cvs, pen, b, half, col, alpha, on, dash_off_px, phase);
          pen = b;
        }
      }
      finish();
    }
  }

  // Markers: a ring in the horizontal plane through the point and a cross, over a halo.
  for (const MarkerOverlay& m : ov.markers) {
    if (!m.p_W.allFinite()) continue;
    constexpr int kSeg = 32;
    for (int pass = 0; pass < 2; ++pass) {
      const Rgbf col = pass == 0 ? black : rgbf(m.color);
      const double half = pass == 0 ? 0.5 * w + 1.0 : 0.5 * w;
      const float alpha = pass == 0 ? 0.35f : 1.0f;
      for (int i = 0; i < kSeg; ++i) {
        const double t0 = 2 * M_PI * i / kSeg, t1 = 2 * M_PI * (i + 1) / kSeg;
        Eigen::Vector2d a, b;
        if (project_segment(camera, X_CW, f, m.p_W + m.ring_m * Eigen::Vector3d(std::cos(t0), std::sin(t0), 0),
                            m.p_W + m.ring_m * Eigen::Vector3d(std::cos(t1), std::sin(t1), 0), a, b))
          draw_segment(cvs, a, b, half, col, alpha);
      }
      for (const Eigen::Vector3d& arm : {Eigen::Vector3d(0.5 * m.ring_m, 0, 0), Eigen::Vector3d(0, 0.5 * m.ring_m, 0)}) {
        Eigen::Vector2d a, b;
        if (project_segment(camera, X_CW, f, m.p_W - arm, m.p_W + arm, a, b)) draw_segment(cvs, a, b, half, col, alpha);
      }
    }
  }

  // Force arrows: shaft and a filled head, with a dark halo for contrast.
  for (const ForceArrow& fa : ov.forces) {
    if (!fa.p_W.allFinite() || !fa.f_W_N.allFinite()) continue;
    const Eigen::Vector3d tip_W = fa.p_W + ov.force_scale_m_per_N * fa.f_W_N;
    Eigen::Vector2d a, b;
    if (!project_segment(camera, X_CW, f, fa.p_W, tip_W, a, b)) continue;
    const double len = (b - a).norm();
    if (!(len >= 1.0)) continue;
    const Eigen::Vector2d dir = (b - a) / len, nrm(-dir.y(), dir.x());
    const double head = std::min(0.45 * len, std::max(10.0, 5.0 * w));
    const Eigen::Vector2d base = b - head * dir;
    const Rgbf col = rgbf(fa.color);
    draw_segment(cvs, a, base, 0.5 * w + 1.0, black, 0.45f);
    draw_triangle(cvs, b + dir, base - nrm * (0.5 * head + 1.0) - dir, base + nrm * (0.5 * head + 1.0) - dir, black,
                  0.45f);
    draw_segment(cvs, a, base + dir, 0.5 * w, col, 1.0f);
    draw_triangle(cvs, b, base - nrm * (0.5 * head), base + nrm * (0.5 * head), col, 1.0f);
    draw_ring(cvs, a, 0, 0.5 * w + 1.0, col, 1.0f, true);
  }

  // Centre of mass: ring on the ground at its projection, dashed drop line, circled cross.
  if (ov.com_W && ov.com_W->allFinite()) {
    const Eigen::Vector3d com = *ov.com_W;
    const Eigen::Vector3d g(com.x(), com.y(), 0.0);
    const Rgbf col = rgbf(ov.com_color);
    constexpr int kSeg = 32;
    constexpr double kGroundRing_m = 0.05;
    for (int i = 0; i < kSeg; ++i) {
      const double t0 = 2 * M_PI * i / kSeg, t1 = 2 * M_PI * (i + 1) / kSeg;
      Eigen::Vector2d a, b;
      if (project_segment(camera, X_CW, f, g + kGroundRing_m * Eigen::Vector3d(std::cos(t0), std::sin(t0), 0),
                          g + kGroundRing_m * Eigen::Vector3d(std::cos(t1), std::sin(t1), 0), a, b))
        draw_segment(cvs, a, b, 0.5 * w, col, 1.0f);
    }
    Eigen::Vector2d pc, pg;
    if (project_segment(camera, X_CW, f, com, g, pc, pg)) {
      draw_ring(cvs, pg, 0, 0.5 * w + 0.5, col, 1.0f, true);
      const double len = (pg - pc).norm();
      if (len > 1) {
        const Eigen::Vector2d dir = (pg - pc) / len;
        for (double s = 0; s < len; s += 10.0)
          draw_segment(cvs, pc + dir * s, pc + dir * std::min(len, s + 6.0), 0.5 * std::max(1.0, 0.6 * w), col, 0.9f);
      }
    }
    if (const auto p = project(camera, com)) {
      const double r = 4.0 * w + 2.0, arm = r + 4.0 * w;
      draw_ring(cvs, *p, r, 0.5 * w + 1.0, black, 0.5f);
      draw_segment(cvs, *p - Eigen::Vector2d(arm, 0), *p + Eigen::Vector2d(arm, 0), 0.5 * w + 1.0, black, 0.5f);
      draw_segment(cvs, *p - Eigen::Vector2d(0, arm), *p + Eigen::Vector2d(0, arm), 0.5 * w + 1.0, black, 0.5f);
      draw_ring(cvs, *p, r, 0.5 * w, col, 1.0f);
      draw_segment(cvs, *p - Eigen::Vector2d(arm, 0), *p + Eigen::Vector2d(arm, 0), 0.5 * w, col, 1.0f);
      draw_segment(cvs, *p - Eigen::Vector2d(0, arm), *p + Eigen::Vector2d(0, arm), 0.5 * w, col, 1.0f);
    }
  }

  // Text: glyph masks blended at a pen position (baseline), panels darkened to 45%.
  const auto glyph_of = [&](char ch) -> const Glyph& { return glyphs_[(ch >= 32 && ch < 127) ? ch - 32 : '?' - 32]; };
  const auto text_width = [&](const std::string& text) {
    int w_text = 0;
    for (char ch : text) w_text += glyph_of(ch).advance;
    return w_text;
  };
  const auto draw_text = [&](int pen_x, int pen_y, const std::string& text, const Rgbf& col) {
    for (char ch : text) {
      const Glyph& g = glyph_of(ch);
      for (int gy = 0; gy < g.coverage.rows; ++gy) {
        const int y = pen_y + g.y0 + gy;
        if (y < 0 || y >= height_) continue;
        const unsigned char* mrow = g.coverage.ptr<unsigned char>(gy);
        for (int gx = 0; gx < g.coverage.cols; ++gx) {
          const int x = pen_x + g.x0 + gx;
          if (x < 0 || x >= width_ || mrow[gx] == 0) continue;
          cvs.blend(x, y, col, mrow[gx] / 255.0f);
        }
      }
      pen_x += g.advance;
      if (pen_x >= width_) break;
    }
  };
  const auto darken = [&](int x_lo, int y_lo, int x_hi, int y_hi) {
    x_lo = std::max(0, x_lo);
    y_lo = std::max(0, y_lo);
    x_hi = std::min(width_, x_hi);
    y_hi = std::min(height_, y_hi);
    for (int y = y_lo; y < y_hi; ++y) {
      unsigned char* row = image_.ptr<unsigned char>(y);
      for (int x = 3 * x_lo; x < 3 * x_hi; ++x) row[x] = static_cast<unsigned char>(row[x] * 45 / 100);
    }
  };
  const Rgbf white{255, 255, 255};
  const int margin = std::max(6, text_line_px_ / 2), pad = std::max(4, text_line_px_ / 3);

  // Text lines on a dark translucent panel in the top-left corner.
  if (!ov.text_lines.empty()) {
    int text_w = 0;
    for (const std::string& line : ov.text_lines) text_w = std::max(text_w, text_width(line));
    const int n_lines = static_cast<int>(ov.text_lines.size());
    darken(margin, margin, margin + text_w + 2 * pad,
           margin + n_lines * text_line_px_ + 2 * pad - (text_line_px_ - text_ascent_px_) / 2);
    for (int li = 0; li < n_lines; ++li)
      draw_text(margin + pad, margin + pad + text_ascent_px_ + li * text_line_px_, ov.text_lines[li], white);
  }

  // Legend of the labelled paths on a dark panel in the top-right corner: per entry a
  // sample of the line (its colour, solid or dashed), then the label in white.
  int n_entries = 0, label_w = 0;
  for (const PathOverlay& path : ov.paths)
    if (!path.label.empty()) {
      ++n_entries;
      label_w = std::max(label_w, text_width(path.label));
    }
  for (const MarkerOverlay& m : ov.markers)
    if (!m.label.empty()) {
      ++n_entries;
      label_w = std::max(label_w, text_width(m.label));
    }
  if (n_entries > 0) {
    const int sample_px = std::max(24, 2 * text_line_px_), gap = pad + 2;
    const int x_hi = width_ - margin, x_lo = x_hi - (2 * pad + sample_px + gap + label_w);
    darken(x_lo, margin, x_hi, margin + n_entries * text_line_px_ + 2 * pad - (text_line_px_ - text_ascent_px_) / 2);
    int li = 0;
    for (const PathOverlay& path : ov.paths) {
      if (path.label.empty()) continue;
      const int pen_y = margin + pad + text_ascent_px_ + li * text_line_px_;
      const double y_mid = pen_y - 0.5 * text_ascent_px_;
      double phase = 0;
      draw_stroke(cvs, {x_lo + pad + 0.5 * w, y_mid}, {x_lo + pad + sample_px - 0.5 * w, y_mid}, 0.5 * w,
                  rgbf(path.color), 1.0f, path.dashed ? dash_on_px : 0.0, dash_off_px, phase);
      draw_text(x_lo + pad + sample_px + gap, pen_y, path.label, white);
      ++li;
    }
    for (const MarkerOverlay& m : ov.markers) {  // a ring and a cross, as drawn
      if (m.label.empty()) continue;
      const int pen_y = margin + pad + text_ascent_px_ + li * text_line_px_;
      const Eigen::Vector2d c(x_lo + pad + 0.5 * sample_px, pen_y - 0.5 * text_ascent_px_);
      const double r = 0.3 * text_ascent_px_ + 1.0;
      draw_ring(cvs, c, r, 0.5 * w, rgbf(m.color), 1.0f);
      draw_segment(cvs, c - Eigen::Vector2d(r, 0), c + Eigen::Vector2d(r, 0), 0.5 * w, rgbf(m.color), 1.0f);
      draw_text(x_lo + pad + sample_px + gap, pen_y, m.label, white);
      ++li;
    }
  }
}

}  // namespace dmbd::viz
