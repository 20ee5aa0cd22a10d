#pragma once
// MP4 videos from frame sequences, written atomically and playable in a browser's
// <video> element.
//
//   dmbd::viz::VideoWriter video("out/video.mp4", 30.0);
//   for (const cv::Mat& frame : frames) video.write(frame);   // BGR, all the same size
//   dmbd::viz::VideoInfo info = video.finish();               // renames into place
//
// or in one call: `write_video(frames, "out/video.mp4", 30.0)`.
//
// Codec: H.264 (FFmpeg's libraries with libx264: High profile, yuv420p, BT.601 colours,
// the preset and constant rate factor of VideoOptions), which every browser plays;
// MPEG-4 Part 2 only as a fallback when no H.264 encoder is available (browsers,
// Chromium included, do not play it). The codec actually used is reported in VideoInfo.
//
// Atomic: frames are encoded into "<dir>/<stem>.tmp.mp4" (FFmpeg picks the container
// from the extension, so the temporary name keeps it) and renamed to the target by
// finish(). A writer destroyed before finish(), or any failure, removes the
// temporary file, so an interrupted run never leaves a half-written video.
//
// Odd sizes: H.264 with 4:2:0 chroma needs even dimensions, so a frame of odd width
// or height is padded by one pixel on the right / bottom edge (the last column / row
// repeated); VideoInfo::size is the encoded (even) size.
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace dmbd::viz {

enum class VideoCodec {
  H264,        // fourcc "avc1"
  Mpeg4Part2,  // fourcc "mp4v" (fallback; not playable in browsers)
};

// "H.264 (avc1)" / "MPEG-4 Part 2 (mp4v)".
std::string to_string(VideoCodec codec);

struct VideoOptions {
  // Codecs tried in order when the first frame arrives; the first one FFmpeg can
  // open is used. Must not be empty.
  std::vector<VideoCodec> codecs = {VideoCodec::H264, VideoCodec::Mpeg4Part2};
  // x264's speed preset (ultrafast ... placebo) and constant rate factor (0-51, lower
  // is better); others are refused. "ultrafast" because on the renderer's 1920 x 1080
  // frames it encodes 4-5x faster than "medium" (OpenCV's fixed choice) at the same
  // CRF, with a PSNR against the frames as high (36.9 dB against 36.4 dB) for a file
  // about 3.7x larger (docs/model.md, issue 29; tests/viz/test_video.cpp checks the
  // PSNR bound).
  std::string h264_preset = "ultrafast";
  int h264_crf = 23;
};

struct VideoInfo {
  std::string path;   // the final file
  VideoCodec codec = VideoCodec::H264;
  int frames = 0;
  cv::Size size;      // encoded size in px (even)
  double fps = 0.0;
};

class VideoWriter {
 public:
  // Nothing is created until the first write(). Throws std::invalid_argument when
  // path does not end in ".mp4" (any case), fps is not finite and positive, or
  // options.codecs is empty.
  VideoWriter(std::string path, double fps, VideoOptions options = {});
  ~VideoWriter();  // removes the temporary file unless finish() succeeded
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;
  VideoWriter(VideoWriter&&) noexcept;
  VideoWriter& operator=(VideoWriter&&) noexcept;

  // Append one frame: 8-bit BGR (CV_8UC3); grey (CV_8UC1) and BGRA (CV_8UC4) are
  // converted. The first frame fixes the size and opens the encoder. Throws
  // std::invalid_argument for an empty frame, another depth or channel count, or a
  // size different from the first frame's (the temporary file is removed), and
  // std::runtime_error naming the path when no codec can be opened there (e.g. the
  // directory does not exist or is not writable), or after finish().
  void write(const cv::Mat& frame);

  // Flush the encoder and rename the temporary file to the path. Throws
  // std::runtime_error naming the path when no frame was written, the encoder
  // produced nothing, or the rename fails (the temporary file is removed), or when
  // called twice.
  VideoInfo finish();

  const std::string& path() const;
  // "<dir>/<stem>.tmp.mp4": where frames go until finish().
  const std::string& temporary_path() const;
  int frames_written() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The whole sequence in one call (see VideoWriter). Throws std::invalid_argument
// when frames is empty, plus whatever VideoWriter throws.
VideoInfo write_video(const std::vector<cv::Mat>& frames, const std::string& path, double fps,
                      const VideoOptions& options = {});
// Frames read from image files (PNG or anything cv::imread reads), in order. Throws
// std::runtime_error naming an image that cannot be read.
VideoInfo write_video_from_files(const std::vector<std::string>& image_paths, const std::string& path, double fps,
                                 const VideoOptions& options = {});

}  // namespace dmbd::viz
