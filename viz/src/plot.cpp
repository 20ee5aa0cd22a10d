// Figure layout and rendering with OpenCV's drawing primitives.
//
// Layout: the figure title (if any) on top, then one equal-height slot per axes.
// All plot areas share the same left edge (the widest y tick labels decide it) so
// that stacked axes line up. Series are drawn into the plot-area sub-image with
// sub-pixel anti-aliased lines after clipping each segment in double precision, so
// nothing spills over the axis box and huge values cannot overflow OpenCV's ints.
#include "dmbd/viz/plot.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "plot_detail.hpp"

namespace dmbd::viz {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kShift = 4;  // fractional bits of the sub-pixel coordinates given to OpenCV
constexpr double kSub = 1 << kShift;

const cv::Scalar kWhite(255, 255, 255);
const cv::Scalar kText(25, 25, 25);
const cv::Scalar kAxisColor(50, 50, 50);
const cv::Scalar kGridMajor(215, 215, 215);
const cv::Scalar kGridMinor(236, 236, 236);
const cv::Scalar kRefColor(80, 80, 80);
const cv::Scalar kNoteColor(70, 70, 70);
const cv::Scalar kLegendBorder(190, 190, 190);

cv::Scalar bgr(Color c) { return cv::Scalar(c.b, c.g, c.r); }
int round_px(double v) { return static_cast<int>(std::lround(v)); }

struct Font {
  int face;
  double scale;
  int thick;
};

// Pixel sizes for a figure, scaled with its size relative to 1000 x 700.
struct Style {
  double s = 1;
  Font tick, label, title, figure_title, note;
  int gap = 10, tick_len = 5, box_thick = 1;
};

Style make_style(int width_px, int height_px) {
  Style st;
  // Linear above 1000 x 700 (the same look at a higher resolution); shrinking more
  // slowly below it so that text in small figures stays legible.
  const double relative = std::min(width_px / 1000.0, height_px / 700.0);
  st.s = std::clamp(relative < 1 ? std::sqrt(relative) : relative, 0.4, 4.0);
  const int thin = std::max(1, round_px(st.s));
  st.tick = {cv::FONT_HERSHEY_SIMPLEX, 0.5 * st.s, thin};
  st.label = {cv::FONT_HERSHEY_SIMPLEX, 0.58 * st.s, thin};
  st.title = {cv::FONT_HERSHEY_DUPLEX, 0.6 * st.s, thin};
  st.figure_title = {cv::FONT_HERSHEY_DUPLEX, 0.75 * st.s, thin};
  st.note = {cv::FONT_HERSHEY_SIMPLEX, 0.45 * st.s, thin};
  st.gap = std::max(4, round_px(10 * st.s));
  st.tick_len = std::max(3, round_px(5 * st.s));
  st.box_thick = std::max(1, round_px(st.s));
  return st;
}

// ---------------------------------------------------------------------------
// Text

// A label with an optional exponent drawn as a superscript ("10" + "-6").
struct Label {
  std::string base, sup;
};

struct TextBox {
  int w = 0;
  int ascent = 0;       // above the baseline, including a raised exponent
  int descent = 0;      // below the baseline
  int base_ascent = 0;  // of the base text alone (for centring digits on a tick)
};

TextBox measure(const std::string& text, const Font& f) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, f.face, f.scale, f.thick, &baseline);
  return {size.width, size.height, baseline, size.height};
}

Font sup_font(const Font& f) { return {f.face, f.scale * 0.72, f.thick}; }
int sup_raise(const TextBox& base) { return round_px(base.ascent * 0.6); }

TextBox measure(const Label& l, const Font& f) {
  TextBox b = measure(l.base, f);
  if (l.sup.empty()) return b;
  const TextBox e = measure(l.sup, sup_font(f));
  const int raise = sup_raise(b);
  b.w += 1 + e.w;
  b.ascent = std::max(b.ascent, raise + e.ascent);
  return b;
}

enum class HAlign { Left, Center, Right };
enum class VAlign { Top, Middle, Bottom };

// Draws l with its box aligned to (x, y); Middle centres the base text's cap height.
void draw_text(cv::Mat& img, const Label& l, double x, double y, HAlign h, VAlign v, const Font& f,
               const cv::Scalar& color) {
  const TextBox b = measure(l, f);
  double ox = x;
  if (h == HAlign::Center) ox = x - b.w / 2.0;
  if (h == HAlign::Right) ox = x - b.w;
  double oy = y + b.ascent;
  if (v == VAlign::Middle) oy = y + b.base_ascent / 2.0;
  if (v == VAlign::Bottom) oy = y - b.descent;
  const cv::Point origin(round_px(ox), round_px(oy));
  cv::putText(img, l.base, origin, f.face, f.scale, color, f.thick, cv::LINE_AA);
  if (!l.sup.empty()) {
    const TextBox base = measure(l.base, f);
    const Font fs = sup_font(f);
    cv::putText(img, l.sup, origin + cv::Point(base.w + 1, -sup_raise(base)), fs.face, fs.scale, color, fs.thick,
                cv::LINE_AA);
  }
}

void draw_text(cv::Mat& img, const std::string& text, double x, double y, HAlign h, VAlign v, const Font& f,
               const cv::Scalar& color) {
  draw_text(img, Label{text, {}}, x, y, h, v, f, color);
}

// A note over the data: text on a nearly opaque white patch.
void draw_note(cv::Mat& img, const std::string& text, double x, double y, HAlign h, VAlign v, const Font& f,
               const cv::Scalar& color) {
  const TextBox b = measure(text, f);
  double left = x, top = y;
  if (h == HAlign::Center) left = x - b.w / 2.0;
  if (h == HAlign::Right) left = x - b.w;
  if (v == VAlign::Middle) top = y - b.base_ascent / 2.0;
  if (v == VAlign::Bottom) top = y - b.ascent - b.descent;
  const int pad = 2;
  const cv::Rect patch =
      cv::Rect(round_px(left) - pad, round_px(top) - pad, b.w + 2 * pad, b.ascent + b.descent + 2 * pad) &
      cv::Rect(0, 0, img.cols, img.rows);
  if (!patch.empty()) {
    cv::Mat m = img(patch);
    m.convertTo(m, -1, 0.2, 255 * 0.8);
  }
  draw_text(img, text, x, y, h, v, f, color);
}

// Text turned 90 degrees counter-clockwise (reading bottom to top), its left edge at
// x_left and centred on y_center; shrunk to fit max_len_px. Rendered into a small
// image, rotated, and combined with the figure by a per-channel minimum (dark text
// on a white background).
void draw_rotated_text(cv::Mat& img, const std::string& text, int x_left, int y_center, int max_len_px, Font f) {
  if (text.empty()) return;
  TextBox b = measure(text, f);
  if (b.w > max_len_px && max_len_px > 0) {
    f.scale *= static_cast<double>(max_len_px) / b.w;
    b = measure(text, f);
  }
  const int pad = 2;
  cv::Mat horizontal(b.ascent + b.descent + 2 * pad, b.w + 2 * pad, CV_8UC3, kWhite);
  cv::putText(horizontal, text, cv::Point(pad, pad + b.ascent), f.face, f.scale, kText, f.thick, cv::LINE_AA);
  cv::Mat rotated;
  cv::rotate(horizontal, rotated, cv::ROTATE_90_COUNTERCLOCKWISE);
  const cv::Rect dst(x_left, y_center - rotated.rows / 2, rotated.cols, rotated.rows);
  const cv::Rect visible = dst & cv::Rect(0, 0, img.cols, img.rows);
  if (visible.empty()) return;
  cv::Mat target = img(visible);
  cv::min(target, rotated(visible - dst.tl()), target);
}

// ---------------------------------------------------------------------------
// Lines

struct Dash {
  double on_px = 0, off_px = 0;  // on_px == 0: solid
  double phase_px = 0;           // position within the current on+off period
};

Dash dash_for(double width_px, double s) {
  const double w = std::max(1.0, width_px);
  // Round caps eat about a width of every gap, hence the longer gaps.
  return {std::max(6.0 * s, 4.0 * w), std::max(5.0 * s, 3.0 * w + 1), 0};
}

cv::Point to_fixed(const cv::Point2d& p) { return {round_px(p.x * kSub), round_px(p.y * kSub)}; }

void aa_line(cv::Mat& img, const cv::Point2d& a, const cv::Point2d& b, const cv::Scalar& color, int thick) {
  cv::line(img, to_fixed(a), to_fixed(b), color, thick, cv::LINE_AA, kShift);
}

// Solid or dashed; a dash pattern continues across consecutive segments.
void draw_segment(cv::Mat& img, const cv::Point2d& a, const cv::Point2d& b, const cv::Scalar& color, int thick,
                  Dash& dash) {
  if (dash.on_px <= 0) {
    aa_line(img, a, b, color, thick);
    return;
  }
  const cv::Point2d d = b - a;
  const double len = std::hypot(d.x, d.y);
  if (!(len > 0)) return;
  const cv::Point2d u = d / len;
  const double period = dash.on_px + dash.off_px;
  double t = 0;
  while (t < len) {
    const bool on = dash.phase_px < dash.on_px;
    const double left = on ? dash.on_px - dash.phase_px : period - dash.phase_px;
    const double step = std::min(left, len - t);
    if (on) aa_line(img, a + u * t, a + u * (t + step), color, thick);
    t += step;
    dash.phase_px += step;
    if (dash.phase_px >= period - 1e-9) dash.phase_px = 0;
  }
}

// Liang-Barsky: clips segment a-b to [x0, x1] x [y0, y1]; false when nothing is left.
bool clip_segment(cv::Point2d& a, cv::Point2d& b, double x0, double y0, double x1, double y1) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  double t0 = 0, t1 = 1;
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {a.x - x0, x1 - a.x, a.y - y0, y1 - a.y};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0) {
      if (q[i] < 0) return false;
      continue;
    }
    const double r = q[i] / p[i];
    if (p[i] < 0) {
      if (r > t1) return false;
      t0 = std::max(t0, r);
    } else {
      if (r < t0) return false;
      t1 = std::min(t1, r);
    }
  }
  const cv::Point2d a0 = a;
  a = a0 + cv::Point2d(dx, dy) * t0;
  b = a0 + cv::Point2d(dx, dy) * t1;
  return true;
}

// ---------------------------------------------------------------------------
// Scales and ticks

struct AxisScale {
  bool log = false;
  double lo = 0, hi = 1;  // as displayed from left/bottom to right/top (lo > hi: reversed)
  double t0 = 0, t1 = 1;  // transformed limits
  double transform(double v) const {
    if (!std::isfinite(v)) return kNaN;
    return log ? (v > 0 ? std::log10(v) : kNaN) : v;
  }
  double fraction(double v) const { return (transform(v) - t0) / (t1 - t0); }  // NaN when invalid
  double min() const { return std::min(lo, hi); }
  double max() const { return std::max(lo, hi); }
};

struct Range {
  double lo = kInf, hi = -kInf;
  bool empty() const { return !(lo <= hi); }
  void add(double v) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
};

bool usable(double v, Scale scale) { return std::isfinite(v) && (scale == Scale::Linear || v > 0); }

void check_series(const Series& s) {
  if (s.x.size() != s.y.size())
    throw std::invalid_argument(
        fmt::format("viz: series '{}' has {} x values but {} y values", s.label, s.x.size(), s.y.size()));
}

// Extent of the points whose x and y are both drawable on the axes' scales (y only of
// the points inside given x limits when the axes ask for it).
void data_ranges(const Axes& ax, Range& xr, Range& yr) {
  for (const Series& s : ax.series) {
    check_series(s);
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (usable(s.x[i], ax.x_scale) && usable(s.y[i], ax.y_scale)) {
        xr.add(s.x[i]);
        const bool shown = !ax.y_limits_from_visible || !ax.x_limits ||
                           (s.x[i] >= ax.x_limits->first && s.x[i] <= ax.x_limits->second);
        if (shown) yr.add(s.y[i]);
      }
    }
  }
}

AxisScale resolve_scale(const std::optional<std::pair<double, double>>& limits, const Range& data, Scale scale,
                        const char* which) {
  AxisScale a;
  a.log = scale == Scale::Log;
  if (limits) {
    const auto [lo, hi] = *limits;
    if (!std::isfinite(lo) || !std::isfinite(hi) || lo == hi)
      throw std::invalid_argument(fmt::format("viz: {} limits ({}, {}) must be finite and different", which, lo, hi));
    if (a.log && (lo <= 0 || hi <= 0))
      throw std::invalid_argument(fmt::format("viz: {} limits ({}, {}) must be positive on a log axis", which, lo, hi));
    a.lo = lo;
    a.hi = hi;
  } else if (data.empty()) {
    a.lo = a.log ? 1 : 0;
    a.hi = a.log ? 10 : 1;
  } else {
    std::tie(a.lo, a.hi) = nice_limits(data.lo, data.hi, scale);
  }
  a.t0 = a.transform(a.lo);
  a.t1 = a.transform(a.hi);
  return a;
}

struct Ticks {
  std::vector<double> major, minor;
  std::vector<Label> labels;  // one per major tick
};

bool contains_close(const std::vector<double>& v, double x) {
  return std::any_of(v.begin(), v.end(), [x](double y) { return std::abs(x - y) <= 1e-9 * std::abs(x); });
}

// Decades as 10^k when the axis reaches beyond 1e-3 .. 1e4, else as plain numbers.
Label log_label(double v, bool powers) {
  const int k = round_px(std::log10(v));
  const bool decade = std::abs(v - detail::pow10(k)) <= 1e-9 * v;
  if (decade && powers) return {"10", std::to_string(k)};
  return {format_tick(v), {}};
}

// Smallest of 1, 2, 3, 4, 5, 10, 20, 25, 50, ... >= n (a double axis spans at most ~630 decades).
int nice_stride(double n) {
  for (int m : {1, 2, 3, 4, 5, 10, 20, 25, 50, 100, 200, 250, 500})
    if (m >= n) return m;
  return 1000;
}

Ticks linear_ticks(const AxisScale& a, std::optional<double> step, int max_ticks) {
  Ticks t;
  const double lo = a.min(), hi = a.max();
  if (step && *step > 0 && std::isfinite(*step)) {
    // Multiples of the requested step, doubled until they fit.
    for (double s = *step; s <= (hi - lo) * 2; s *= 2) {
      t.major = detail::multiples_within(lo, hi, s, max_ticks);
      if (!t.major.empty()) break;
    }
  }
  if (t.major.size() < 2) t.major = nice_ticks(lo, hi, max_ticks);
  for (double v : t.major) t.labels.push_back({format_tick(v), {}});
  return t;
}

Ticks log_axis_ticks(const AxisScale& a, int max_ticks, double length_px, double min_minor_decade_px) {
  Ticks t;
  const double lo = a.min(), hi = a.max();
  const int k_lo = static_cast<int>(std::floor(std::log10(lo))), k_hi = static_cast<int>(std::ceil(std::log10(hi)));
  const double decade_px = length_px / std::max(std::log10(hi) - std::log10(lo), 1e-12);
  const auto decades = log_ticks(lo, hi);
  const auto add_minor = [&](bool with_decades) {
    for (int k = k_lo; k <= k_hi; ++k)
      for (int m = with_decades ? 1 : 2; m <= 9; ++m) {
        const double v = m * detail::pow10(k);
        if (v >= lo && v <= hi && !contains_close(t.major, v)) t.minor.push_back(v);
      }
  };
  if (decades.size() >= 2) {
    const int stride = nice_stride(decades.size() / static_cast<double>(max_ticks));
    for (double v : decades) {
      const int k = round_px(std::log10(v));
      (((k % stride) + stride) % stride == 0 ? t.major : t.minor).push_back(v);
    }
    if (stride > 1 && decade_px < min_minor_decade_px / 5) t.minor.clear();  // would be a grey wash
    if (stride == 1 && decade_px >= min_minor_decade_px) add_minor(false);
  } else {
    // Less than two decades in view: 1-2-5 ticks, else plain round numbers.
    for (int k = k_lo; k <= k_hi; ++k)
      for (double m : {1.0, 2.0, 5.0}) {
        const double v = m * detail::pow10(k);
        if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9)) t.major.push_back(v);
      }
    if (t.major.size() < 2 || static_cast<int>(t.major.size()) > max_ticks) {
      t.major.clear();
      for (double v : nice_ticks(lo, hi, max_ticks))
        if (v > 0) t.major.push_back(v);
    }
    add_minor(true);
  }
  const bool powers =
      std::any_of(t.major.begin(), t.major.end(), [](double v) { return v < 1e-3 || v > 1e4 * 1.000001; });
  for (double v : t.major) t.labels.push_back(log_label(v, powers));
  return t;
}

// ---------------------------------------------------------------------------
// Layout

struct AxesLayout {
  cv::Rect plot;
  AxisScale x, y;
  Ticks x_ticks, y_ticks;
};

struct Layout {
  Style style;
  int title_height_px = 0;
  int y_label_x = 0;  // left edge of the rotated y labels
  std::vector<AxesLayout> axes;
};

int text_height(const Font& f) {
  const TextBox b = measure(std::string("0123456789()"), f);
  return b.ascent + b.descent;
}

Layout compute_layout(int width_px, int height_px, const std::string& title, const std::vector<Axes>& axes) {
  Layout L;
  L.style = make_style(width_px, height_px);
  const Style& st = L.style;
  const int tick_h = text_height(st.tick);
  const int tick_ascent = measure(std::string("0"), st.tick).ascent;
  const int label_h = text_height(st.label);
  const int title_h = text_height(st.title);

  L.title_height_px = title.empty() ? 0 : text_height(st.figure_title) + st.gap;
  const int top = L.title_height_px + st.gap / 2;
  const int n = static_cast<int>(axes.size());
  if (n == 0) return L;
  const int slot = (height_px - top - st.gap / 2) / n;

  // Vertical placement and y ticks (they only depend on heights).
  bool any_y_label = false;
  int widest_y_label = 0;
  L.axes.resize(axes.size());
  for (int i = 0; i < n; ++i) {
    const Axes& ax = axes[i];
    AxesLayout& al = L.axes[i];
    Range xr, yr;
    data_ranges(ax, xr, yr);
    al.x = resolve_scale(ax.x_limits, xr, ax.x_scale, "x");
    al.y = resolve_scale(ax.y_limits, yr, ax.y_scale, "y");

    const int top_pad = ax.title.empty() ? std::max(st.gap, tick_ascent) : title_h + st.gap;
    int bottom_pad = st.tick_len + st.gap / 2;
    if (ax.x_tick_labels) bottom_pad += tick_h;
    if (!ax.x_label.empty()) bottom_pad += st.gap / 2 + label_h;
    bottom_pad += st.gap / 2;
    al.plot.y = top + i * slot + top_pad;
    al.plot.height = std::max(8, slot - top_pad - bottom_pad);

    const int max_y_ticks = std::clamp(al.plot.height * 5 / (14 * tick_ascent), 2, 8);  // 2.8 digit heights apart
    al.y_ticks = al.y.log ? log_axis_ticks(al.y, max_y_ticks, al.plot.height, 20 * st.s)
                          : linear_ticks(al.y, ax.y_tick_step, max_y_ticks);
    for (const Label& l : al.y_ticks.labels) widest_y_label = std::max(widest_y_label, measure(l, st.tick).w);
    any_y_label = any_y_label || !ax.y_label.empty();
  }

  // Horizontal placement, shared by all axes, then x ticks.
  L.y_label_x = st.gap;
  const int left = st.gap + (any_y_label ? label_h + st.gap : 0) + widest_y_label + st.gap / 2 + st.tick_len;
  const int right = std::max(2 * st.gap, measure(std::string("00000"), st.tick).w / 2 + st.gap);
  const int plot_w = std::max(8, width_px - left - right);
  for (int i = 0; i < n; ++i) {
    const Axes& ax = axes[i];
    AxesLayout& al = L.axes[i];
    al.plot.x = left;
    al.plot.width = plot_w;
    al.plot &= cv::Rect(0, 0, width_px, height_px);  // only matters for absurdly crowded figures
    // As many ticks as fit with their labels at least a gap apart.
    for (int max_x = std::clamp(static_cast<int>(plot_w / (80 * st.s)), 2, 11); max_x >= 2; --max_x) {
      al.x_ticks =
          al.x.log ? log_axis_ticks(al.x, max_x, plot_w, 25 * st.s) : linear_ticks(al.x, ax.x_tick_step, max_x);
      const auto& ticks = al.x_ticks.major;
      bool fits = true;
      for (std::size_t k = 1; k < ticks.size() && fits; ++k) {
        const double dx = std::abs(al.x.fraction(ticks[k]) - al.x.fraction(ticks[k - 1])) * (plot_w - 1);
        const double need =
            (measure(al.x_ticks.labels[k], st.tick).w + measure(al.x_ticks.labels[k - 1], st.tick).w) / 2.0 + st.gap;
        fits = dx >= need;
      }
      if (fits) break;
    }
  }
  return L;
}

// ---------------------------------------------------------------------------
// Drawing

struct LegendLayout {
  cv::Rect box;  // in figure pixels; empty: no legend
  std::vector<std::size_t> entries;
  int pad = 0, sample_w = 0, row_h = 0;
};

// Box in a corner of the plot area, one row per labelled series: the top-right one
// unless another (top-left, bottom-right, bottom-left, in that order) covers fewer
// series pixels (series_ink, in plot-area coordinates; empty: top-right).
LegendLayout legend_layout(const Axes& ax, const cv::Rect& plot, const Style& st, const cv::Mat& series_ink) {
  LegendLayout g;
  for (std::size_t i = 0; i < ax.series.size(); ++i)
    if (!ax.series[i].label.empty()) g.entries.push_back(i);
  if (!ax.legend || g.entries.empty()) return g;
  g.pad = std::max(3, st.gap * 2 / 3);
  g.sample_w = round_px(30 * st.s);
  g.row_h = text_height(st.tick) + g.pad;
  int text_w = 0;
  for (std::size_t i : g.entries) text_w = std::max(text_w, measure(ax.series[i].label, st.tick).w);
  const int box_w = g.pad + g.sample_w + g.pad + text_w + g.pad;
  const int box_h = g.pad / 2 + static_cast<int>(g.entries.size()) * g.row_h + g.pad / 2;
  const int right = plot.x + plot.width - st.gap - box_w, left = plot.x + st.gap;
  const int top = plot.y + st.gap, bottom = plot.y + plot.height - st.gap - box_h;
  const cv::Rect inner(plot.x + 1, plot.y + 1, plot.width - 2, plot.height - 2);
  int best_cost = -1;
  for (const cv::Point& corner : {cv::Point(right, top), cv::Point(left, top), cv::Point(right, bottom), cv::Point(left, bottom)}) {
    cv::Rect box(std::max(corner.x, plot.x + 1), std::max(corner.y, plot.y + 1), box_w, box_h);
    box &= inner;
    const int cost = series_ink.empty() || box.empty() ? 0 : cv::countNonZero(series_ink(box - plot.tl()));
    if (best_cost < 0 || cost < best_cost) {
      g.box = box;
      best_cost = cost;
    }
    if (best_cost == 0) break;
  }
  return g;
}

void draw_legend(cv::Mat& img, const Axes& ax, const LegendLayout& g, const std::vector<cv::Scalar>& colors,
                 const Style& st) {
  if (g.box.empty()) return;
  const Font& f = st.tick;
  const int pad = g.pad, sample_w = g.sample_w, row_h = g.row_h;
  const auto& entries = g.entries;
  const cv::Rect& box = g.box;
  cv::Mat area = img(box);
  area.convertTo(area, -1, 0.12, 255 * 0.88);  // nearly opaque white
  cv::rectangle(img, box, kLegendBorder, 1, cv::LINE_8);
  cv::Mat inner = img(box);
  for (std::size_t r = 0; r < entries.size(); ++r) {
    const Series& s = ax.series[entries[r]];
    const double cy = pad / 2 + r * row_h + row_h / 2.0;
    const int thick = std::max(1, round_px(s.width_px));
    Dash dash = s.dashed ? dash_for(s.width_px, st.s) : Dash{};
    draw_segment(inner, {static_cast<double>(pad), cy}, {static_cast<double>(pad + sample_w), cy}, colors[entries[r]],
                 thick, dash);
    if (s.markers)
      cv::circle(inner, to_fixed({pad + sample_w / 2.0, cy}), round_px((thick + 2.5) * kSub), colors[entries[r]],
                 cv::FILLED, cv::LINE_AA, kShift);
    draw_text(inner, s.label, pad + sample_w + pad, cy, HAlign::Left, VAlign::Middle, f, kText);
  }
}

void draw_series(cv::Mat& area, const Series& s, const cv::Scalar& color, const AxisScale& xs, const AxisScale& ys,
                 double style_scale) {
  const int thick = std::max(1, round_px(s.width_px));
  const double marker_r = thick + 2.5;
  const double pad = thick + marker_r + 2;  // drawn beyond the area so that line ends are cut off cleanly
  const double x0 = -pad, y0 = -pad, x1 = area.cols - 1 + pad, y1 = area.rows - 1 + pad;
  const double sx = area.cols - 1, sy = area.rows - 1;
  const auto to_px = [&](std::size_t i) {
    return cv::Point2d(xs.fraction(s.x[i]) * sx, (1 - ys.fraction(s.y[i])) * sy);
  };
  const auto valid = [](const cv::Point2d& p) { return std::isfinite(p.x) && std::isfinite(p.y); };

  Dash dash = s.dashed ? dash_for(s.width_px, style_scale) : Dash{};
  bool have_prev = false;
  cv::Point2d prev;
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    const cv::Point2d p = to_px(i);
    if (!valid(p)) {
      have_prev = false;  // NaN, inf or (log axis) non-positive: break the line
      continue;
    }
    if (have_prev) {
      cv::Point2d a = prev, b = p;
      if (clip_segment(a, b, x0, y0, x1, y1)) draw_segment(area, a, b, color, thick, dash);
    }
    prev = p;
    have_prev = true;
  }
  if (s.markers) {
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      const cv::Point2d p = to_px(i);
      if (valid(p) && p.x >= x0 && p.x <= x1 && p.y >= y0 && p.y <= y1)
        cv::circle(area, to_fixed(p), round_px(marker_r * kSub), color, cv::FILLED, cv::LINE_AA, kShift);
    }
  }
}

void draw_axes(cv::Mat& img, const Axes& ax, const AxesLayout& al, const Layout& L) {
  const Style& st = L.style;
  const cv::Rect& r = al.plot;
  if (r.width < 2 || r.height < 2) return;  // no room at all
  cv::Mat area = img(r);
  const double sx = r.width - 1, sy = r.height - 1;
  const auto col_of = [&](double v) { return al.x.fraction(v) * sx; };        // relative to r.x
  const auto row_of = [&](double v) { return (1 - al.y.fraction(v)) * sy; };  // relative to r.y
  const auto inside = [](double p, double extent) { return std::isfinite(p) && p >= -0.5 && p <= extent + 0.5; };

  // Grid: minor (log axes) under major.
  const auto grid = [&](const std::vector<double>& xs, const std::vector<double>& ys, const cv::Scalar& c) {
    for (double v : xs) {
      const double p = col_of(v);
      if (inside(p, sx)) cv::line(area, {round_px(p), 0}, {round_px(p), r.height - 1}, c, 1, cv::LINE_8);
    }
    for (double v : ys) {
      const double p = row_of(v);
      if (inside(p, sy)) cv::line(area, {0, round_px(p)}, {r.width - 1, round_px(p)}, c, 1, cv::LINE_8);
    }
  };
  grid(al.x_ticks.minor, al.y_ticks.minor, kGridMinor);
  grid(al.x_ticks.major, al.y_ticks.major, kGridMajor);

  // Reference lines.
  for (double v : ax.h_lines) {
    const double p = row_of(v);
    Dash dash = dash_for(1, st.s);
    if (inside(p, sy)) draw_segment(area, {0, p}, {sx, p}, kRefColor, 1, dash);
  }
  for (double v : ax.v_lines) {
    const double p = col_of(v);
    Dash dash = dash_for(1, st.s);
    if (inside(p, sx)) draw_segment(area, {p, 0}, {p, sy}, kRefColor, 1, dash);
  }

  // Series; with notes or a legend to place, the pixels they change are remembered.
  const bool has_notes =
      std::any_of(ax.h_line_labels.begin(), ax.h_line_labels.end(), [](const std::string& t) { return !t.empty(); }) ||
      std::any_of(ax.v_line_labels.begin(), ax.v_line_labels.end(), [](const std::string& t) { return !t.empty(); });
  const bool legend_wanted =
      ax.legend && std::any_of(ax.series.begin(), ax.series.end(), [](const Series& x) { return !x.label.empty(); });
  const cv::Mat before_series = has_notes || legend_wanted ? area.clone() : cv::Mat();
  std::vector<cv::Scalar> colors;
  for (std::size_t i = 0; i < ax.series.size(); ++i) {
    const Color c = ax.series[i].color;
    colors.push_back(bgr(c.r == 0 && c.g == 0 && c.b == 0 ? palette_color(i) : c));
    draw_series(area, ax.series[i], colors.back(), al.x, al.y, st.s);
  }

  cv::Mat series_ink;  // non-zero where a series was drawn
  if (has_notes || legend_wanted) {
    cv::Mat diff;
    cv::absdiff(area, before_series, diff);
    cv::inRange(diff, cv::Scalar::all(0), cv::Scalar::all(8), series_ink);
    cv::bitwise_not(series_ink, series_ink);
  }

  // Box and outward ticks.
  for (int k = 0; k < st.box_thick; ++k)
    cv::rectangle(img, cv::Rect(r.x - k, r.y - k, r.width + 2 * k, r.height + 2 * k), kAxisColor, 1, cv::LINE_8);
  const int bottom = r.y + r.height - 1 + st.box_thick;
  const int left = r.x - st.box_thick;
  const auto x_tick = [&](double v, int len) {
    const double p = col_of(v);
    if (inside(p, sx))
      cv::line(img, {r.x + round_px(p), bottom}, {r.x + round_px(p), bottom + len - 1}, kAxisColor, st.box_thick,
               cv::LINE_8);
  };
  const auto y_tick = [&](double v, int len) {
    const double p = row_of(v);
    if (inside(p, sy))
      cv::line(img, {left - len + 1, r.y + round_px(p)}, {left, r.y + round_px(p)}, kAxisColor, st.box_thick,
               cv::LINE_8);
  };
  for (double v : al.x_ticks.major) x_tick(v, st.tick_len);
  for (double v : al.y_ticks.major) y_tick(v, st.tick_len);
  if (al.x.log)
    for (double v : al.x_ticks.minor) x_tick(v, (st.tick_len + 1) / 2);
  if (al.y.log)
    for (double v : al.y_ticks.minor) y_tick(v, (st.tick_len + 1) / 2);

  // Tick labels.
  int below = bottom + st.tick_len + st.gap / 2;
  if (ax.x_tick_labels) {
    for (std::size_t k = 0; k < al.x_ticks.major.size(); ++k) {
      const double p = col_of(al.x_ticks.major[k]);
      if (inside(p, sx))
        draw_text(img, al.x_ticks.labels[k], r.x + p, below, HAlign::Center, VAlign::Top, st.tick, kText);
    }
    below += text_height(st.tick);
  }
  for (std::size_t k = 0; k < al.y_ticks.major.size(); ++k) {
    const double p = row_of(al.y_ticks.major[k]);
    if (inside(p, sy))
      draw_text(img, al.y_ticks.labels[k], left - st.tick_len - st.gap / 2, r.y + p, HAlign::Right, VAlign::Middle,
                st.tick, kText);
  }

  // Axis labels and title.
  if (!ax.x_label.empty())
    draw_text(img, ax.x_label, r.x + r.width / 2.0, below + st.gap / 2, HAlign::Center, VAlign::Top, st.label, kText);
  draw_rotated_text(img, ax.y_label, L.y_label_x, r.y + r.height / 2, r.height, st.label);
  if (!ax.title.empty())
    draw_text(img, ax.title, r.x + r.width / 2.0, r.y - st.gap / 2 - st.box_thick, HAlign::Center, VAlign::Bottom,
              st.title, kText);

  // Reference-line notes, placed where they hide no data: candidate spots in order
  // of preference, the first that covers no series pixel and no other note, legend or
  // reference line wins (else the one covering the fewest series pixels).
  const LegendLayout legend = legend_layout(ax, r, st, series_ink);
  std::vector<cv::Rect> blocked;
  if (!legend.box.empty()) blocked.push_back(legend.box - r.tl());
  std::vector<std::pair<cv::Rect, std::size_t>> ref_rects;  // thin boxes around reference lines
  for (std::size_t k = 0; k < ax.h_lines.size(); ++k)
    ref_rects.push_back({cv::Rect(0, round_px(row_of(ax.h_lines[k])) - 1, r.width, 3), k});
  for (std::size_t k = 0; k < ax.v_lines.size(); ++k)
    ref_rects.push_back({cv::Rect(round_px(col_of(ax.v_lines[k])) - 1, 0, 3, r.height), ax.h_lines.size() + k});
  const int note_pad = 2;
  const auto place_note = [&](const std::string& text, const std::vector<cv::Point2d>& spots, std::size_t own) {
    const TextBox b = measure(text, st.note);
    const cv::Rect bounds(0, 0, r.width, r.height);
    int best = -1, best_cost = std::numeric_limits<int>::max();
    for (std::size_t i = 0; i < spots.size() && best_cost > 0; ++i) {
      const cv::Rect box(round_px(spots[i].x) - note_pad, round_px(spots[i].y) - note_pad, b.w + 2 * note_pad,
                         b.ascent + b.descent + 2 * note_pad);
      if ((box & bounds) != box) continue;
      const auto hits = [&box](const cv::Rect& o) { return !(box & o).empty(); };
      if (std::any_of(blocked.begin(), blocked.end(), hits)) continue;
      if (std::any_of(ref_rects.begin(), ref_rects.end(),
                      [&](const auto& ref) { return ref.second != own && hits(ref.first); }))
        continue;
      const int cost = series_ink.empty() ? 0 : cv::countNonZero(series_ink(box));
      if (cost < best_cost) {
        best = static_cast<int>(i);
        best_cost = cost;
      }
    }
    const cv::Point2d at = best >= 0 ? spots[best] : spots.front();
    blocked.emplace_back(round_px(at.x) - note_pad - st.gap / 2, round_px(at.y) - note_pad - st.gap / 4,
                         b.w + 2 * note_pad + st.gap, b.ascent + b.descent + 2 * note_pad + st.gap / 2);
    draw_note(area, text, at.x, at.y, HAlign::Left, VAlign::Top, st.note, kNoteColor);
  };
  const double note_w_pad = st.gap / 2.0;
  const int note_h = text_height(st.note);
  for (std::size_t k = 0; k < ax.h_lines.size() && k < ax.h_line_labels.size(); ++k) {
    const double p = row_of(ax.h_lines[k]);
    if (ax.h_line_labels[k].empty() || !inside(p, sy)) continue;
    // Above or below the line, at the right end, then at the left end.
    const double w = measure(ax.h_line_labels[k], st.note).w;
    const double above = p - st.gap / 2.0 - note_h, below = p + st.gap / 2.0;
    const double right = sx - note_w_pad - w, left = note_w_pad;
    place_note(ax.h_line_labels[k], {{right, above}, {right, below}, {left, above}, {left, below}}, k);
  }
  for (std::size_t k = 0; k < ax.v_lines.size() && k < ax.v_line_labels.size(); ++k) {
    const double p = col_of(ax.v_lines[k]);
    if (ax.v_line_labels[k].empty() || !inside(p, sx)) continue;
    // Beside the line (right, then left), near the top row by row, then near the bottom.
    const double w = measure(ax.v_line_labels[k], st.note).w;
    const double step = note_h + 2 * note_pad + 2;
    std::vector<cv::Point2d> spots;
    for (int row = 0; row < 4; ++row)
      for (double x : {p + note_w_pad, p - note_w_pad - w}) spots.emplace_back(x, st.gap / 2.0 + row * step);
    for (int row = 0; row < 4; ++row)
      for (double x : {p + note_w_pad, p - note_w_pad - w})
        spots.emplace_back(x, sy - st.gap / 2.0 - note_h - row * step);
    place_note(ax.v_line_labels[k], spots, ax.h_lines.size() + k);
  }

  draw_legend(img, ax, legend, colors, st);
}

}  // namespace

std::pair<double, double> nice_limits(double lo, double hi, Scale scale) {
  if (!std::isfinite(lo) || !std::isfinite(hi))
    throw std::invalid_argument(fmt::format("viz: cannot choose limits for data from {} to {}", lo, hi));
  if (lo > hi) std::swap(lo, hi);
  if (scale == Scale::Log) {
    if (!(lo > 0)) throw std::invalid_argument(fmt::format("viz: log-axis limits need positive data, got {}", lo));
    int k0 = static_cast<int>(std::floor(std::log10(lo) + 1e-9));
    int k1 = static_cast<int>(std::ceil(std::log10(hi) - 1e-9));
    if (k1 <= k0) {
      --k0;
      ++k1;
    }
    return {detail::pow10(k0), detail::pow10(k1)};
  }
  if (lo == hi) {
    const double d = lo == 0 ? 1.0 : 0.1 * std::abs(lo);
    lo -= d;
    hi += d;
  }
  const double range = hi - lo;
  const double padded_lo = lo - 0.03 * range, padded_hi = hi + 0.03 * range;
  const double step = detail::nice_step(padded_hi - padded_lo, 39);
  if (step == 0) return {padded_lo, padded_hi};
  return {detail::multiple_of(std::floor(padded_lo / step), step),
          detail::multiple_of(std::ceil(padded_hi / step), step)};
}

cv::Rect Figure::plot_area(std::size_t index) const {
  if (index >= axes().size())
    throw std::out_of_range(fmt::format("viz: axes index {} out of range (figure has {})", index, axes().size()));
  return compute_layout(width_px(), height_px(), title, axes()).axes[index].plot;
}

cv::Mat Figure::render() const {
  const Layout L = compute_layout(width_px(), height_px(), title, axes());
  cv::Mat img(height_px(), width_px(), CV_8UC3, kWhite);
  for (std::size_t i = 0; i < axes().size(); ++i) draw_axes(img, axes()[i], L.axes[i], L);
  if (!title.empty()) {
    // Centred over the plot areas when there are any, else over the figure.
    const double cx = L.axes.empty() ? width_px() / 2.0 : L.axes[0].plot.x + L.axes[0].plot.width / 2.0;
    draw_text(img, title, cx, L.style.gap * 0.8, HAlign::Center, VAlign::Top, L.style.figure_title, kText);
  }
  return img;
}

}  // namespace dmbd::viz
