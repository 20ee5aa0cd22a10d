// Tests for dmbd::viz plots: tick placement and labels, automatic limits, what lands
// where in a rendered image, and atomic PNG output.
#include "dmbd/viz/plot.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace dmbd::viz {
namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr Color kRed{230, 0, 0};

// Pixels that are not (nearly) white.
int count_non_white(const cv::Mat& img) {
  cv::Mat white;
  cv::inRange(img, cv::Scalar(245, 245, 245), cv::Scalar(255, 255, 255), white);
  return static_cast<int>(img.total()) - cv::countNonZero(white);
}

// Saturated red (BGR), as drawn by a kRed series including its anti-aliased core;
// nothing else in these figures is red.
cv::Mat red_mask(const cv::Mat& img) {
  cv::Mat mask;
  cv::inRange(img, cv::Scalar(0, 0, 170), cv::Scalar(110, 110, 255), mask);
  return mask;
}

// One axes on [0, 1] x [0, 1] with the given series, no legend.
Figure unit_figure(Series s, int width_px = 640, int height_px = 480) {
  Figure fig(width_px, height_px);
  Axes& ax = fig.add_axes();
  ax.x_limits = std::make_pair(0.0, 1.0);
  ax.y_limits = std::make_pair(0.0, 1.0);
  ax.legend = false;
  ax.series.push_back(std::move(s));
  return fig;
}

// Column of the plot area at data x in [0, 1] (x limits [0, 1]).
int column_at(const cv::Rect& area, double x) { return area.x + static_cast<int>(std::lround(x * (area.width - 1))); }

TEST(NiceTicks, UnitRangeInFifths) {
  const std::vector<double> expected = {0, 0.2, 0.4, 0.6, 0.8, 1.0};
  const auto ticks = nice_ticks(0, 1, 6);
  ASSERT_EQ(ticks.size(), expected.size());
  // Each tick is computed as (k * m) / 10^e, i.e. rounded once: exactly the literal.
  for (std::size_t i = 0; i < ticks.size(); ++i) EXPECT_EQ(ticks[i], expected[i]) << "tick " << i;
}

TEST(NiceTicks, RoundStepsCoveringTheRange) {
  struct Case {
    double lo, hi;
    int max_ticks;
  };
  for (const Case c : {Case{-3.7, 12.2, 8}, Case{0.001, 0.0137, 5}, Case{-180, 0, 9}, Case{1e6, 1.0003e6, 6},
                       Case{-1, -0.5, 4}, Case{0, 86.5, 7}, Case{-0.013, 0.013, 11}}) {
    SCOPED_TRACE(testing::Message() << "[" << c.lo << ", " << c.hi << "] max " << c.max_ticks);
    const auto t = nice_ticks(c.lo, c.hi, c.max_ticks);
    ASSERT_GE(t.size(), 2u);
    ASSERT_LE(t.size(), static_cast<std::size_t>(c.max_ticks));
    const double step = t[1] - t[0];
    const double tol = 1e-9 * step;  // rounding of k * step
    for (std::size_t i = 1; i < t.size(); ++i) {
      EXPECT_GT(t[i], t[i - 1]);
      EXPECT_NEAR(t[i] - t[i - 1], step, tol);
    }
    EXPECT_GE(t.front(), c.lo - tol);
    EXPECT_LE(t.back(), c.hi + tol);
    // Covers the range: no room for another tick at either end.
    EXPECT_LT(t.front() - c.lo, step);
    EXPECT_LT(c.hi - t.back(), step);
    // The step is 1, 2 or 5 x 10^k and the ticks are multiples of it.
    const double mantissa = step / std::pow(10.0, std::floor(std::log10(step)));
    EXPECT_TRUE(std::abs(mantissa - 1) < 1e-9 || std::abs(mantissa - 2) < 1e-9 || std::abs(mantissa - 5) < 1e-9)
        << "step " << step;
    for (double v : t) EXPECT_NEAR(v / step, std::round(v / step), 1e-6) << v;
  }
}

TEST(NiceTicks, DegenerateInputs) {
  EXPECT_EQ(nice_ticks(2.5, 2.5, 5), std::vector<double>{2.5});
  EXPECT_EQ(nice_ticks(1, 0, 6), nice_ticks(0, 1, 6));
  EXPECT_TRUE(nice_ticks(kNaN, 1, 6).empty());
  EXPECT_LE(nice_ticks(0, 1, 1).size(), 2u);  // max_ticks below 2 acts as 2
}

TEST(LogTicks, DecadesWithinRange) {
  EXPECT_EQ(log_ticks(0.5, 2000), (std::vector<double>{1, 10, 100, 1000}));
  EXPECT_EQ(log_ticks(1, 1000), (std::vector<double>{1, 10, 100, 1000}));  // ends included
  EXPECT_EQ(log_ticks(0.002, 0.5), (std::vector<double>{0.01, 0.1}));
  EXPECT_TRUE(log_ticks(2, 9).empty());
  EXPECT_TRUE(log_ticks(0, 100).empty());
  EXPECT_TRUE(log_ticks(-1, 100).empty());
}

TEST(FormatTick, CompactLabels) {
  EXPECT_EQ(format_tick(0.5), "0.5");
  EXPECT_EQ(format_tick(0.0), "0");
  EXPECT_EQ(format_tick(-0.0), "0");
  EXPECT_EQ(format_tick(-180), "-180");
  EXPECT_EQ(format_tick(1000), "1000");
  EXPECT_EQ(format_tick(0.1 + 0.2), "0.3");
  EXPECT_EQ(format_tick(0.001), "0.001");
  EXPECT_EQ(format_tick(12345), "12345");
  EXPECT_EQ(format_tick(1e5), "1e5");
  EXPECT_EQ(format_tick(2.5e-6), "2.5e-6");
  EXPECT_EQ(format_tick(-1.5e7), "-1.5e7");
}

TEST(NiceLimits, RoundWithSmallMargin) {
  const auto [lo, hi] = nice_limits(0, 1, Scale::Linear);
  EXPECT_LT(lo, 0);
  EXPECT_GT(hi, 1);
  EXPECT_GE(lo, -0.15);  // margin at most 15% of the range each side
  EXPECT_LE(hi, 1.15);
  EXPECT_NEAR(lo * 20, std::round(lo * 20), 1e-9);  // round to a twentieth
  EXPECT_NEAR(hi * 20, std::round(hi * 20), 1e-9);

  const auto [flo, fhi] = nice_limits(0.6, 6000, Scale::Log);
  EXPECT_DOUBLE_EQ(flo, 0.1);
  EXPECT_DOUBLE_EQ(fhi, 1e4);

  const auto [clo, chi] = nice_limits(3, 3, Scale::Linear);  // a constant still gets a range
  EXPECT_LT(clo, 3);
  EXPECT_GT(chi, 3);
  EXPECT_THROW(nice_limits(0, 10, Scale::Log), std::invalid_argument);
}

TEST(Render, SizeTypeAndNotBlank) {
  Figure fig(800, 560);
  fig.title = "Sine";
  Axes& ax = fig.add_axes();
  ax.x_label = "Time (s)";
  ax.y_label = "Angle (rad)";
  Series s{"sin", {}, {}};
  for (int i = 0; i < 1000; ++i) {
    s.x.push_back(i * 0.01);
    s.y.push_back(std::sin(i * 0.01));
  }
  ax.series.push_back(s);
  const cv::Mat img = fig.render();
  EXPECT_EQ(img.cols, 800);
  EXPECT_EQ(img.rows, 560);
  EXPECT_EQ(img.type(), CV_8UC3);
  // Box, grid, text and a curve: well above 1% of the pixels; a blank figure has none.
  EXPECT_GT(count_non_white(img), static_cast<int>(img.total() / 100));
}

TEST(Render, EmptyFigureIsWhite) {
  const cv::Mat img = Figure(300, 200).render();
  EXPECT_EQ(count_non_white(img), 0);
}

TEST(Render, HorizontalLineLandsOnMiddleRowAndIsClipped) {
  // y = 0.5 on [0, 1] axes, from x = -1 to 2: must be cut at the axis box.
  const Figure fig = unit_figure(Series{"", {-1, 2}, {0.5, 0.5}, kRed, 2.0});
  const cv::Mat img = fig.render();
  const cv::Rect area = fig.plot_area(0);
  ASSERT_GT(area.width, 100);
  ASSERT_GT(area.height, 100);
  const cv::Mat red = red_mask(img);

  cv::Mat outside = red.clone();
  outside(area).setTo(0);
  EXPECT_EQ(cv::countNonZero(outside), 0) << "series drawn outside the plot area";

  const cv::Moments m = cv::moments(red(area), true);
  ASSERT_GT(m.m00, area.width);  // about 2 px per column
  const double mean_row = area.y + m.m01 / m.m00;
  EXPECT_NEAR(mean_row, area.y + (area.height - 1) / 2.0, 1.0);  // a 2 px line centred on the row, +-1 px

  // Every column from box to box is covered.
  cv::Mat columns;
  cv::reduce(red(area), columns, 0, cv::REDUCE_MAX);
  EXPECT_GE(cv::countNonZero(columns), area.width - 2);
}

TEST(Render, NaNBreaksTheLine) {
  const Figure fig = unit_figure(Series{"", {0, 0.4, 0.5, 0.6, 1}, {0.5, 0.5, kNaN, 0.5, 0.5}, kRed, 2.0});
  const cv::Mat red = red_mask(fig.render());
  const cv::Rect area = fig.plot_area(0);
  const auto red_in_column = [&](double x) { return cv::countNonZero(red.col(column_at(area, x))) > 0; };
  EXPECT_TRUE(red_in_column(0.2));
  EXPECT_TRUE(red_in_column(0.8));
  EXPECT_FALSE(red_in_column(0.45));
  EXPECT_FALSE(red_in_column(0.5));
  EXPECT_FALSE(red_in_column(0.55));
}

TEST(Render, DashedLineHasGaps) {
  const auto red_columns = [](bool dashed) {
    Series s{"", {0, 1}, {0.5, 0.5}, kRed, 2.0, dashed};
    const Figure fig = unit_figure(s);
    cv::Mat columns;
    cv::reduce(red_mask(fig.render())(fig.plot_area(0)), columns, 0, cv::REDUCE_MAX);
    return cv::countNonZero(columns);
  };
  const int solid = red_columns(false), dashed = red_columns(true);
  EXPECT_GT(dashed, solid * 4 / 10);  // dashes are about 60% on
  EXPECT_LT(dashed, solid * 8 / 10);
}

TEST(Render, MarkersAtPoints) {
  Series s{"", {0.25, 0.75}, {0.25, 0.75}, kRed, 1.0};
  s.markers = true;
  s.y = {0.25, kNaN};  // a lone point: no line, only its marker
  const Figure fig = unit_figure(s);
  const cv::Rect area = fig.plot_area(0);
  const cv::Mat red = red_mask(fig.render());
  const int cx = column_at(area, 0.25);
  const int cy = area.y + static_cast<int>(std::lround(0.75 * (area.height - 1)));
  EXPECT_GT(cv::countNonZero(red(cv::Rect(cx - 3, cy - 3, 7, 7))), 15);
  EXPECT_EQ(cv::countNonZero(red) - cv::countNonZero(red(cv::Rect(cx - 6, cy - 6, 13, 13))), 0);
}

TEST(Render, LegendInTopRightCorner) {
  const auto red_top_right = [](bool legend) {
    // A line along the bottom, labelled: only the legend sample can be red up top.
    Figure fig = unit_figure(Series{"response", {0, 1}, {0.05, 0.05}, kRed, 2.0});
    fig.axes()[0].legend = legend;
    const cv::Rect a = fig.plot_area(0);
    const cv::Rect corner(a.x + a.width / 2, a.y, a.width / 2, a.height / 4);
    return cv::countNonZero(red_mask(fig.render())(corner));
  };
  EXPECT_GT(red_top_right(true), 20);
  EXPECT_EQ(red_top_right(false), 0);
}

// A labelled line along the top: the legend moves out of its way to the first free
// corner in order (top-right, top-left, bottom-right, bottom-left): bottom-right.
TEST(Render, LegendAvoidsTheData) {
  const auto red_in = [](bool legend, bool top) {
    Figure fig = unit_figure(Series{"response", {0, 1}, {0.97, 0.97}, kRed, 2.0});
    fig.axes()[0].legend = legend;
    const cv::Rect a = fig.plot_area(0);
    const cv::Rect corner(a.x + a.width / 2, top ? a.y + a.height / 4 : a.y + 3 * a.height / 4, a.width / 2, a.height / 4);
    return cv::countNonZero(red_mask(fig.render())(corner));
  };
  EXPECT_GT(red_in(true, false), 20);  // the legend's red sample, bottom right
  EXPECT_EQ(red_in(false, false), 0);
  EXPECT_EQ(red_in(true, true), 0);  // not just below the line at the top
}

TEST(Render, LogAxisIgnoresNonPositiveValues) {
  Figure fig(640, 480);
  Axes& ax = fig.add_axes();
  ax.x_scale = Scale::Log;
  ax.y_scale = Scale::Log;
  ax.series.push_back(Series{"", {-1, 0, 1, 10, 100}, {5, 4, 1, 0, 100}, kRed, 2.0});
  ax.series.push_back(Series{"", {-3, -2}, {1, 2}});  // nothing drawable at all
  cv::Mat img;
  ASSERT_NO_THROW(img = fig.render());
  // Only (1, 1) and (100, 100) are drawable and they are not adjacent: no segment.
  EXPECT_EQ(cv::countNonZero(red_mask(img)), 0);

  fig.axes()[0].y_scale = Scale::Linear;  // now 1, 10, 100 at y = 1, 0, 100 form a line
  ASSERT_NO_THROW(img = fig.render());
  const cv::Rect area = fig.plot_area(0);
  cv::Mat columns;
  cv::reduce(red_mask(img)(area), columns, 0, cv::REDUCE_MAX);
  // Automatic x limits are the decades [1, 100]: the line spans the width.
  EXPECT_GE(cv::countNonZero(columns), area.width - 3);
}

TEST(Render, BadInputsThrow) {
  Figure fig(300, 200);
  fig.add_axes().series.push_back(Series{"bad", {1, 2, 3}, {1, 2}});
  EXPECT_THROW(fig.render(), std::invalid_argument);

  Figure log_fig(300, 200);
  Axes& ax = log_fig.add_axes();
  ax.x_scale = Scale::Log;
  ax.x_limits = std::make_pair(0.0, 10.0);
  EXPECT_THROW(log_fig.render(), std::invalid_argument);

  EXPECT_THROW(Figure(10, 700), std::invalid_argument);
  EXPECT_THROW(Figure().plot_area(0), std::out_of_range);
}

TEST(Render, StackedAxesShareWidthAndSplitHeight) {
  Figure fig(1000, 700);
  fig.add_axes();
  fig.add_axes();
  fig.axes()[0].y_label = "Magnitude (dB)";
  const cv::Rect top = fig.plot_area(0), bottom = fig.plot_area(1);
  EXPECT_EQ(top.x, bottom.x);
  EXPECT_EQ(top.width, bottom.width);
  EXPECT_LT(top.y + top.height, bottom.y);
  EXPECT_NEAR(top.height, bottom.height, 40);  // equal slots; only the x label differs
}

// 2nd-order Butterworth low-pass at 60 Hz: H(jw) = 1 / (1 - (w/wc)^2 + j sqrt(2) w/wc).
void butterworth(std::vector<double>& f_hz, std::vector<double>& mag_db, std::vector<double>& phase_deg) {
  for (int i = 0; i <= 400; ++i) {
    const double f = std::pow(10.0, -0.5 + 4.0 * i / 400);  // 0.3 Hz .. 3 kHz
    const double u = f / 60.0;
    const double re = 1 - u * u, im = std::sqrt(2.0) * u;
    f_hz.push_back(f);
    mag_db.push_back(-10 * std::log10(re * re + im * im));
    phase_deg.push_back(-std::atan2(im, re) * 180 / std::acos(-1.0));
  }
}

TEST(BodeFigure, MagnitudeOverPhaseOnSharedLogAxis) {
  std::vector<double> f, mag, phase;
  butterworth(f, mag, phase);
  Figure fig = bode_figure(f, mag, phase, "Butterworth", 60.0, std::nullopt);
  ASSERT_EQ(fig.axes().size(), 2u);
  const Axes& m = fig.axes()[0];
  const Axes& p = fig.axes()[1];
  EXPECT_EQ(m.x_scale, Scale::Log);
  EXPECT_EQ(p.x_scale, Scale::Log);
  ASSERT_TRUE(m.x_limits && p.x_limits);
  EXPECT_EQ(*m.x_limits, *p.x_limits);
  EXPECT_DOUBLE_EQ(m.x_limits->first, 0.1);
  EXPECT_DOUBLE_EQ(m.x_limits->second, 1e4);
  EXPECT_EQ(m.h_lines, std::vector<double>{0.0});
  EXPECT_EQ(p.h_lines, std::vector<double>{-180.0});
  EXPECT_EQ(m.v_lines, std::vector<double>{60.0});
  EXPECT_EQ(p.v_lines, std::vector<double>{60.0});
  // Phase from about 0 to -180 deg: ticks at multiples of 45 deg, the data inside.
  ASSERT_TRUE(p.y_tick_step && p.y_limits);
  EXPECT_EQ(*p.y_tick_step, 45.0);
  EXPECT_LT(p.y_limits->first, -179.0);
  EXPECT_GT(p.y_limits->second, -0.01);
  EXPECT_NE(p.x_label.find("Hz"), std::string::npos);
  EXPECT_NE(m.y_label.find("dB"), std::string::npos);
  EXPECT_NE(p.y_label.find("deg"), std::string::npos);
  EXPECT_GT(count_non_white(fig.render()), 7000);

  EXPECT_THROW(bode_figure(f, mag, {1.0}, "bad"), std::invalid_argument);
}

TEST(StepFigure, ResponseAndFinalValue) {
  std::vector<double> t, y;
  for (int i = 0; i <= 500; ++i) {
    t.push_back(i * 0.001);
    y.push_back(1 - std::exp(-t.back() / 0.05) * std::cos(60 * t.back()));
  }
  Figure fig = step_figure(t, y, "Step", 1.0, "Position (m)");
  ASSERT_EQ(fig.axes().size(), 1u);
  const Axes& ax = fig.axes()[0];
  EXPECT_EQ(ax.h_lines, std::vector<double>{1.0});
  EXPECT_EQ(ax.y_label, "Position (m)");
  EXPECT_NE(ax.x_label.find("(s)"), std::string::npos);
  ASSERT_TRUE(ax.x_limits && ax.y_limits);
  EXPECT_DOUBLE_EQ(ax.x_limits->first, 0.0);
  EXPECT_DOUBLE_EQ(ax.x_limits->second, 0.5);
  EXPECT_LT(ax.y_limits->first, 0.0);
  EXPECT_GT(ax.y_limits->second, *std::max_element(y.begin(), y.end()));
  EXPECT_GT(count_non_white(fig.render()), 5000);
}

class SavePng : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dmbd_viz_test_" + std::to_string(::getpid()) + "_" +
                                        testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(SavePng, WritesReadableFileAndNoTemporary) {
  Figure fig = unit_figure(Series{"line", {0, 1}, {0, 1}}, 320, 240);
  const std::string path = (dir_ / "figure.png").string();
  fig.save_png(path);
  const cv::Mat back = cv::imread(path, cv::IMREAD_COLOR);
  ASSERT_FALSE(back.empty());
  EXPECT_EQ(back.cols, 320);
  EXPECT_EQ(back.rows, 240);
  EXPECT_EQ(cv::norm(back, fig.render(), cv::NORM_INF), 0);  // PNG is lossless
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator{}), 1);

  fig.save_png(path);  // overwriting an existing file works too
  EXPECT_FALSE(fs::exists(path + ".tmp"));
}

TEST_F(SavePng, MissingDirectoryThrowsAndLeavesNothing) {
  const Figure fig = unit_figure(Series{"line", {0, 1}, {0, 1}}, 320, 240);
  const std::string path = (dir_ / "missing" / "figure.png").string();
  try {
    fig.save_png(path);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  EXPECT_FALSE(fs::exists(dir_ / "missing"));
  EXPECT_TRUE(fs::is_empty(dir_));
}

}  // namespace
}  // namespace dmbd::viz
