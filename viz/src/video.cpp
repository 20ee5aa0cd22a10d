// MP4 video writing through OpenCV's FFmpeg backend: H.264 first, MPEG-4 Part 2 as a
// fallback, into a temporary file renamed on success.
#include "dmbd/viz/video.hpp"

#include <algorithm>
#include <memory>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "dmbd/base/temporaries.hpp"

namespace dmbd::viz {
namespace {

namespace fs = std::filesystem;

int fourcc_of(VideoCodec codec) {
  switch (codec) {
    case VideoCodec::H264:
      return cv::VideoWriter::fourcc('a', 'v', 'c', '1');
    case VideoCodec::Mpeg4Part2:
      return cv::VideoWriter::fourcc('m', 'p', '4', 'v');
  }
  return 0;
}

bool ends_with_mp4(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".mp4";
}

// "<dir>/<stem>.tmp.mp4" for "<dir>/<stem>.mp4".
std::string temporary_name(const std::string& path) {
  return path.substr(0, path.size() - 4) + ".tmp" + path.substr(path.size() - 4);
}

void remove_quietly(const std::string& path) {
  std::error_code ec;
  fs::remove(path, ec);
}

// 8-bit BGR with even dimensions (last column / row repeated when odd).
cv::Mat to_even_bgr(const cv::Mat& frame) {
  cv::Mat bgr;
  switch (frame.type()) {
    case CV_8UC3:
      bgr = frame;
      break;
    case CV_8UC1:
      cv::cvtColor(frame, bgr, cv::COLOR_GRAY2BGR);
      break;
    case CV_8UC4:
      cv::cvtColor(frame, bgr, cv::COLOR_BGRA2BGR);
      break;
    default:
      throw std::invalid_argument(fmt::format(
          "viz: video frames must be 8-bit with 1, 3 or 4 channels, got depth {} with {} channels", frame.depth(),
          frame.channels()));
  }
  const int pad_right = bgr.cols % 2, pad_bottom = bgr.rows % 2;
  if (pad_right == 0 && pad_bottom == 0) return bgr;
  cv::Mat padded;
  cv::copyMakeBorder(bgr, padded, 0, pad_bottom, 0, pad_right, cv::BORDER_REPLICATE);
  return padded;
}

}  // namespace

std::string to_string(VideoCodec codec) {
  switch (codec) {
    case VideoCodec::H264:
      return "H.264 (avc1)";
    case VideoCodec::Mpeg4Part2:
      return "MPEG-4 Part 2 (mp4v)";
  }
  return "unknown codec";
}

struct VideoWriter::Impl {
  std::string path, tmp;
  std::unique_ptr<TemporaryPath> removed_on_signal;  // tmp, while it may exist
  double fps = 0.0;
  VideoOptions options;
  cv::VideoWriter writer;
  cv::Size input_size, encoded_size;
  VideoCodec codec = VideoCodec::H264;
  int frames = 0;
  bool finished = false;

  ~Impl() {
    if (writer.isOpened()) writer.release();
    if (!finished && !tmp.empty()) remove_quietly(tmp);
  }

  // Drop the encoder and the temporary file (after an error).
  void abandon() {
    if (writer.isOpened()) writer.release();
    remove_quietly(tmp);
  }

  void open(cv::Size size) {
    remove_quietly(tmp);  // a leftover of an interrupted run
    std::vector<std::string> tried;
    for (VideoCodec c : options.codecs) {
      bool opened = false;
      try {
        opened = writer.open(tmp, cv::CAP_FFMPEG, fourcc_of(c), fps, size, true);
      } catch (const cv::Exception&) {
        opened = false;
      }
      if (opened && writer.isOpened()) {
        codec = c;
        encoded_size = size;
        return;
      }
      writer.release();
      remove_quietly(tmp);
      tried.push_back(to_string(c));
    }
    throw std::runtime_error(fmt::format(
        "viz: cannot write video '{}': FFmpeg could not open '{}' ({}x{} px, {} fps) with {}; does the directory "
        "exist and is it writable?",
        path, tmp, size.width, size.height, fps, fmt::join(tried, " or ")));
  }
};

VideoWriter::VideoWriter(std::string path, double fps, VideoOptions options) : impl_(std::make_unique<Impl>()) {
  if (!ends_with_mp4(path))
    throw std::invalid_argument(fmt::format("viz: video path '{}' must end in .mp4", path));
  if (!std::isfinite(fps) || fps <= 0.0)
    throw std::invalid_argument(fmt::format("viz: video '{}': fps must be finite and positive, got {}", path, fps));
  if (options.codecs.empty())
    throw std::invalid_argument(fmt::format("viz: video '{}': no codec to try (VideoOptions::codecs is empty)", path));
  impl_->tmp = temporary_name(path);
  impl_->removed_on_signal = std::make_unique<TemporaryPath>(impl_->tmp);
  impl_->path = std::move(path);
  impl_->fps = fps;
  impl_->options = std::move(options);
}

VideoWriter::~VideoWriter() = default;
VideoWriter::VideoWriter(VideoWriter&&) noexcept = default;
VideoWriter& VideoWriter::operator=(VideoWriter&&) noexcept = default;

void VideoWriter::write(const cv::Mat& frame) {
  Impl& d = *impl_;
  if (d.finished) throw std::runtime_error(fmt::format("viz: video '{}' is already finished", d.path));
  if (frame.empty()) {
    d.abandon();
    throw std::invalid_argument(fmt::format("viz: video '{}': frame {} is empty", d.path, d.frames));
  }
  if (d.frames == 0 && !d.writer.isOpened()) {
    d.input_size = frame.size();
    const cv::Mat even = to_even_bgr(frame);
    d.open(even.size());
    d.writer.write(even);
    ++d.frames;
    return;
  }
  if (frame.size() != d.input_size) {
    d.abandon();
    throw std::invalid_argument(fmt::format("viz: video '{}': frame {} is {}x{} px but the first frame is {}x{} px",
                                            d.path, d.frames, frame.cols, frame.rows, d.input_size.width,
                                            d.input_size.height));
  }
  cv::Mat even;
  try {
    even = to_even_bgr(frame);
  } catch (...) {
    d.abandon();
    throw;
  }
  d.writer.write(even);
  ++d.frames;
}

VideoInfo VideoWriter::finish() {
  Impl& d = *impl_;
  if (d.finished) throw std::runtime_error(fmt::format("viz: video '{}' is already finished", d.path));
  if (d.frames == 0 || !d.writer.isOpened()) {
    d.abandon();
    throw std::runtime_error(fmt::format("viz: cannot write video '{}': no frame was written", d.path));
  }
  d.writer.release();  // flushes the encoder and writes the MP4 index
  std::error_code ec;
  const auto bytes = fs::file_size(d.tmp, ec);
  if (ec || bytes == 0) {
    d.abandon();
    throw std::runtime_error(
        fmt::format("viz: cannot write video '{}': the encoder left no data in '{}'", d.path, d.tmp));
  }
  fs::rename(d.tmp, d.path, ec);
  if (ec) {
    d.abandon();
    throw std::runtime_error(
        fmt::format("viz: cannot rename '{}' to '{}': {}", d.tmp, d.path, ec.message()));
  }
  d.finished = true;
  return VideoInfo{d.path, d.codec, d.frames, d.encoded_size, d.fps};
}

const std::string& VideoWriter::path() const { return impl_->path; }
const std::string& VideoWriter::temporary_path() const { return impl_->tmp; }
int VideoWriter::frames_written() const { return impl_->frames; }

VideoInfo write_video(const std::vector<cv::Mat>& frames, const std::string& path, double fps,
                      const VideoOptions& options) {
  VideoWriter video(path, fps, options);
  if (frames.empty()) throw std::invalid_argument(fmt::format("viz: video '{}': no frames", path));
  for (const cv::Mat& frame : frames) video.write(frame);
  return video.finish();
}

VideoInfo write_video_from_files(const std::vector<std::string>& image_paths, const std::string& path, double fps,
                                 const VideoOptions& options) {
  VideoWriter video(path, fps, options);
  if (image_paths.empty()) throw std::invalid_argument(fmt::format("viz: video '{}': no frames", path));
  for (const std::string& image_path : image_paths) {
    const cv::Mat frame = cv::imread(image_path, cv::IMREAD_COLOR);
    if (frame.empty())
      throw std::runtime_error(fmt::format("viz: cannot write video '{}': cannot read frame image '{}'", path,
                                           image_path));
    video.write(frame);
  }
  return video.finish();
}

}  // namespace dmbd::viz
