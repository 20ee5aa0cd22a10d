#pragma once
// A heat map: values on a grid of equal cells drawn in a colour map (viridis), with axes
// ticked in data units, one data unit as long on both axes (equal aspect), and a colour
// bar with its own title. Used for the workspace density maps (`dmbd model workspace`).
//
//   dmbd::viz::HeatMap map;
//   map.cols = 3; map.rows = 2; map.x0 = -0.1; map.y0 = -0.9; map.cell_w = map.cell_h = 0.02;
//   map.values = {0, 0.5, 1,  0.25, 0, 0.75};   // row 0 (bottom) first
//   map.x_label = "x (m)"; map.y_label = "z (m)"; map.colorbar_label = "density score";
//   dmbd::viz::save_heat_map_png(map, 900, 700, "xz.png");
//
// Values at or below `vmin` are "empty" when `empty_below_min` is set and drawn in the
// background colour; others map linearly from [vmin, vmax] onto the colour map (clamped).
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "dmbd/viz/plot.hpp"  // Color

namespace dmbd::viz {

struct HeatMap {
  std::string title, x_label, y_label, colorbar_label;
  double x0 = 0, y0 = 0;          // lower-left corner of cell (row 0, column 0), data units
  double cell_w = 1, cell_h = 1;  // cell size, data units (> 0)
  int cols = 0, rows = 0;
  std::vector<double> values;  // rows x cols, row-major, row 0 at the bottom (y0)
  double vmin = 0, vmax = 1;   // colour-map range (vmin < vmax)
  bool empty_below_min = true;
};

// Viridis at t in [0, 1] (clamped; NaN gives t = 0): linear interpolation between the
// map's values at multiples of 1/8 (t = 0: (68, 1, 84), t = 1: (253, 231, 37)).
Color heat_color(double t);

// Where render_heat_map puts the cells and the colour bar in an image of the size given:
// `plot` is the cells' rectangle (column c covers plot.x + [c, c+1) * plot.width / cols,
// row r, counted from the bottom, the same upward from plot.y + plot.height); `colorbar`
// goes from vmax at its top row to vmin at its bottom row.
struct HeatMapLayout {
  cv::Rect plot, colorbar;
};

// Throws std::invalid_argument when values.size() != rows * cols, rows or cols < 1, a
// cell size is not positive and finite, vmin >= vmax, or the image is smaller than
// 200 x 150 px.
HeatMapLayout heat_map_layout(const HeatMap& map, int width_px, int height_px);

// BGR 8-bit image of the map, its axes, ticks, labels, title and colour bar.
cv::Mat render_heat_map(const HeatMap& map, int width_px, int height_px);

// Writes the PNG atomically (dmbd::write_file_atomic); throws OutputError naming the path.
void save_heat_map_png(const HeatMap& map, int width_px, int height_px, const std::string& path);

}  // namespace dmbd::viz
