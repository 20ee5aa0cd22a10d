// PNG encoding and saving a figure (atomically, dmbd/base/file.hpp).
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

#include "dmbd/viz/plot.hpp"
#include "dmbd/base/file.hpp"

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

void Figure::save_png(const std::string& path) const { dmbd::write_file_atomic(path, encode_png(render())); }

}  // namespace dmbd::viz
