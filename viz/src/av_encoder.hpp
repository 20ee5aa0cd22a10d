#pragma once
// One MP4 file encoded by FFmpeg's libraries (libavformat, libavcodec, libswscale),
// linked directly rather than through OpenCV's FFmpeg writer: that writer fixes x264's
// preset at "medium", which at 1920 x 1080 was most of a run's frame stage, and the
// OpenCV 4.6 of Debian ignores OPENCV_FFMPEG_WRITER_OPTIONS. Here the preset and the
// constant rate factor are the caller's (VideoOptions).
#include <memory>
#include <string>

#include <opencv2/core.hpp>

#include "dmbd/viz/video.hpp"

namespace dmbd::viz::detail {

class AvEncoder {
 public:
  // Opens `path` (an MP4 container) for 8-bit BGR frames of `size` (even) at `fps`
  // with `codec`. Returns nullptr and sets *why when the encoder or the file cannot be
  // opened (nothing is left at `path` then).
  static std::unique_ptr<AvEncoder> open(const std::string& path, VideoCodec codec, cv::Size size, double fps,
                                         const VideoOptions& options, std::string* why);
  ~AvEncoder();  // frees the encoder and closes the file (finished or not)
  AvEncoder(const AvEncoder&) = delete;
  AvEncoder& operator=(const AvEncoder&) = delete;

  // Converts one BGR frame of the opened size to YUV 4:2:0 and encodes it. Throws
  // std::runtime_error with FFmpeg's reason when encoding or writing fails.
  void write(const cv::Mat& bgr);
  // Drains the encoder, writes the MP4 index and closes the file. Throws
  // std::runtime_error with FFmpeg's reason (a full disk shows here).
  void finish();

 private:
  struct State;
  explicit AvEncoder(std::unique_ptr<State> state);
  std::unique_ptr<State> s_;
};

}  // namespace dmbd::viz::detail
