// PNG encoding of 8-bit images with libdeflate, and Figure::save_png. Written here
// rather than through cv::imencode because OpenCV's libpng + zlib path (already at
// zlib level 1) was the largest part of a run's frame stage at 1920 x 1080;
// libdeflate's level-1 compressor on the unfiltered rows is about twice as fast, for
// smaller files (docs/model.md has the figures). Other depths go through OpenCV.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <libdeflate.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "dmbd/base/file.hpp"
#include "dmbd/viz/plot.hpp"

namespace dmbd::viz {
namespace {

constexpr int kLevel = 1;  // libdeflate's fastest; level 2 costs ~10 % more time for ~5 % less size

struct CompressorDeleter {
  void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
};

// One compressor and one filtered-rows buffer per thread, kept between images (the
// frame writer's thread encodes hundreds of frames of one size).
struct Workspace {
  std::unique_ptr<libdeflate_compressor, CompressorDeleter> compressor{libdeflate_alloc_compressor(kLevel)};
  std::vector<unsigned char> rows, deflated;
};

std::vector<unsigned char> encode_with_opencv(const cv::Mat& image) {
  std::vector<unsigned char> bytes;
  bool ok = false;
  try {
    ok = cv::imencode(".png", image, bytes);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(
        fmt::format("viz: cannot encode a {}x{} image as PNG: {}", image.cols, image.rows, e.what()));
  }
  if (!ok) throw std::runtime_error(fmt::format("viz: cannot encode a {}x{} image as PNG", image.cols, image.rows));
  return bytes;
}

void put_u32(std::vector<unsigned char>& out, std::uint32_t v) {
  const unsigned char b[4] = {static_cast<unsigned char>(v >> 24), static_cast<unsigned char>(v >> 16),
                              static_cast<unsigned char>(v >> 8), static_cast<unsigned char>(v)};
  out.insert(out.end(), b, b + 4);
}

// A chunk: length, type, data, CRC-32 of type and data.
void put_chunk(std::vector<unsigned char>& out, const char* type, const unsigned char* data, std::size_t n) {
  put_u32(out, static_cast<std::uint32_t>(n));
  const std::size_t start = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data, data + n);
  put_u32(out, libdeflate_crc32(0, out.data() + start, n + 4));
}

// Row y in PNG's channel order (grey, RGB or RGBA) after its filter-type byte, 0: no
// filter. On the renderer's frames (flat shading, a repeating grid) the unfiltered rows
// hold long exact repeats: libdeflate's level 1 runs about 1.8x faster on them than on
// "Sub"-filtered rows, for the same size (docs/model.md, issue 29).
void put_row(const cv::Mat& image, int y, unsigned char* out) {
  *out++ = 0;
  const int c = image.channels();
  const cv::Mat src(1, image.cols, image.type(), const_cast<unsigned char*>(image.ptr<unsigned char>(y)));
  cv::Mat dst(1, image.cols, image.type(), out);
  if (c == 1)
    src.copyTo(dst);
  else
    cv::cvtColor(src, dst, c == 3 ? cv::COLOR_BGR2RGB : cv::COLOR_BGRA2RGBA);  // writes into dst's memory
}

void put_header(std::vector<unsigned char>& out, const cv::Mat& image) {
  static const unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  out.insert(out.end(), kSignature, kSignature + 8);
  std::vector<unsigned char> ihdr;
  put_u32(ihdr, static_cast<std::uint32_t>(image.cols));
  put_u32(ihdr, static_cast<std::uint32_t>(image.rows));
  const unsigned char colour_type = image.channels() == 1 ? 0 : image.channels() == 3 ? 2 : 6;
  const unsigned char rest[5] = {8, colour_type, 0, 0, 0};  // depth, colour, deflate, filter set 0, no interlace
  ihdr.insert(ihdr.end(), rest, rest + 5);
  put_chunk(out, "IHDR", ihdr.data(), ihdr.size());
}

}  // namespace

std::vector<unsigned char> encode_png(const cv::Mat& image) {
  if (image.empty()) throw std::runtime_error("viz: cannot encode an empty image as PNG");
  const int c = image.channels();
  if (image.depth() != CV_8U || (c != 1 && c != 3 && c != 4)) return encode_with_opencv(image);
  thread_local Workspace ws;
  if (!ws.compressor) throw std::runtime_error("viz: cannot encode PNG: libdeflate has no memory for a compressor");
  const std::size_t row_bytes = 1 + static_cast<std::size_t>(image.cols) * static_cast<std::size_t>(c);
  ws.rows.resize(row_bytes * static_cast<std::size_t>(image.rows));
  for (int y = 0; y < image.rows; ++y) put_row(image, y, ws.rows.data() + row_bytes * static_cast<std::size_t>(y));

  std::vector<unsigned char> out;
  put_header(out, image);
  std::vector<unsigned char>& idat = ws.deflated;
  idat.resize(libdeflate_zlib_compress_bound(ws.compressor.get(), ws.rows.size()));
  const std::size_t n =
      libdeflate_zlib_compress(ws.compressor.get(), ws.rows.data(), ws.rows.size(), idat.data(), idat.size());
  if (n == 0) throw std::runtime_error(fmt::format("viz: cannot encode a {}x{} image as PNG", image.cols, image.rows));
  constexpr std::size_t kMaxChunk = std::size_t{1} << 30;  // a chunk's length field holds < 2^31
  out.reserve(out.size() + n + 12 * (n / kMaxChunk + 2));
  for (std::size_t at = 0; at < n; at += kMaxChunk)
    put_chunk(out, "IDAT", idat.data() + at, std::min(kMaxChunk, n - at));
  put_chunk(out, "IEND", nullptr, 0);
  return out;
}

void Figure::save_png(const std::string& path) const { dmbd::write_file_atomic(path, encode_png(render())); }

}  // namespace dmbd::viz
