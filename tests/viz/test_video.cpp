// Tests for dmbd::viz video writing: a synthetic moving square is encoded, decoded
// back with cv::VideoCapture and compared with what was drawn; odd sizes, the
// MPEG-4 fallback, image-file input, atomic output and failure paths; and the MP4
// actually plays in headless Chromium's <video> element.
#include "dmbd/viz/video.hpp"

#include <stdlib.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "viz_test_support.hpp"
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

namespace dmbd::viz {
namespace {

namespace fs = std::filesystem;
using test::find_chromium;
// Temp folders named after this test file.
struct TempDir : test::TempDir {
  TempDir() : test::TempDir("dmbd_test_video") {}
};


constexpr int kSquare_px = 40;
const cv::Scalar kSquareBgr(0, 0, 220);      // red square
const cv::Scalar kBackgroundBgr(235, 235, 235);

// Top-left corner of the square in frame i.
cv::Point square_corner(int i) { return {20 + 6 * i, 60 + 3 * i}; }

cv::Mat square_frame(int i, cv::Size size) {
  cv::Mat frame(size, CV_8UC3, kBackgroundBgr);
  cv::rectangle(frame, cv::Rect(square_corner(i), cv::Size(kSquare_px, kSquare_px)), kSquareBgr, cv::FILLED);
  return frame;
}

std::vector<cv::Mat> square_frames(int n, cv::Size size) {
  std::vector<cv::Mat> frames;
  for (int i = 0; i < n; ++i) frames.push_back(square_frame(i, size));
  return frames;
}

// Centroid of the red pixels (R > 150, G and B < 100) of a BGR image; {-1, -1} when none.
cv::Point2d red_centroid(const cv::Mat& bgr, int* count = nullptr) {
  cv::Mat mask;
  cv::inRange(bgr, cv::Scalar(0, 0, 150), cv::Scalar(100, 100, 255), mask);
  const cv::Moments m = cv::moments(mask, true);
  if (count) *count = cv::countNonZero(mask);
  if (m.m00 == 0) return {-1, -1};
  return {m.m10 / m.m00, m.m01 / m.m00};
}

std::vector<cv::Mat> decode_all(const std::string& path) {
  cv::VideoCapture cap(path, cv::CAP_FFMPEG);
  EXPECT_TRUE(cap.isOpened()) << path;
  std::vector<cv::Mat> frames;
  cv::Mat frame;
  while (cap.read(frame)) frames.push_back(frame.clone());
  return frames;
}

std::string fourcc_text(double fourcc) {
  const int v = static_cast<int>(fourcc);
  return {static_cast<char>(v & 0xff), static_cast<char>((v >> 8) & 0xff), static_cast<char>((v >> 16) & 0xff),
          static_cast<char>((v >> 24) & 0xff)};
}

std::vector<std::string> files_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  return names;
}

TEST(Video, MovingSquareRoundTripsThroughH264) {
  TempDir dir;
  const cv::Size size(320, 240);
  const std::string path = dir / "video.mp4";
  const VideoInfo info = write_video(square_frames(30, size), path, 25.0);

  // This machine has libx264 (scripts/setup installs libopencv-dev, whose FFmpeg has
  // it); without H.264 the video would not play in browsers, so insist on it.
  EXPECT_EQ(info.codec, VideoCodec::H264) << "got " << to_string(info.codec);
  EXPECT_EQ(info.path, path);
  EXPECT_EQ(info.frames, 30);
  EXPECT_EQ(info.size, size);
  EXPECT_EQ(info.fps, 25.0);
  EXPECT_EQ(files_in(dir.path()), std::vector<std::string>{"video.mp4"}) << "temporary file left behind";

  // An ISO-BMFF file: "ftyp" box first.
  std::ifstream in(path, std::ios::binary);
  std::string head(12, '\0');
  in.read(head.data(), 12);
  EXPECT_EQ(head.substr(4, 4), "ftyp");

  cv::VideoCapture cap(path, cv::CAP_FFMPEG);
  ASSERT_TRUE(cap.isOpened());
  EXPECT_EQ(cap.get(cv::CAP_PROP_FRAME_COUNT), 30);
  EXPECT_EQ(cap.get(cv::CAP_PROP_FRAME_WIDTH), 320);
  EXPECT_EQ(cap.get(cv::CAP_PROP_FRAME_HEIGHT), 240);
  EXPECT_NEAR(cap.get(cv::CAP_PROP_FPS), 25.0, 1e-6);  // stored as the exact rational 25/1
  EXPECT_EQ(fourcc_text(cap.get(cv::CAP_PROP_FOURCC)), "avc1");
  cap.release();

  const std::vector<cv::Mat> decoded = decode_all(path);
  ASSERT_EQ(decoded.size(), 30u);
  for (int i : {0, 15, 29}) {
    SCOPED_TRACE(i);
    ASSERT_EQ(decoded[i].size(), size);
    // Lossy codec (CRF 23, 4:2:0 chroma): a flat 40 px square keeps its centroid
    // within 1 px (chroma is subsampled in 2x2 blocks; edges ring symmetrically) and
    // most of its area (+-10% of 1600 px classified as red).
    int red_px = 0;
    const cv::Point2d c = red_centroid(decoded[i], &red_px);
    const cv::Point2d drawn = cv::Point2d(square_corner(i)) + cv::Point2d(kSquare_px - 1, kSquare_px - 1) * 0.5;
    EXPECT_NEAR(c.x, drawn.x, 1.0);
    EXPECT_NEAR(c.y, drawn.y, 1.0);
    EXPECT_NEAR(red_px, kSquare_px * kSquare_px, 160);
    // Overall fidelity: mean absolute error below 4 levels in each channel. Measured
    // ~2.7 here, and it is mostly not compression: OpenCV's BGR -> limited-range
    // YUV -> BGR conversion shifts flat colours by 1-4 levels (235 grey comes back as
    // (231, 234, 232)).
    cv::Mat diff;
    cv::absdiff(decoded[i], square_frame(i, size), diff);
    const cv::Scalar mae = cv::mean(diff);
    for (int ch = 0; ch < 3; ++ch) EXPECT_LT(mae[ch], 4.0) << "channel " << ch;
  }
}

TEST(Video, OddSizeIsPaddedToEven) {
  TempDir dir;
  const cv::Size odd(321, 241);
  const std::string path = dir / "odd.mp4";
  const VideoInfo info = write_video(square_frames(10, odd), path, 10.0);
  EXPECT_EQ(info.size, cv::Size(322, 242));
  const std::vector<cv::Mat> decoded = decode_all(path);
  ASSERT_EQ(decoded.size(), 10u);
  EXPECT_EQ(decoded[5].size(), cv::Size(322, 242));
  // Padding is appended right and bottom, so the picture is not shifted (1 px as above).
  const cv::Point2d c = red_centroid(decoded[5]);
  const cv::Point2d drawn = cv::Point2d(square_corner(5)) + cv::Point2d(kSquare_px - 1, kSquare_px - 1) * 0.5;
  EXPECT_NEAR(c.x, drawn.x, 1.0);
  EXPECT_NEAR(c.y, drawn.y, 1.0);
}

TEST(Video, GreyAndBgraFramesAreConverted) {
  TempDir dir;
  std::vector<cv::Mat> frames;
  for (int i = 0; i < 4; ++i) frames.emplace_back(64, 64, CV_8UC1, cv::Scalar(60 * i));
  VideoInfo info = write_video(frames, dir / "grey.mp4", 5.0);
  EXPECT_EQ(info.frames, 4);
  const auto decoded = decode_all(dir / "grey.mp4");
  ASSERT_EQ(decoded.size(), 4u);
  EXPECT_NEAR(cv::mean(decoded[3])[1], 180.0, 4.0);  // flat grey within 4 levels (colour conversion, above)

  frames.clear();
  for (int i = 0; i < 4; ++i) frames.emplace_back(64, 64, CV_8UC4, cv::Scalar(255, 0, 0, 255));
  info = write_video(frames, dir / "bgra.mp4", 5.0);
  EXPECT_EQ(info.frames, 4);
}

TEST(Video, Mpeg4FallbackWhenAskedFor) {
  TempDir dir;
  VideoOptions options;
  options.codecs = {VideoCodec::Mpeg4Part2};
  const VideoInfo info = write_video(square_frames(12, {160, 120}), dir / "v.mp4", 12.0, options);
  EXPECT_EQ(info.codec, VideoCodec::Mpeg4Part2);
  cv::VideoCapture cap(dir / "v.mp4", cv::CAP_FFMPEG);
  ASSERT_TRUE(cap.isOpened());
  EXPECT_EQ(fourcc_text(cap.get(cv::CAP_PROP_FOURCC)), "mp4v");
  EXPECT_EQ(cap.get(cv::CAP_PROP_FRAME_COUNT), 12);
  EXPECT_EQ(to_string(VideoCodec::Mpeg4Part2), "MPEG-4 Part 2 (mp4v)");
  EXPECT_EQ(to_string(VideoCodec::H264), "H.264 (avc1)");
}

TEST(Video, FromImageFiles) {
  TempDir dir;
  std::vector<std::string> pngs;
  for (int i = 0; i < 10; ++i) {
    pngs.push_back(dir / ("frame_" + std::to_string(i) + ".png"));
    ASSERT_TRUE(cv::imwrite(pngs.back(), square_frame(i, {200, 150})));
  }
  const VideoInfo info = write_video_from_files(pngs, dir / "video.mp4", 5.0);
  EXPECT_EQ(info.frames, 10);
  EXPECT_EQ(info.size, cv::Size(200, 150));
  EXPECT_EQ(decode_all(dir / "video.mp4").size(), 10u);

  // A missing image: the error names it, and no video (final or temporary) remains.
  pngs.insert(pngs.begin() + 3, dir / "missing.png");
  try {
    write_video_from_files(pngs, dir / "broken.mp4", 5.0);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.png"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "broken.mp4"));
  EXPECT_FALSE(fs::exists(dir / "broken.tmp.mp4"));
}

// The quality bound of the default preset (VideoOptions::h264_preset): on rendered
// frames (the stored reference render, panned 6 px a frame so every frame moves) the
// decoded video's mean PSNR against the frames is within 0.5 dB of x264's "medium" at
// the same CRF, and above 33 dB.
double mean_psnr(const std::vector<cv::Mat>& frames, const std::string& path, const VideoOptions& options) {
  write_video(frames, path, 30.0, options);
  const std::vector<cv::Mat> decoded = decode_all(path);
  EXPECT_EQ(decoded.size(), frames.size());
  double sum = 0;
  for (std::size_t i = 0; i < decoded.size() && i < frames.size(); ++i) sum += cv::PSNR(decoded[i], frames[i]);
  return sum / static_cast<double>(frames.size());
}

TEST(Video, TheDefaultPresetKeepsMediumsQualityOnRenderedFrames) {
  TempDir dir;
  const cv::Mat render = cv::imread(std::string(DMBD_SOURCE_DIR) + "/tests/report/data/render_three_quarter_960x540.png",
                                    cv::IMREAD_COLOR);
  ASSERT_FALSE(render.empty());
  std::vector<cv::Mat> frames;
  for (int i = 0; i < 16; ++i) frames.push_back(render(cv::Rect(6 * i, 0, 640, 480)).clone());
  VideoOptions medium;
  medium.h264_preset = "medium";
  const double psnr_default = mean_psnr(frames, dir / "default.mp4", {});
  const double psnr_medium = mean_psnr(frames, dir / "medium.mp4", medium);
  EXPECT_GE(psnr_default, psnr_medium - 0.5) << "default " << psnr_default << " dB, medium " << psnr_medium << " dB";
  EXPECT_GT(psnr_default, 33.0);
}

TEST(Video, AnUnknownPresetOrACrfOutOfRangeIsRefused) {
  TempDir dir;
  VideoOptions typo;
  typo.h264_preset = "ultrafest";
  try {
    VideoWriter(dir / "v.mp4", 25.0, typo);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("unknown x264 preset 'ultrafest'"), std::string::npos) << e.what();
  }
  for (int crf : {-1, 52}) {
    VideoOptions o;
    o.h264_crf = crf;
    EXPECT_THROW(VideoWriter(dir / "v.mp4", 25.0, o), std::invalid_argument) << crf;
  }
  VideoOptions slow;
  slow.h264_preset = "veryslow";
  slow.h264_crf = 0;
  EXPECT_NO_THROW(VideoWriter(dir / "v.mp4", 25.0, slow));
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(Video, MissingDirectoryThrowsAndLeavesNothing) {
  TempDir dir;
  const std::string path = dir / "no_such_dir/video.mp4";
  try {
    write_video(square_frames(3, {64, 64}), path, 10.0);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(Video, ParentIsAFileThrowsAndLeavesNothing) {
  // (Not a read-only directory: tests may run as root, which writes anywhere.)
  TempDir dir;
  std::ofstream(dir / "plain.txt") << "not a directory";
  const std::string path = dir / "plain.txt/video.mp4";
  EXPECT_THROW(write_video(square_frames(3, {64, 64}), path, 10.0), std::runtime_error);
  EXPECT_EQ(files_in(dir.path()), std::vector<std::string>{"plain.txt"});
}

TEST(Video, InvalidArguments) {
  TempDir dir;
  EXPECT_THROW(VideoWriter(dir / "v.avi", 25.0), std::invalid_argument);
  EXPECT_THROW(VideoWriter(dir / "mp4", 25.0), std::invalid_argument);
  EXPECT_THROW(VideoWriter(dir / "v.mp4", 0.0), std::invalid_argument);
  EXPECT_THROW(VideoWriter(dir / "v.mp4", std::nan("")), std::invalid_argument);
  EXPECT_THROW(VideoWriter(dir / "v.mp4", 25.0, VideoOptions{{}}), std::invalid_argument);
  EXPECT_NO_THROW(VideoWriter(dir / "V.MP4", 25.0));
  EXPECT_THROW(write_video({}, dir / "v.mp4", 25.0), std::invalid_argument);

  VideoWriter video(dir / "v.mp4", 25.0);
  EXPECT_THROW(video.write(cv::Mat()), std::invalid_argument);
  EXPECT_THROW(video.write(cv::Mat(64, 64, CV_32FC3, cv::Scalar(0.5, 0.5, 0.5))), std::invalid_argument);
  EXPECT_TRUE(fs::is_empty(dir.path()));

  // A frame of another size: rejected, and the temporary file is removed.
  VideoWriter sized(dir / "sized.mp4", 25.0);
  EXPECT_EQ(sized.temporary_path(), dir / "sized.tmp.mp4");
  sized.write(square_frame(0, {64, 64}));
  EXPECT_TRUE(fs::exists(sized.temporary_path()));
  try {
    sized.write(square_frame(1, {64, 48}));
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("64x48"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(Video, FinishRules) {
  TempDir dir;
  {
    VideoWriter empty(dir / "empty.mp4", 25.0);
    EXPECT_THROW(empty.finish(), std::runtime_error);  // no frame
  }
  VideoWriter video(dir / "v.mp4", 25.0);
  video.write(square_frame(0, {64, 64}));
  EXPECT_EQ(video.frames_written(), 1);
  const VideoInfo info = video.finish();
  EXPECT_EQ(info.frames, 1);
  EXPECT_THROW(video.finish(), std::runtime_error);
  EXPECT_THROW(video.write(square_frame(1, {64, 64})), std::runtime_error);
  EXPECT_EQ(files_in(dir.path()), std::vector<std::string>{"v.mp4"});
}

TEST(Video, AbandonedWriterRemovesItsTemporaryFile) {
  TempDir dir;
  {
    VideoWriter video(dir / "v.mp4", 25.0);
    for (int i = 0; i < 5; ++i) video.write(square_frame(i, {128, 96}));
    EXPECT_TRUE(fs::exists(dir / "v.tmp.mp4"));
    VideoWriter moved = std::move(video);  // ownership of the temporary file moves too
    EXPECT_EQ(moved.frames_written(), 5);
  }
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

// ---- Playback in a real browser -------------------------------------------------


std::string read_text(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(Video, PlaysInHeadlessChromium) {
  const std::string chromium = find_chromium();
  ASSERT_FALSE(chromium.empty()) << "chromium is not installed (needed to check browser playback): run scripts/setup";
  TempDir dir;
  const VideoInfo info = write_video(square_frames(30, {320, 240}), dir / "video.mp4", 25.0);
  ASSERT_EQ(info.codec, VideoCodec::H264);

  // A test page (the report itself has no script) that writes the element's state
  // into an attribute, which --dump-dom prints once the virtual-time budget is spent.
  std::ofstream(dir / "play.html") << R"html(<!DOCTYPE html><html><body>
<video id="v" src="video.mp4" preload="auto" muted></video>
<script>
const v = document.getElementById('v');
function report() {
  document.body.setAttribute('data-state', 'ready=' + v.readyState + ' w=' + v.videoWidth + ' h=' + v.videoHeight +
    ' duration=' + v.duration + ' error=' + (v.error ? v.error.code : 0));
}
report();
setInterval(report, 50);
</script></body></html>)html";
  const std::string out = dir / "dom.html", log = dir / "chromium.log";
  const std::string cmd = "timeout 60 '" + chromium + "' --headless --no-sandbox --disable-gpu --user-data-dir='" +
                          (dir / "profile") + "' --virtual-time-budget=5000 --dump-dom 'file://" + (dir / "play.html") +
                          "' > '" + out + "' 2> '" + log + "'";
  const int rc = std::system(cmd.c_str());
  ASSERT_EQ(rc, 0) << cmd << "\n" << read_text(log);
  const std::string dom = read_text(out);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(dom, m, std::regex(R"(data-state="ready=(\d) w=(\d+) h=(\d+) duration=([0-9.]+) error=(\d))")))
      << dom;
  EXPECT_GE(std::stoi(m[1]), 2) << "HAVE_CURRENT_DATA: a frame was decoded";
  EXPECT_EQ(m[2], "320");
  EXPECT_EQ(m[3], "240");
  EXPECT_NEAR(std::stod(m[4]), 30 / 25.0, 0.05);  // container duration, 1.2 s +- one frame
  EXPECT_EQ(m[5], "0") << "MediaError code";
}

}  // namespace
}  // namespace dmbd::viz
