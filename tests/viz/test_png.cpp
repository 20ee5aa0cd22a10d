// Tests for dmbd::viz::encode_png (viz/src/png.cpp, libdeflate): every 8-bit layout
// decodes back to the same pixels through OpenCV's libpng, other depths still encode
// through OpenCV, and a rendered frame compresses at least as well as OpenCV's encoder.
#include <cstdint>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "dmbd/viz/plot.hpp"

namespace dmbd::viz {
namespace {

// Pixels that exercise every byte value and differ between neighbours and channels.
cv::Mat pattern(int rows, int cols, int type) {
  cv::Mat m(rows, cols, type);
  cv::RNG rng(7);
  rng.fill(m, cv::RNG::UNIFORM, 0, 256);
  if (cols > 8) m.colRange(0, cols / 2).setTo(cv::Scalar(10, 200, 30, 250));  // a flat half, as in a frame
  return m;
}

void expect_same_pixels(const cv::Mat& a, const cv::Mat& b) {
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.type(), b.type());
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
}

struct Layout {
  int type, rows, cols;
};

std::string name_of(const Layout& l) {
  const int c = CV_MAT_CN(l.type);
  return std::string(c == 1 ? "grey" : c == 3 ? "bgr" : "bgra") + "_" + std::to_string(l.rows) + "x" +
         std::to_string(l.cols);
}
void PrintTo(const Layout& l, std::ostream* os) { *os << name_of(l); }

class PngRoundTrip : public ::testing::TestWithParam<Layout> {};

TEST_P(PngRoundTrip, DecodesToTheSamePixels) {
  const Layout l = GetParam();
  const cv::Mat image = pattern(l.rows, l.cols, l.type);
  const std::vector<unsigned char> bytes = encode_png(image);
  ASSERT_GE(bytes.size(), 8u);
  EXPECT_EQ(bytes[1], 'P');
  expect_same_pixels(cv::imdecode(bytes, cv::IMREAD_UNCHANGED), image);
}

INSTANTIATE_TEST_SUITE_P(Layouts, PngRoundTrip,
                         ::testing::Values(Layout{CV_8UC3, 37, 53}, Layout{CV_8UC1, 20, 31}, Layout{CV_8UC4, 9, 17},
                                           Layout{CV_8UC3, 1, 1}, Layout{CV_8UC3, 540, 960}),
                         [](const ::testing::TestParamInfo<Layout>& info) { return name_of(info.param); });

TEST(Png, SixteenBitImagesStillEncodeThroughOpenCv) {
  const cv::Mat image = pattern(12, 18, CV_16UC3);
  expect_same_pixels(cv::imdecode(encode_png(image), cv::IMREAD_UNCHANGED), image);
}

TEST(Png, AViewIntoALargerImageEncodesOnlyItsPixels) {
  const cv::Mat big = pattern(40, 60, CV_8UC3);
  const cv::Mat view = big(cv::Rect(5, 7, 23, 11));  // rows not contiguous
  expect_same_pixels(cv::imdecode(encode_png(view), cv::IMREAD_UNCHANGED), view.clone());
}

TEST(Png, AnEmptyImageIsAnError) { EXPECT_THROW(encode_png(cv::Mat()), std::runtime_error); }

// A rendered frame (the stored reference image): no larger than OpenCV's PNG of it.
TEST(Png, ARenderedFrameIsNoLargerThanOpenCvsPng) {
  const cv::Mat frame =
      cv::imread(std::string(DMBD_SOURCE_DIR) + "/tests/report/data/render_three_quarter_960x540.png", cv::IMREAD_COLOR);
  ASSERT_FALSE(frame.empty());
  std::vector<unsigned char> opencv;
  ASSERT_TRUE(cv::imencode(".png", frame, opencv));
  const std::vector<unsigned char> ours = encode_png(frame);
  EXPECT_LE(ours.size(), opencv.size());
  expect_same_pixels(cv::imdecode(ours, cv::IMREAD_COLOR), frame);
}

}  // namespace
}  // namespace dmbd::viz
