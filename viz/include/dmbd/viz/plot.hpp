#pragma once
// 2-D line plots rendered with OpenCV: linear/log axes, stacked axes sharing the
// figure width, legends, reference lines, and the Bode / step figures used by
// `dmbd analyze`. Everything is in pixels of the output image (suffix _px).
//
//   dmbd::viz::Figure fig(1000, 700);
//   auto& ax = fig.add_axes();
//   ax.x_label = "Time (s)";
//   ax.y_label = "Position (rad)";
//   ax.series.push_back({"q1", t_s, q1_rad});
//   fig.save_png("q1.png");
//
// Rendering is a pure function of the description: `render()` is const and
// `save_png()` writes "<path>.tmp" and renames it, so an interrupted run never
// leaves a half-written PNG.
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

namespace dmbd::viz {

// 8-bit RGB. {0, 0, 0} in a Series means "automatic" (use {1, 1, 1} for black).
struct Color {
  unsigned char r = 0, g = 0, b = 0;
};

enum class Scale { Linear, Log };

struct Series {
  std::string label;         // empty: not in legend
  std::vector<double> x, y;  // same length; NaN/inf points break the line
  Color color{};             // {0,0,0} => auto colour from a palette (tab10-like) by index
  double width_px = 2.0;
  bool dashed = false;
  bool markers = false;  // draw small circles at the points
};

struct Axes {
  std::string title, x_label, y_label;  // labels carry units, e.g. "Frequency (Hz)"
  Scale x_scale = Scale::Linear, y_scale = Scale::Linear;
  // Automatic when empty: nice round limits with a small margin on linear axes,
  // whole decades on log axes (non-positive values are ignored there).
  std::optional<std::pair<double, double>> x_limits, y_limits;
  std::vector<Series> series;
  std::vector<double> h_lines, v_lines;  // thin dashed reference lines (e.g. -180 deg, a crossover frequency)
  bool legend = true;  // in the top-right corner, or the first of top-left, bottom-right, bottom-left covering fewer series pixels

  // Additions.
  // Optional text beside the reference line of the same index (empty or missing:
  // none), put where it hides no series, other note, line or the legend if it can:
  // h-line text above or below the line at its right, else left, end; v-line text
  // right or left of the line near the top, else near the bottom.
  std::vector<std::string> h_line_labels, v_line_labels;
  // Linear axes only: major ticks at multiples of this step (doubled until they fit)
  // instead of the automatic 1-2-5 steps; e.g. 45 for a phase axis in degrees.
  std::optional<double> x_tick_step, y_tick_step;
  // False hides the numbers under the x axis (the ticks and grid stay): for the upper
  // axes of a stack that shares its x axis with the one below.
  bool x_tick_labels = true;
};

class Figure {
 public:
  // Throws std::invalid_argument unless both sizes are at least 64 px.
  Figure(int width_px = 1000, int height_px = 700);

  // Axes are stacked vertically, equal heights, sharing the figure width. The
  // returned reference is invalidated by a later add_axes() beyond 8 axes; index
  // axes() when in doubt.
  Axes& add_axes();
  std::vector<Axes>& axes();
  const std::vector<Axes>& axes() const;

  std::string title;  // optional figure title on top

  // BGR 8-bit image of width_px x height_px. Throws std::invalid_argument when a
  // series has x and y of different lengths, or when given limits are not finite,
  // empty, or not positive on a log axis.
  cv::Mat render() const;

  // Write a PNG atomically: encode in memory, write "<path>.tmp", then rename.
  // Throws std::runtime_error naming the path on failure (nothing is left behind).
  void save_png(const std::string& path) const;

  // Additions.
  int width_px() const { return width_px_; }
  int height_px() const { return height_px_; }
  // Pixel rectangle of the plot area (inside the axis box) of axes()[index] as
  // render() lays it out; the data limits map onto its first and last pixel
  // rows/columns. Throws std::out_of_range for a bad index.
  cv::Rect plot_area(std::size_t index) const;

 private:
  int width_px_, height_px_;
  std::vector<Axes> axes_;
};

// Convenience used by `dmbd analyze`: magnitude (dB) over phase (deg) on a shared
// log frequency axis in Hz, a 0 dB and a -180 deg line, and dashed vertical lines at
// the crossover frequencies when given.
Figure bode_figure(const std::vector<double>& freq_hz, const std::vector<double>& mag_db,
                   const std::vector<double>& phase_deg, const std::string& title,
                   std::optional<double> gain_crossover_hz = {}, std::optional<double> phase_crossover_hz = {});
// Response against time in s, with a dashed horizontal line at the final value.
Figure step_figure(const std::vector<double>& t_s, const std::vector<double>& y, const std::string& title,
                   std::optional<double> final_value = {}, const std::string& y_label = "Output");

// Round numbers: the multiples of a 1, 2 or 5 x 10^k step within [lo, hi], strictly
// increasing, with the finest such step that gives at most max(max_ticks, 2) of them
// (nice_ticks(0, 1, 6) == {0, 0.2, 0.4, 0.6, 0.8, 1}). {lo} when lo == hi; empty
// when either bound is not finite.
std::vector<double> nice_ticks(double lo, double hi, int max_ticks);
// Decades (10^k) within [lo, hi], lo > 0 (empty otherwise).
std::vector<double> log_ticks(double lo, double hi);
// Compact label: up to 6 significant digits, trailing zeros removed ("0.5", "-180",
// "1000", "0.001"); exponent form without padding below 1e-4 and from 1e5 on
// ("1e5", "2.5e-6"). 0 and -0 give "0".
std::string format_tick(double value);

// Additions.
// The automatic limits render() uses for data spanning [lo, hi] (lo <= hi, finite;
// positive on a log scale): on a linear scale the range padded by 3% and rounded
// outward to a round step of about a fortieth of it ([0, 1] -> [-0.05, 1.05]), a
// single value widened by 10% of itself (or by 1 if it is 0); on a log scale whole
// decades (a single decade value widened by one decade each way).
std::pair<double, double> nice_limits(double lo, double hi, Scale scale);
// The tab10-like palette used for automatic series colours (cycles every 10).
Color palette_color(std::size_t index);
// PNG bytes of an image (throws std::runtime_error if OpenCV cannot encode it).
std::vector<unsigned char> encode_png(const cv::Mat& image);
// Write bytes atomically to path via "<path>.tmp" and a rename; throws
// std::runtime_error naming the path on failure and removes the .tmp file.
void write_file_atomic(const std::string& path, const std::vector<unsigned char>& bytes);

}  // namespace dmbd::viz
