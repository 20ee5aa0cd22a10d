// PNG encoding and atomic file writes (temporary name, then rename).
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

#include "dmbd/viz/plot.hpp"

namespace dmbd::viz {

std::vector<unsigned char> encode_png(const cv::Mat& image) {
  std::vector<unsigned char> bytes;
  bool ok = false;
  try {
    ok = !image.empty() && cv::imencode(".png", image, bytes);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(
        fmt::format("viz: cannot encode a {}x{} image as PNG: {}", image.cols, image.rows, e.what()));
  }
  if (!ok) throw std::runtime_error(fmt::format("viz: cannot encode a {}x{} image as PNG", image.cols, image.rows));
  return bytes;
}

void write_file_atomic(const std::string& path, const std::vector<unsigned char>& bytes) {
  const std::string tmp = path + ".tmp";
  std::FILE* file = std::fopen(tmp.c_str(), "wb");
  if (file == nullptr)
    throw std::runtime_error(
        fmt::format("viz: cannot write '{}': cannot create '{}': {}", path, tmp, std::strerror(errno)));
  const bool written = std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
  const int write_errno = errno;
  const bool closed = std::fclose(file) == 0;
  if (!written || !closed) {
    const int err = !written ? write_errno : errno;
    std::remove(tmp.c_str());
    throw std::runtime_error(fmt::format("viz: cannot write '{}': {}", tmp, std::strerror(err)));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    std::remove(tmp.c_str());
    throw std::runtime_error(fmt::format("viz: cannot rename '{}' to '{}': {}", tmp, path, std::strerror(err)));
  }
}

void Figure::save_png(const std::string& path) const { write_file_atomic(path, encode_png(render())); }

}  // namespace dmbd::viz
