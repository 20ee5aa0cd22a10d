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

#include "dmbd/base/figure.hpp"

namespace dmbd::viz {

// The description types are dmbd::plot's (dmbd/base/figure.hpp); viz draws them.
using Color = plot::Color;
using Scale = plot::Scale;
using Series = plot::Series;
using Axes = plot::Axes;

// A plot description that can draw itself.
class Figure : public plot::Figure {
 public:
  using plot::Figure::Figure;
  explicit Figure(const plot::Figure& description) : plot::Figure(description) {}

  // BGR 8-bit image of width_px x height_px. Throws std::invalid_argument when a
  // series has x and y of different lengths, or when given limits are not finite,
  // empty, or not positive on a log axis.
  cv::Mat render() const;

  // Write a PNG atomically: encode in memory, write "<path>.tmp", then rename.
  // Throws OutputError naming the path on failure (nothing is left behind).
  void save_png(const std::string& path) const;

  // Pixel rectangle of the plot area (inside the axis box) of axes()[index] as
  // render() lays it out; the data limits map onto its first and last pixel
  // rows/columns. Throws std::out_of_range for a bad index.
  cv::Rect plot_area(std::size_t index) const;
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
// PNG bytes of an image: 8-bit grey, BGR or BGRA by libdeflate (src/png.cpp), other
// depths by OpenCV. Throws std::runtime_error for an empty image or one that cannot be
// encoded.
std::vector<unsigned char> encode_png(const cv::Mat& image);

}  // namespace dmbd::viz
