// MP4 encoding with libavformat / libavcodec / libswscale (see av_encoder.hpp).
#include "av_encoder.hpp"

#include <mutex>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

namespace dmbd::viz::detail {
namespace {

std::string av_error(int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, text, sizeof text);
  return text;
}

// FFmpeg (and x264 through it) print to stderr at "info" by default: statistics on
// close, capabilities on open. Every failure here becomes one exception with FFmpeg's
// reason, so their lines would only duplicate it. A program that has set its own level
// keeps it.
void quiet_ffmpeg_logging() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (av_log_get_level() == AV_LOG_INFO) av_log_set_level(AV_LOG_QUIET);
  });
}

const AVCodec* find_encoder(VideoCodec codec) {
  return codec == VideoCodec::H264 ? avcodec_find_encoder_by_name("libx264") : avcodec_find_encoder(AV_CODEC_ID_MPEG4);
}

}  // namespace

struct AvEncoder::State {
  std::string path;
  AVFormatContext* format = nullptr;
  AVCodecContext* encoder = nullptr;
  AVStream* stream = nullptr;
  SwsContext* to_yuv = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  std::int64_t next_pts = 0;
  bool file_open = false;

  ~State() {
    av_packet_free(&packet);
    av_frame_free(&frame);
    sws_freeContext(to_yuv);
    avcodec_free_context(&encoder);
    if (format && file_open) avio_closep(&format->pb);
    avformat_free_context(format);
  }

  [[noreturn]] void fail(const char* what, int code) const {
    throw std::runtime_error(fmt::format("viz: cannot write video '{}': {}: {}", path, what, av_error(code)));
  }

  // Codec settings. H.264: High profile, the caller's x264 preset and CRF. MPEG-4 Part 2:
  // a fixed quantiser of 3 (near transparent; the fallback is for players, not size).
  // The colours are tagged as swscale converts them: BT.601 matrix, limited range.
  int configure(const AVCodec* codec, cv::Size size, double fps, const VideoOptions& options, AVDictionary** opts) {
    encoder = avcodec_alloc_context3(codec);
    if (!encoder) return AVERROR(ENOMEM);
    encoder->width = size.width;
    encoder->height = size.height;
    encoder->pix_fmt = AV_PIX_FMT_YUV420P;
    encoder->framerate = av_d2q(fps, 1 << 20);
    encoder->time_base = av_inv_q(encoder->framerate);
    encoder->colorspace = AVCOL_SPC_SMPTE170M;
    encoder->color_range = AVCOL_RANGE_MPEG;
    if (format->oformat->flags & AVFMT_GLOBALHEADER) encoder->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    if (codec->id == AV_CODEC_ID_H264) {
      av_dict_set(opts, "preset", options.h264_preset.c_str(), 0);
      av_dict_set(opts, "crf", fmt::format("{}", options.h264_crf).c_str(), 0);
      av_dict_set(opts, "profile", "high", 0);
    } else {
      encoder->flags |= AV_CODEC_FLAG_QSCALE;
      encoder->global_quality = FF_QP2LAMBDA * 3;
    }
    return avcodec_open2(encoder, codec, opts);
  }

  // The stream, the file and its header; the frame and packet reused for every frame.
  int open_file() {
    stream = avformat_new_stream(format, nullptr);
    if (!stream) return AVERROR(ENOMEM);
    stream->time_base = encoder->time_base;
    int rc = avcodec_parameters_from_context(stream->codecpar, encoder);
    if (rc < 0) return rc;
    if ((rc = avio_open(&format->pb, path.c_str(), AVIO_FLAG_WRITE)) < 0) return rc;
    file_open = true;
    if ((rc = avformat_write_header(format, nullptr)) < 0) return rc;
    frame = av_frame_alloc();
    packet = av_packet_alloc();
    if (!frame || !packet) return AVERROR(ENOMEM);
    frame->format = encoder->pix_fmt;
    frame->width = encoder->width;
    frame->height = encoder->height;
    return av_frame_get_buffer(frame, 0);
  }

  // Sends a frame (nullptr: drain) and writes every packet the encoder has ready.
  void send(const AVFrame* f) {
    int rc = avcodec_send_frame(encoder, f);
    if (rc < 0) fail("the encoder refused a frame", rc);
    while ((rc = avcodec_receive_packet(encoder, packet)) >= 0) {
      // Every frame lasts one period; without it the MP4's last sample has no
      // duration and players (and FFmpeg's own demuxer) drop the last frame.
      if (packet->duration == 0) packet->duration = 1;
      av_packet_rescale_ts(packet, encoder->time_base, stream->time_base);
      packet->stream_index = stream->index;
      rc = av_interleaved_write_frame(format, packet);  // takes the packet's data
      if (rc < 0) fail("writing a packet failed", rc);
    }
    if (rc != AVERROR(EAGAIN) && rc != AVERROR_EOF) fail("the encoder failed", rc);
  }
};

AvEncoder::AvEncoder(std::unique_ptr<State> state) : s_(std::move(state)) {}
AvEncoder::~AvEncoder() = default;

std::unique_ptr<AvEncoder> AvEncoder::open(const std::string& path, VideoCodec codec, cv::Size size, double fps,
                                           const VideoOptions& options, std::string* why) {
  quiet_ffmpeg_logging();
  const AVCodec* av_codec = find_encoder(codec);
  if (!av_codec) {
    *why = "this FFmpeg has no such encoder";
    return nullptr;
  }
  auto s = std::make_unique<State>();
  s->path = path;
  int rc = avformat_alloc_output_context2(&s->format, nullptr, "mp4", path.c_str());
  AVDictionary* opts = nullptr;
  if (rc >= 0) rc = s->configure(av_codec, size, fps, options, &opts);
  av_dict_free(&opts);
  if (rc >= 0) rc = s->open_file();
  if (rc >= 0) {
    s->to_yuv = sws_getContext(size.width, size.height, AV_PIX_FMT_BGR24, size.width, size.height,
                               AV_PIX_FMT_YUV420P, SWS_BILINEAR, nullptr, nullptr, nullptr);
    if (!s->to_yuv) rc = AVERROR(ENOMEM);
  }
  if (rc < 0) {
    *why = av_error(rc);
    return nullptr;
  }
  return std::unique_ptr<AvEncoder>(new AvEncoder(std::move(s)));
}

void AvEncoder::write(const cv::Mat& bgr) {
  State& s = *s_;
  const int rc = av_frame_make_writable(s.frame);  // the encoder may still hold the last one
  if (rc < 0) s.fail("no frame buffer", rc);
  const std::uint8_t* const src[1] = {bgr.data};
  const int src_stride[1] = {static_cast<int>(bgr.step)};
  sws_scale(s.to_yuv, src, src_stride, 0, bgr.rows, s.frame->data, s.frame->linesize);
  s.frame->pts = s.next_pts++;
  s.send(s.frame);
}

void AvEncoder::finish() {
  State& s = *s_;
  s.send(nullptr);
  int rc = av_write_trailer(s.format);
  if (rc < 0) s.fail("writing the MP4 index failed", rc);
  s.file_open = false;
  rc = avio_closep(&s.format->pb);
  if (rc < 0) s.fail("closing the file failed", rc);
}

}  // namespace dmbd::viz::detail
