#pragma once
// A plot as data: stacked axes of line series, labels, scales, limits and reference
// lines, with no drawing in it. The analyses that decide what to show (sim's
// experiments, dmbd analyze) fill one in; dmbd::viz draws it (viz::Figure adds
// render() and save_png()); report/ puts it on a page. Sizes are in pixels of the
// image it will be drawn as (suffix _px).
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace dmbd::plot {

// 8-bit RGB. {0, 0, 0} in a Series means "automatic" (use {1, 1, 1} for black).
struct Color {
  unsigned char r = 0, g = 0, b = 0;
};

// The automatic series colours (matplotlib's tab10), cycling every 10: give a series
// palette_color(k) explicitly to keep one colour per variant across figures.
inline Color palette_color(std::size_t index) {
  static constexpr Color kTab10[] = {{31, 119, 180}, {255, 127, 14},  {44, 160, 44},   {214, 39, 40},  {148, 103, 189},
                                     {140, 86, 75},  {227, 119, 194}, {127, 127, 127}, {188, 189, 34}, {23, 190, 207}};
  return kTab10[index % 10];
}

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
  // Automatic y limits from the points inside x_limits only (a window of a longer run).
  bool y_limits_from_visible = false;
  std::vector<Series> series;
  std::vector<double> h_lines, v_lines;  // thin dashed reference lines (e.g. -180 deg, a crossover frequency)
  bool legend = true;  // in the top-right corner, or the first of top-left, bottom-right, bottom-left covering fewer series pixels
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
  Figure(int width_px = 1000, int height_px = 700) : width_px_(width_px), height_px_(height_px) {
    if (width_px < 64 || height_px < 64)
      throw std::invalid_argument("figure size " + std::to_string(width_px) + " x " + std::to_string(height_px) +
                                  " px is too small (at least 64 x 64)");
    axes_.reserve(8);
  }

  // Axes are stacked vertically, equal heights, sharing the figure width. The
  // returned reference is invalidated by a later add_axes() beyond 8 axes; index
  // axes() when in doubt.
  Axes& add_axes() { return axes_.emplace_back(); }
  std::vector<Axes>& axes() { return axes_; }
  const std::vector<Axes>& axes() const { return axes_; }
  int width_px() const { return width_px_; }
  int height_px() const { return height_px_; }

  std::string title;  // optional figure title on top

 private:
  int width_px_, height_px_;
  std::vector<Axes> axes_;
};

}  // namespace dmbd::plot
