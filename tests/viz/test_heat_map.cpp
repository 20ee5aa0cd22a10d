// Heat maps (viz/heat_map.hpp): the colour map, cells in their colours at their places,
// equal aspect, the colour bar from vmin to vmax, its title and the axes' labels drawn,
// and bad descriptions refused.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>

#include "dmbd/viz/heat_map.hpp"
#include "viz_test_support.hpp"

namespace dmbd::viz {
namespace {

cv::Vec3b bgr(Color c) { return {c.b, c.g, c.r}; }

// Matplotlib's viridis at 0, 0.5 and 1 (its table, rounded to 8 bits).
TEST(HeatMap, ColourMapIsViridisClampedAndNanIsTheLowEnd) {
  const auto same = [](Color a, Color b) { return a.r == b.r && a.g == b.g && a.b == b.b; };
  EXPECT_TRUE(same(heat_color(0), {68, 1, 84}));
  EXPECT_TRUE(same(heat_color(0.5), {33, 144, 141}));
  EXPECT_TRUE(same(heat_color(1), {253, 231, 37}));
  EXPECT_TRUE(same(heat_color(-3), heat_color(0)));
  EXPECT_TRUE(same(heat_color(7), heat_color(1)));
  EXPECT_TRUE(same(heat_color(std::nan("")), heat_color(0)));
  // Between table entries: linear (t = 1/16 is half way between 0 and 1/8).
  const Color c = heat_color(1.0 / 16);
  EXPECT_EQ(c.r, 70);   // (68 + 71) / 2 = 69.5, rounded away from zero
  EXPECT_EQ(c.g, 23);   // (1 + 44) / 2 = 22.5
  EXPECT_EQ(c.b, 103);  // (84 + 122) / 2
}

HeatMap known_map() {
  HeatMap m;
  m.cols = 3, m.rows = 2;
  m.x0 = -0.1, m.y0 = -0.9, m.cell_w = m.cell_h = 0.1;
  m.values = {0, 0.5, 1, 0.25, 0.75, 2};  // bottom row first; 2 is clamped to the top colour
  m.title = "known";
  m.x_label = "x (m)";
  m.y_label = "z (m)";
  m.colorbar_label = "density score";
  return m;
}

// Each cell's centre pixel is exactly its colour (cells are filled without smoothing),
// an empty cell (value <= vmin) stays white, rows count from the bottom.
TEST(HeatMap, KnownDensityRendersEachCellInItsColourAtItsPlace) {
  const HeatMap m = known_map();
  const cv::Mat img = render_heat_map(m, 800, 600);
  const HeatMapLayout L = heat_map_layout(m, 800, 600);
  ASSERT_EQ(img.cols, 800);
  ASSERT_EQ(img.rows, 600);
  for (int r = 0; r < m.rows; ++r)
    for (int c = 0; c < m.cols; ++c) {
      const int x = L.plot.x + static_cast<int>((c + 0.5) * L.plot.width / m.cols);
      const int y = L.plot.y + L.plot.height - 1 - static_cast<int>((r + 0.5) * L.plot.height / m.rows);
      const double v = m.values[static_cast<std::size_t>(r * m.cols + c)];
      const cv::Vec3b want = v > 0 ? bgr(heat_color(v)) : cv::Vec3b(255, 255, 255);
      EXPECT_EQ(img.at<cv::Vec3b>(y, x), want) << "cell row " << r << " col " << c;
    }
  // Equal aspect: square cells are square on screen (within a pixel of rounding).
  EXPECT_NEAR(L.plot.width / 3.0, L.plot.height / 2.0, 1.0);
  HeatMap tall = m;
  tall.cell_h = 0.2;
  const HeatMapLayout T = heat_map_layout(tall, 800, 600);
  EXPECT_NEAR(T.plot.height / 2.0, 2 * T.plot.width / 3.0, 1.5);
}

// The bar runs from heat_color(1) at its top row to heat_color(0) at its bottom row, the
// middle row at 0.5 (within one 8-bit step of rounding); its title and tick labels put
// dark pixels right of it, and the axes' labels and ticks below and left of the cells.
TEST(HeatMap, ColourBarSpansTheMapWithATitleAndTheAxesAreLabelled) {
  const HeatMap m = known_map();
  const cv::Mat img = render_heat_map(m, 800, 600);
  const cv::Rect b = heat_map_layout(m, 800, 600).colorbar;
  const int cx = b.x + b.width / 2;
  EXPECT_EQ(img.at<cv::Vec3b>(b.y, cx), bgr(heat_color(1)));
  EXPECT_EQ(img.at<cv::Vec3b>(b.y + b.height - 1, cx), bgr(heat_color(0)));
  const cv::Vec3b mid = img.at<cv::Vec3b>(b.y + (b.height - 1) / 2, cx), want = bgr(heat_color(0.5));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(mid[k], want[k], 2) << k;
  const auto dark_pixels = [&](const cv::Mat& image, cv::Rect r) {
    r &= cv::Rect(0, 0, image.cols, image.rows);
    int n = 0;
    for (int y = r.y; y < r.y + r.height; ++y)
      for (int x = r.x; x < r.x + r.width; ++x) {
        const cv::Vec3b p = image.at<cv::Vec3b>(y, x);
        n += p[0] < 100 && p[1] < 100 && p[2] < 100;
      }
    return n;
  };
  const cv::Rect right_of_bar(b.x + b.width + 2, b.y, 800 - b.x - b.width - 2, b.height);
  HeatMap untitled = m;
  untitled.colorbar_label.clear();
  const int with_title = dark_pixels(img, right_of_bar);
  const int without_title = dark_pixels(render_heat_map(untitled, 800, 600), right_of_bar);
  EXPECT_GT(without_title, 20);                 // the tick labels 0 ... 1
  EXPECT_GT(with_title, without_title + 100);  // and the title
  const cv::Rect p = heat_map_layout(m, 800, 600).plot;
  EXPECT_GT(dark_pixels(img, cv::Rect(p.x, p.y + p.height + 2, p.width, 60)), 50);  // x ticks and label
  EXPECT_GT(dark_pixels(img, cv::Rect(0, p.y, p.x - 2, p.height)), 50);              // y ticks and label
}

TEST(HeatMap, BadDescriptionsAreRefused) {
  HeatMap m = known_map();
  m.values.pop_back();
  EXPECT_THROW(render_heat_map(m, 800, 600), std::invalid_argument);
  m = known_map();
  m.vmax = m.vmin;
  EXPECT_THROW(render_heat_map(m, 800, 600), std::invalid_argument);
  m = known_map();
  m.cell_w = 0;
  EXPECT_THROW(render_heat_map(m, 800, 600), std::invalid_argument);
  EXPECT_THROW(render_heat_map(known_map(), 100, 600), std::invalid_argument);
}

TEST(HeatMap, SavedPngReadsBackAsTheRenderedImage) {
  test::TempDir dir("dmbd_heat_map");
  save_heat_map_png(known_map(), 640, 480, dir / "map.png");
  const cv::Mat back = cv::imread(dir / "map.png", cv::IMREAD_COLOR);
  ASSERT_FALSE(back.empty());
  EXPECT_EQ(cv::norm(back, render_heat_map(known_map(), 640, 480), cv::NORM_INF), 0);
}

}  // namespace
}  // namespace dmbd::viz
