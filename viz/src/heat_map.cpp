// Heat maps: cells filled in viridis (no anti-aliasing, so a cell is exactly its colour),
// axes in data units with equal aspect, and a titled colour bar.
#include "dmbd/viz/heat_map.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "dmbd/base/file.hpp"

namespace dmbd::viz {

namespace {

const cv::Scalar kWhite(255, 255, 255);
const cv::Scalar kText(25, 25, 25);
const cv::Scalar kFrame(50, 50, 50);
constexpr int kFace = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kTickScale = 0.5, kLabelScale = 0.58;
constexpr int kLeft = 95, kRight = 150, kTop = 50, kBottom = 75, kBarGap = 25, kBarWidth = 26;

int round_px(double v) { return static_cast<int>(std::lround(v)); }

// Text whose box has (x, y) at a fraction align_x of its width from the left and
// align_y of its cap height from the top.
void put(cv::Mat& img, const std::string& s, double x, double y, double align_x, double align_y, double scale) {
  int base = 0;
  const cv::Size sz = cv::getTextSize(s, kFace, scale, 1, &base);
  cv::putText(img, s, {round_px(x - align_x * sz.width), round_px(y + (1 - align_y) * sz.height)}, kFace, scale,
              kText, 1, cv::LINE_AA);
}

// Text reading bottom to top, centred on (x_center, y_center).
void put_vertical(cv::Mat& img, const std::string& s, int x_center, int y_center, double scale) {
  if (s.empty()) return;
  int base = 0;
  const cv::Size sz = cv::getTextSize(s, kFace, scale, 1, &base);
  cv::Mat flat(sz.height + base + 4, sz.width + 4, CV_8UC3, kWhite), turned;
  cv::putText(flat, s, {2, 2 + sz.height}, kFace, scale, kText, 1, cv::LINE_AA);
  cv::rotate(flat, turned, cv::ROTATE_90_COUNTERCLOCKWISE);
  const cv::Rect dst(x_center - turned.cols / 2, y_center - turned.rows / 2, turned.cols, turned.rows);
  const cv::Rect vis = dst & cv::Rect(0, 0, img.cols, img.rows);
  if (vis.empty()) return;
  cv::Mat target = img(vis);
  cv::min(target, turned(vis - dst.tl()), target);
}

void check(const HeatMap& m, int width_px, int height_px) {
  if (m.rows < 1 || m.cols < 1 || m.values.size() != static_cast<std::size_t>(m.rows) * m.cols)
    throw std::invalid_argument(fmt::format("viz: heat map of {} x {} cells has {} values", m.rows, m.cols,
                                            m.values.size()));
  if (!(m.cell_w > 0) || !(m.cell_h > 0) || !std::isfinite(m.cell_w) || !std::isfinite(m.cell_h) ||
      !std::isfinite(m.x0) || !std::isfinite(m.y0))
    throw std::invalid_argument(fmt::format("viz: heat map cells of {} x {} at ({}, {}) are not positive and finite",
                                            m.cell_w, m.cell_h, m.x0, m.y0));
  if (!(m.vmin < m.vmax) || !std::isfinite(m.vmin) || !std::isfinite(m.vmax))
    throw std::invalid_argument(fmt::format("viz: heat map colour range [{}, {}] is empty", m.vmin, m.vmax));
  if (width_px < 200 || height_px < 150)
    throw std::invalid_argument(fmt::format("viz: heat map image {} x {} px is too small (200 x 150)", width_px,
                                            height_px));
}

cv::Scalar bgr(Color c) { return {static_cast<double>(c.b), static_cast<double>(c.g), static_cast<double>(c.r)}; }

}  // namespace

Color heat_color(double t) {
  static constexpr unsigned char kViridis[9][3] = {{68, 1, 84},    {71, 44, 122},  {59, 81, 139},
                                                   {44, 113, 142}, {33, 144, 141}, {39, 173, 129},
                                                   {92, 200, 99},  {170, 220, 50}, {253, 231, 37}};
  t = std::isnan(t) ? 0.0 : std::clamp(t, 0.0, 1.0);
  const double s = t * 8;
  const int i = std::min(7, static_cast<int>(s));
  const double f = s - i;
  const auto mix = [&](int k) {
    return static_cast<unsigned char>(std::lround(kViridis[i][k] + f * (kViridis[i + 1][k] - kViridis[i][k])));
  };
  return {mix(0), mix(1), mix(2)};
}

HeatMapLayout heat_map_layout(const HeatMap& m, int width_px, int height_px) {
  check(m, width_px, height_px);
  const double aw = width_px - kLeft - kRight, ah = height_px - kTop - kBottom;
  const double dw = m.cols * m.cell_w, dh = m.rows * m.cell_h;
  const double px_per_unit = std::min(aw / dw, ah / dh);
  const int pw = std::max(m.cols, round_px(dw * px_per_unit)), ph = std::max(m.rows, round_px(dh * px_per_unit));
  HeatMapLayout L;
  L.plot = cv::Rect(kLeft + round_px((aw - pw) / 2), kTop + round_px((ah - ph) / 2), pw, ph);
  L.colorbar = cv::Rect(L.plot.x + pw + kBarGap, L.plot.y, kBarWidth, ph);
  return L;
}

cv::Mat render_heat_map(const HeatMap& m, int width_px, int height_px) {
  const HeatMapLayout L = heat_map_layout(m, width_px, height_px);
  cv::Mat img(height_px, width_px, CV_8UC3, kWhite);
  const cv::Rect& p = L.plot;
  // Cells: column c spans [floor(c w / cols), floor((c + 1) w / cols)), rows from the bottom.
  const auto edge = [](int k, int px, int n) { return static_cast<int>(static_cast<long>(k) * px / n); };
  for (int r = 0; r < m.rows; ++r)
    for (int c = 0; c < m.cols; ++c) {
      const double v = m.values[static_cast<std::size_t>(r) * m.cols + c];
      if (m.empty_below_min && !(v > m.vmin)) continue;
      const int x0 = p.x + edge(c, p.width, m.cols), x1 = p.x + edge(c + 1, p.width, m.cols);
      const int y1 = p.y + p.height - edge(r, p.height, m.rows), y0 = p.y + p.height - edge(r + 1, p.height, m.rows);
      cv::rectangle(img, cv::Rect(x0, y0, x1 - x0, y1 - y0), bgr(heat_color((v - m.vmin) / (m.vmax - m.vmin))),
                    cv::FILLED);
    }
  // Axes: a frame, outward ticks in data units, labels.
  cv::rectangle(img, cv::Rect(p.x - 1, p.y - 1, p.width + 2, p.height + 2), kFrame, 1);
  const double dw = m.cols * m.cell_w, dh = m.rows * m.cell_h;
  for (double v : nice_ticks(m.x0, m.x0 + dw, std::max(2, p.width / 70))) {
    const int x = p.x + round_px((v - m.x0) / dw * (p.width - 1));
    cv::line(img, {x, p.y + p.height}, {x, p.y + p.height + 5}, kFrame, 1);
    put(img, format_tick(v), x, p.y + p.height + 10, 0.5, 0, kTickScale);
  }
  int widest = 0;
  for (double v : nice_ticks(m.y0, m.y0 + dh, std::max(2, p.height / 50))) {
    const int y = p.y + p.height - 1 - round_px((v - m.y0) / dh * (p.height - 1));
    cv::line(img, {p.x - 6, y}, {p.x - 1, y}, kFrame, 1);
    put(img, format_tick(v), p.x - 10, y, 1, 0.5, kTickScale);
    int base = 0;
    widest = std::max(widest, cv::getTextSize(format_tick(v), kFace, kTickScale, 1, &base).width);
  }
  put(img, m.x_label, p.x + p.width / 2.0, p.y + p.height + 36, 0.5, 0, kLabelScale);
  put_vertical(img, m.y_label, std::max(12, p.x - 22 - widest), p.y + p.height / 2, kLabelScale);
  put(img, m.title, width_px / 2.0, 14, 0.5, 0, kLabelScale + 0.07);
  // Colour bar: vmax at the top row, vmin at the bottom row; its ticks and title.
  const cv::Rect& b = L.colorbar;
  for (int i = 0; i < b.height; ++i) {
    const double t = b.height > 1 ? 1.0 - static_cast<double>(i) / (b.height - 1) : 1.0;
    cv::line(img, {b.x, b.y + i}, {b.x + b.width - 1, b.y + i}, bgr(heat_color(t)), 1);
  }
  cv::rectangle(img, cv::Rect(b.x - 1, b.y - 1, b.width + 2, b.height + 2), kFrame, 1);
  int bar_widest = 0;
  for (double v : nice_ticks(m.vmin, m.vmax, std::max(2, b.height / 50))) {
    const int y = b.y + b.height - 1 - round_px((v - m.vmin) / (m.vmax - m.vmin) * (b.height - 1));
    cv::line(img, {b.x + b.width, y}, {b.x + b.width + 4, y}, kFrame, 1);
    put(img, format_tick(v), b.x + b.width + 8, y, 0, 0.5, kTickScale);
    int base = 0;
    bar_widest = std::max(bar_widest, cv::getTextSize(format_tick(v), kFace, kTickScale, 1, &base).width);
  }
  put_vertical(img, m.colorbar_label, b.x + b.width + 22 + bar_widest, b.y + b.height / 2, kLabelScale);
  return img;
}

void save_heat_map_png(const HeatMap& map, int width_px, int height_px, const std::string& path) {
  dmbd::write_file_atomic(path, encode_png(render_heat_map(map, width_px, height_px)));
}

}  // namespace dmbd::viz
