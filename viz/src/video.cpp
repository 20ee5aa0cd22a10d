// MP4 video writing through FFmpeg's libraries (av_encoder.hpp): H.264 first, MPEG-4
// Part 2 as a fallback, into a temporary file renamed on success.
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

#include "av_encoder.hpp"
#include "dmbd/base/temporaries.hpp"

namespace dmbd::viz {
namespace {

namespace fs = std::filesystem;

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

// x264's presets, fastest first. An unknown one would make libx264 fail to open and
// the writer fall back to MPEG-4 without a word, so it is refused here.
constexpr const char* kPresets[] = {"ultrafast", "superfast", "veryfast", "faster", "fast",
                                    "medium",    "slow",      "slower",   "veryslow", "placebo"};

void validate_h264_settings(const std::string& path, const VideoOptions& options) {
  if (std::find(std::begin(kPresets), std::end(kPresets), options.h264_preset) == std::end(kPresets))
    throw std::invalid_argument(fmt::format("viz: video '{}': unknown x264 preset '{}' (expected one of {})", path,
                                            options.h264_preset, fmt::join(kPresets, ", ")));
  if (options.h264_crf < 0 || options.h264_crf > 51)
    throw std::invalid_argument(
        fmt::format("viz: video '{}': x264 CRF {} is outside 0 ... 51", path, options.h264_crf));
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
  std::unique_ptr<detail::AvEncoder> writer;
  cv::Size input_size, encoded_size;
  VideoCodec codec = VideoCodec::H264;
  int frames = 0;
  bool finished = false;

  ~Impl() {
    writer.reset();
    if (!finished && !tmp.empty()) remove_quietly(tmp);
  }

  // Drop the encoder and the temporary file (after an error).
  void abandon() {
    writer.reset();
    remove_quietly(tmp);
  }

  // One frame into the encoder; after a failure (a full disk) nothing is left behind.
  void encode(const cv::Mat& even) {
    try {
      writer->write(even);
    } catch (...) {
      abandon();
      throw;
    }
    ++frames;
  }

  void open(cv::Size size) {
    remove_quietly(tmp);  // a leftover of an interrupted run
    std::vector<std::string> tried;
    for (VideoCodec c : options.codecs) {
      std::string why;
      writer = detail::AvEncoder::open(tmp, c, size, fps, options, &why);
      if (writer) {
        codec = c;
        encoded_size = size;
        return;
      }
      remove_quietly(tmp);
      tried.push_back(fmt::format("{} ({})", to_string(c), why));
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
  validate_h264_settings(path, options);
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
  if (d.frames == 0 && !d.writer) {
    d.input_size = frame.size();
    const cv::Mat even = to_even_bgr(frame);
    d.open(even.size());
    d.encode(even);
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
  d.encode(even);
}

VideoInfo VideoWriter::finish() {
  Impl& d = *impl_;
  if (d.finished) throw std::runtime_error(fmt::format("viz: video '{}' is already finished", d.path));
  if (d.frames == 0 || !d.writer) {
    d.abandon();
    throw std::runtime_error(fmt::format("viz: cannot write video '{}': no frame was written", d.path));
  }
  try {
    d.writer->finish();  // flushes the encoder and writes the MP4 index
  } catch (...) {
    d.abandon();
    throw;
  }
  d.writer.reset();
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
